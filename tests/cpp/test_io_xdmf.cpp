// io/xdmf: the sidecar text names the run file's datasets with their current
// dimensions (slowest first, as stored), escapes the file name, and is
// replaced atomically.  The end-to-end check (a run's sidecar against its
// own HDF5 file, read back by an XML parser and by VTK when installed) is
// tests/python/test_xdmf.py.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "io/xdmf.hpp"
#include "io_test_support.hpp"

using namespace slipstrip;

namespace {

std::size_t count_of(const std::string& text, const std::string& piece) {
  std::size_t n = 0;
  for (auto at = text.find(piece); at != std::string::npos; at = text.find(piece, at + 1)) ++n;
  return n;
}

io::XdmfSpaceTime example() {
  io::XdmfSpaceTime d;
  d.h5_file_name = "run.h5";
  d.snapshot_count = 7;
  d.node_count = 64;
  d.fields = {"slip", "slip_rate"};
  return d;
}

}  // namespace

TEST_CASE("the space-time sidecar points at every field with its stored dimensions") {
  const std::string text = io::xdmf_space_time_text(example());
  CHECK(count_of(text, "<Topology TopologyType=\"2DRectMesh\" Dimensions=\"7 64\"/>") == 1);
  CHECK(count_of(text, "Dimensions=\"64\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">run.h5:/snapshots/x<") == 1);
  CHECK(count_of(text, "Dimensions=\"7\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">run.h5:/snapshots/time<") == 1);
  CHECK(count_of(text, "Dimensions=\"7 64\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">run.h5:/snapshots/slip<") == 1);
  CHECK(count_of(text, "run.h5:/snapshots/slip_rate<") == 1);
  CHECK(count_of(text, "<Attribute ") == 2);
  CHECK(count_of(text, "</Attribute>") == 2);
}

TEST_CASE("a file name with XML metacharacters is escaped") {
  auto d = example();
  d.h5_file_name = "a&b<c>\".h5";
  const std::string text = io::xdmf_space_time_text(d);
  CHECK(text.find("a&amp;b&lt;c&gt;&quot;.h5:/snapshots/slip<") != std::string::npos);
  CHECK(text.find("a&b") == std::string::npos);
}

TEST_CASE("sidecar name and atomic replacement") {
  CHECK(io::xdmf_sidecar_path("dir/run.h5") == "dir/run.xdmf");
  CHECK(io::xdmf_sidecar_path("run.hdf5") == "run.hdf5.xdmf");
  CHECK(io::xdmf_sidecar_path(".h5") == ".h5.xdmf");
  const std::string path = io_test::temp_path("xdmf_sidecar") + ".xdmf";
  auto d = example();
  io::write_xdmf_sidecar(path, d);
  d.snapshot_count = 9;
  io::write_xdmf_sidecar(path, d);
  std::ifstream in(path);
  std::stringstream read;
  read << in.rdbuf();
  CHECK(read.str() == io::xdmf_space_time_text(d));
  CHECK_FALSE(std::filesystem::exists(path + ".tmp"));
  std::filesystem::remove(path);
  CHECK_THROWS_WITH_AS(io::write_xdmf_sidecar("/no/such/dir/run.xdmf", d),
                       doctest::Contains("/no/such/dir/run.xdmf"), std::runtime_error);
}
