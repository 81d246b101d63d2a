#include "io/xdmf.hpp"

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string_view>

namespace slipstrip::io {

namespace {

// XML attribute and text values: the file name is the only free text.
std::string xml_escaped(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string data_item(const std::string& dimensions, const std::string& file, const std::string& dataset) {
  return "<DataItem Dimensions=\"" + dimensions +
         "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" + xml_escaped(file) + ":" +
         xml_escaped(dataset) + "</DataItem>";
}

// A 2D interface: one grid per snapshot, each with its time.
std::string xdmf_interface_2d_text(const XdmfSpaceTime& d) {
  if (d.times.size() != d.snapshot_count)
    throw std::invalid_argument("XdmfSpaceTime.times has " + std::to_string(d.times.size()) +
                                " values for " + std::to_string(d.snapshot_count) + " snapshots");
  const std::size_t nodes_x = d.node_count / d.nodes_z;
  const std::string nt = std::to_string(d.snapshot_count), nz = std::to_string(d.nodes_z),
                    nx = std::to_string(nodes_x), map_dims = "1 " + nz + " " + nx,
                    field_dims = nt + " " + nz + " " + nx;
  std::string text =
      "<?xml version=\"1.0\" ?>\n"
      "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      "<Xdmf Version=\"3.0\">\n"
      "  <Domain>\n"
      "    <Grid Name=\"interface\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t s = 0; s < d.snapshot_count; ++s) {
    char time[32];
    std::snprintf(time, sizeof time, "%.17g", d.times[s]);
    // XDMF orders dimensions slowest first: (z, x), as the datasets are stored.
    text += "      <Grid Name=\"snapshot " + std::to_string(s) + "\" GridType=\"Uniform\">\n"
            "        <Time Value=\"" + std::string(time) + "\"/>\n"
            "        <Topology TopologyType=\"2DRectMesh\" Dimensions=\"" + nz + " " + nx + "\"/>\n"
            "        <Geometry GeometryType=\"VXVY\">\n"
            "          " + data_item(nx, d.h5_file_name, "/grid/x") + "\n"
            "          " + data_item(nz, d.h5_file_name, "/grid/z") + "\n"
            "        </Geometry>\n";
    // Snapshot s of the field: start (s, 0, 0), stride 1, count (1, nz, nx)
    // of the whole dataset's dimensions.
    const std::string slab = "|" + std::to_string(s) + " 0 0:1 1 1:" + map_dims + ":" + field_dims;
    for (const std::string& field : d.fields)
      text += "        <Attribute Name=\"" + xml_escaped(field) + "\" AttributeType=\"Scalar\" Center=\"Node\">\n"
              "          " + data_item(map_dims, d.h5_file_name, d.snapshot_group + "/" + field + slab) + "\n"
              "        </Attribute>\n";
    text += "      </Grid>\n";
  }
  text +=
      "    </Grid>\n"
      "  </Domain>\n"
      "</Xdmf>\n";
  return text;
}

}  // namespace

std::string xdmf_space_time_text(const XdmfSpaceTime& d) {
  if (d.nodes_z > 1) return xdmf_interface_2d_text(d);
  const std::string nt = std::to_string(d.snapshot_count), n = std::to_string(d.node_count);
  // XDMF orders dimensions slowest first: [time, x], as the datasets are stored.
  std::string text =
      "<?xml version=\"1.0\" ?>\n"
      "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
      "<Xdmf Version=\"3.0\">\n"
      "  <Domain>\n"
      "    <Grid Name=\"interface_space_time\" GridType=\"Uniform\">\n"
      "      <!-- first axis: x [m]; second axis: time [s] (snapshot times) -->\n"
      "      <Topology TopologyType=\"2DRectMesh\" Dimensions=\"" + nt + " " + n + "\"/>\n"
      "      <Geometry GeometryType=\"VXVY\">\n"
      "        " + data_item(n, d.h5_file_name, d.x_dataset) + "\n"
      "        " + data_item(nt, d.h5_file_name, d.time_dataset) + "\n"
      "      </Geometry>\n";
  for (const std::string& field : d.fields) {
    text += "      <Attribute Name=\"" + xml_escaped(field) + "\" AttributeType=\"Scalar\" Center=\"Node\">\n"
            "        " + data_item(nt + " " + n, d.h5_file_name, d.snapshot_group + "/" + field) + "\n"
            "      </Attribute>\n";
  }
  text +=
      "    </Grid>\n"
      "  </Domain>\n"
      "</Xdmf>\n";
  return text;
}

std::string xdmf_sidecar_path(const std::string& h5_path) {
  constexpr std::string_view ext = ".h5";
  if (h5_path.size() > ext.size() && h5_path.compare(h5_path.size() - ext.size(), ext.size(), ext) == 0)
    return h5_path.substr(0, h5_path.size() - ext.size()) + ".xdmf";
  return h5_path + ".xdmf";
}

void write_xdmf_sidecar(const std::string& sidecar_path, const XdmfSpaceTime& description) {
  const std::string temporary = sidecar_path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << xdmf_space_time_text(description);
    out.flush();
    if (!out) throw std::runtime_error("XDMF sidecar '" + sidecar_path + "' cannot be written");
  }
  if (std::rename(temporary.c_str(), sidecar_path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw std::runtime_error("XDMF sidecar '" + sidecar_path + "' cannot be written (rename failed)");
  }
}

}  // namespace slipstrip::io
