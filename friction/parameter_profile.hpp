#pragma once
// Friction parameters that vary along the interface: f0, a, b and the
// characteristic slip D may each be given as a profile in x (or, on a 2D
// interface, in z) instead of one number (docs/friction.md, "Parameters along
// x"; TOML spelling in docs/config.md, "Parameters along x or z").  A profile is resolved once, at set-up, into one value per
// node; the time loop only ever sees those per-node arrays.
//
// This file knows nothing about TOML: config/friction_profile_toml.hpp turns a
// TOML value into a ParameterProfile and back.
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "friction/friction_law.hpp"

namespace slipstrip {

// The nodes a profile is sampled at: node (ix, iz) at (ix dx, iz dz), index
// ix + nodes_x iz (x fastest, as the 2D interface's fields).  nodes_z = 1 is
// the one-dimensional interface.
struct FrictionNodeGrid {
  std::size_t nodes_x = 0;
  double dx = 0.0;
  std::size_t nodes_z = 1;
  double dz = 0.0;
  std::size_t nodes() const { return nodes_x * nodes_z; }
};

// One parameter as a function of one coordinate s [m], x or (on a 2D interface) z
// (node i at x = i L / N, or at z = i W / N_z):
//   piecewise_constant : p(s) = values[k] for x[k] <= s < x[k+1]; values[0] below x[0],
//                        values.back() from x.back() on.
//   piecewise_linear   : linear between the points (x[k], values[k]); constant
//                        (the end value) outside [x.front(), x.back()].  Not
//                        wrapped periodically: give the point at s = L (W) yourself.
//   node_file          : values[i] is node i's value, read from `path` (one
//                        number per line, one line per node, x fastest on a 2D
//                        interface; docs/config.md).  x is empty, axis unused.
// x holds the points along `axis`, strictly increasing and as long as values
// (both non-empty).  A profile along z is constant along x, and vice versa.
struct ParameterProfile {
  enum class Kind { piecewise_constant, piecewise_linear, node_file };
  enum class Axis { x, z };
  Kind kind = Kind::piecewise_constant;
  std::vector<double> x;       // [m], positions along `axis`
  std::vector<double> values;  // in the parameter's unit
  std::string path;            // node_file only: absolute path of the file read
  Axis axis = Axis::x;

  double at(double position) const;  // not for node_file; position along `axis`
  // One value per node, node i at x = i * dx (a one-dimensional interface; a
  // profile along z is refused).  node_file: the values as read (throws
  // std::invalid_argument unless there are exactly `nodes` of them).
  std::vector<double> at_nodes(std::size_t nodes, double dx, std::string_view key) const;
  // One value per node of `grid` (index ix + nodes_x iz).  Throws
  // std::invalid_argument naming `key` for a profile along z on a grid with
  // nodes_z = 1 and for a node file without exactly grid.nodes() values.
  std::vector<double> at_nodes(const FrictionNodeGrid& grid, std::string_view key) const;
};

std::string_view to_string(ParameterProfile::Kind kind);
std::string_view to_string(ParameterProfile::Axis axis);  // "x", "z"

// The [friction] parameters given as profiles; an empty optional means the
// scalar in FrictionParameters applies at every node.  When a profile is set,
// the resolved config keeps NaN in the matching FrictionParameters field, so
// code that needs one value for the whole interface (linear stability, Lc)
// cannot use node 0's value by accident: it calls uniform_friction().
struct FrictionProfiles {
  std::optional<ParameterProfile> f0, a, b, characteristic_slip;

  bool any() const { return f0 || a || b || characteristic_slip; }
  // "friction.a, friction.b" for the keys given as profiles ("" if none).
  std::string keys() const;
};

// Per-node values of the four parameters (structure of arrays, N each).
struct FrictionNodeValues {
  std::vector<double> f0, a, b, characteristic_slip;
};

// Scalars where no profile is given, profiles sampled at the nodes otherwise,
// then every node checked against the rules of validate(FrictionParameters)
// and the ranges of docs/config.md.  Throws std::invalid_argument naming the
// key, the node, its position and the value, e.g.
//   friction.a at node 612 (x = 1.195 m) = -0.001 is out of range: expected a >= 0
//   friction.a at node (ix, iz) = (3, 17) (x = 0.0117 m, z = 0.066 m) = -0.001 is out of range: ...
// The first form samples x_i = i dx (a one-dimensional interface).
FrictionNodeValues resolve_friction_nodes(const FrictionParameters& scalars,
                                          const FrictionProfiles& profiles, std::size_t nodes,
                                          double dx);
FrictionNodeValues resolve_friction_nodes(const FrictionParameters& scalars,
                                          const FrictionProfiles& profiles, const FrictionNodeGrid& grid);

// Node i's parameters as one FrictionParameters (scalar routines, failures).
FrictionParameters friction_at_node(const FrictionParameters& scalars,
                                    const FrictionNodeValues& nodes, std::size_t i);

// The parameters when every node has the same ones (profiles that are
// constant count as uniform).  Throws std::invalid_argument naming `purpose`
// and the non-uniform keys otherwise.
FrictionParameters uniform_friction(const FrictionParameters& scalars,
                                    const FrictionProfiles& profiles, std::size_t nodes,
                                    double dx, std::string_view purpose);
FrictionParameters uniform_friction(const FrictionParameters& scalars,
                                    const FrictionProfiles& profiles, const FrictionNodeGrid& grid,
                                    std::string_view purpose);

}  // namespace slipstrip
