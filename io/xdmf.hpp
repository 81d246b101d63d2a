#pragma once
// XDMF sidecar of a run file: a small XML text next to RUN.h5 that tells
// ParaView and VisIt how to read the interface snapshots as one space-time
// field (x along one axis, the snapshot times along the other) without any
// conversion: the data stay in the HDF5 file and the XML only points at them.
#include <cstddef>
#include <string>
#include <vector>

namespace slipstrip::io {

struct XdmfSpaceTime {
  std::string h5_file_name;          // as seen from the sidecar's directory (the same directory)
  std::size_t snapshot_count = 0;    // rows written so far
  std::size_t node_count = 0;        // N
  std::string x_dataset = "/snapshots/x";        // [N] node positions [m]
  std::string time_dataset = "/snapshots/time";  // [snapshot_count] times [s]
  std::string snapshot_group = "/snapshots";     // fields are <group>/<name>, [snapshot_count, N]
  std::vector<std::string> fields;   // e.g. slip, slip_rate, state, shear_stress
  // > 1: a 2D interface (docs/3d.md) of nodes_z rows of node_count / nodes_z
  // nodes; fields are <group>/<name> [snapshot_count, nodes_z, nodes_x] and
  // the axes /grid/x and /grid/z.
  std::size_t nodes_z = 1;
  // A 2D interface: the snapshot_count snapshot times [s] (the values of
  // time_dataset), written into the XML, one per grid of the collection.
  std::vector<double> times;
};

// The XDMF 3 text: a 2DRectMesh whose first coordinate is x and second is time
// (ParaView shows it as an x-t image; its axes are in m and s).  A 2D
// interface (nodes_z > 1): a temporal collection of one 2DRectMesh (x, z) per
// snapshot, each with its <Time Value> (the times, to 17 digits: the double
// exactly) and fields that are hyperslabs (one snapshot) of the
// [snapshots, nodes_z, nodes_x] datasets in XDMF 3's form
// "file:/dataset|start:stride:count:dimensions", the form ParaView's XDMF 3
// reader (vtkXdmf3Reader) reads; it aborts on a <Time TimeType="List"> and
// reads no values from XDMF 2's HyperSlab DataItem.
std::string xdmf_space_time_text(const XdmfSpaceTime& description);

// "RUN.h5" -> "RUN.xdmf" (any other name gets ".xdmf" appended).
std::string xdmf_sidecar_path(const std::string& h5_path);

// Writes the sidecar atomically (a temporary file renamed over the old one), so
// a reader never sees half a file while the run rewrites it after each flush.
// Throws std::runtime_error naming the path if it cannot be written.
void write_xdmf_sidecar(const std::string& sidecar_path, const XdmfSpaceTime& description);

}  // namespace slipstrip::io
