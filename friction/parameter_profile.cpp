// Friction parameters along x: sampling a profile at the nodes, per-node
// validation, and the uniform-parameter view.  See parameter_profile.hpp.
#include "friction/parameter_profile.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace slipstrip {
namespace {

std::string format_double(double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

// The per-node rules: those of validate(FrictionParameters) and the
// "physically generous" ranges of docs/config.md, with the bounds of
// friction_law.hpp that the config schema applies to a scalar value, so a
// profile cannot smuggle in a value a scalar key would refuse.
struct NodeRule {
  const char* key;
  double low;         // allowed: low < value (strict) or low <= value
  bool low_strict;
  double high;        // value <= high
  std::string allowed;
};

std::string shortest(double x) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
}

// "0 < f0 <= 10 (dimensionless)"
NodeRule coefficient_rule(const char* key, const char* symbol, bool positive,
                          std::string_view note = "(dimensionless)") {
  return {key, 0.0, positive, kMaxFrictionCoefficient,
          "0 " + std::string(positive ? "<" : "<=") + " " + symbol + " <= " +
              shortest(kMaxFrictionCoefficient) + " " + std::string(note)};
}

NodeRule slip_distance_rule() {
  return {"friction.characteristic_slip", kMinCharacteristicSlip, false, kMaxCharacteristicSlip,
          "a slip distance D between " + shortest(kMinCharacteristicSlip) + " and " +
              shortest(kMaxCharacteristicSlip) + " [m]"};
}

void check_nodes(std::span<const double> values, const NodeRule& rule, const FrictionNodeGrid& grid) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = values[i];
    const bool above = rule.low_strict ? v > rule.low : v >= rule.low;
    if (std::isfinite(v) && above && v <= rule.high) continue;
    const std::size_t ix = i % grid.nodes_x, iz = i / grid.nodes_x;
    const std::string where =
        grid.nodes_z == 1
            ? "node " + std::to_string(i) + " (x = " + format_double(static_cast<double>(i) * grid.dx) + " m)"
            : "node (ix, iz) = (" + std::to_string(ix) + ", " + std::to_string(iz) + ") (x = " +
                  format_double(static_cast<double>(ix) * grid.dx) + " m, z = " +
                  format_double(static_cast<double>(iz) * grid.dz) + " m)";
    throw std::invalid_argument(std::string(rule.key) + " at " + where + " = " + format_double(v) +
                                " is out of range: expected " + rule.allowed);
  }
}

std::vector<double> node_values(double scalar, const std::optional<ParameterProfile>& profile,
                                const FrictionNodeGrid& grid, std::string_view key) {
  if (!profile) return std::vector<double>(grid.nodes(), scalar);
  return profile->at_nodes(grid, key);
}

bool all_equal(std::span<const double> v) {
  return std::adjacent_find(v.begin(), v.end(), std::not_equal_to<>()) == v.end();
}

}  // namespace

std::string_view to_string(ParameterProfile::Kind kind) {
  switch (kind) {
    case ParameterProfile::Kind::piecewise_constant: return "piecewise_constant";
    case ParameterProfile::Kind::piecewise_linear: return "piecewise_linear";
    case ParameterProfile::Kind::node_file: return "node_file";
  }
  throw std::invalid_argument("ParameterProfile: unknown kind");
}

std::string_view to_string(ParameterProfile::Axis axis) { return axis == ParameterProfile::Axis::z ? "z" : "x"; }

double ParameterProfile::at(double position) const {
  if (kind == Kind::node_file || x.empty() || x.size() != values.size())
    throw std::logic_error("ParameterProfile::at: needs x and values of the same, non-zero length");
  // First point strictly right of `position`.
  const auto right = std::upper_bound(x.begin(), x.end(), position);
  if (right == x.begin()) return values.front();
  const auto k = static_cast<std::size_t>(right - x.begin()) - 1;  // x[k] <= position
  if (kind == Kind::piecewise_constant || k + 1 == x.size()) return values[k];
  // Linear: exact at the points (weight 0), and between two equal values the
  // value itself (no rounding), so a flat stretch stays flat bit for bit.
  if (values[k] == values[k + 1]) return values[k];
  const double weight = (position - x[k]) / (x[k + 1] - x[k]);
  return values[k] + weight * (values[k + 1] - values[k]);
}

std::vector<double> ParameterProfile::at_nodes(std::size_t nodes, double dx,
                                               std::string_view key) const {
  return at_nodes(FrictionNodeGrid{nodes, dx}, key);
}

std::vector<double> ParameterProfile::at_nodes(const FrictionNodeGrid& grid, std::string_view key) const {
  const std::size_t nodes = grid.nodes();
  if (kind == Kind::node_file) {
    if (values.size() != nodes)
      throw std::invalid_argument(
          std::string(key) + ": the file '" + path + "' has " + std::to_string(values.size()) +
          " values, expected one per node (" +
          (grid.nodes_z == 1 ? std::to_string(nodes) + " = geometry.nodes)"
                             : std::to_string(nodes) + " = geometry.nodes x geometry.nodes_z, x fastest)"));
    return values;
  }
  if (axis == Axis::z && grid.nodes_z == 1)
    throw std::invalid_argument(std::string(key) +
                                " = {...}: a profile along z (z = [...]) on a one-dimensional interface "
                                "(geometry.nodes_z = 1): expected a profile along x (x = [...]) or a number");
  // Sample the profile once per column (along x) or row (along z) and repeat it.
  std::vector<double> out(nodes);
  for (std::size_t iz = 0; iz < grid.nodes_z; ++iz) {
    const double along_z = axis == Axis::z ? at(static_cast<double>(iz) * grid.dz) : 0.0;
    for (std::size_t ix = 0; ix < grid.nodes_x; ++ix)
      out[ix + grid.nodes_x * iz] =
          axis == Axis::z ? along_z : (iz == 0 ? at(static_cast<double>(ix) * grid.dx) : out[ix]);
  }
  return out;
}

std::string FrictionProfiles::keys() const {
  std::string out;
  const auto add = [&out](const std::optional<ParameterProfile>& p, const char* key) {
    if (!p) return;
    if (!out.empty()) out += ", ";
    out += key;
  };
  add(f0, "friction.f0");
  add(a, "friction.a");
  add(b, "friction.b");
  add(characteristic_slip, "friction.characteristic_slip");
  return out;
}

FrictionNodeValues resolve_friction_nodes(const FrictionParameters& scalars,
                                          const FrictionProfiles& profiles, std::size_t nodes,
                                          double dx) {
  return resolve_friction_nodes(scalars, profiles, FrictionNodeGrid{nodes, dx});
}

FrictionNodeValues resolve_friction_nodes(const FrictionParameters& scalars,
                                          const FrictionProfiles& profiles, const FrictionNodeGrid& grid) {
  FrictionNodeValues out{node_values(scalars.f0, profiles.f0, grid, "friction.f0"),
                         node_values(scalars.a, profiles.a, grid, "friction.a"),
                         node_values(scalars.b, profiles.b, grid, "friction.b"),
                         node_values(scalars.characteristic_slip, profiles.characteristic_slip,
                                     grid, "friction.characteristic_slip")};
  check_nodes(out.f0, coefficient_rule("friction.f0", "f0", true), grid);
  check_nodes(out.a, coefficient_rule("friction.a", "a", false), grid);
  check_nodes(out.b, coefficient_rule("friction.b", "b", false), grid);
  check_nodes(out.characteristic_slip, slip_distance_rule(), grid);
  // The regularized law divides by a (exp(psi/a)).
  if (scalars.strength_law == StrengthLaw::regularized)
    check_nodes(out.a,
                coefficient_rule("friction.a", "a", true, "for friction.law = \"regularized\""), grid);
  return out;
}

FrictionParameters friction_at_node(const FrictionParameters& scalars,
                                    const FrictionNodeValues& nodes, std::size_t i) {
  FrictionParameters p = scalars;
  p.f0 = nodes.f0[i];
  p.a = nodes.a[i];
  p.b = nodes.b[i];
  p.characteristic_slip = nodes.characteristic_slip[i];
  return p;
}

FrictionParameters uniform_friction(const FrictionParameters& scalars,
                                    const FrictionProfiles& profiles, std::size_t nodes,
                                    double dx, std::string_view purpose) {
  return uniform_friction(scalars, profiles, FrictionNodeGrid{nodes, dx}, purpose);
}

FrictionParameters uniform_friction(const FrictionParameters& scalars,
                                    const FrictionProfiles& profiles, const FrictionNodeGrid& grid,
                                    std::string_view purpose) {
  if (!profiles.any()) return scalars;
  const FrictionNodeValues v = resolve_friction_nodes(scalars, profiles, grid);
  std::string varying;
  const auto check = [&varying](std::span<const double> values, const char* key) {
    if (all_equal(values)) return;
    if (!varying.empty()) varying += ", ";
    varying += key;
  };
  check(v.f0, "friction.f0");
  check(v.a, "friction.a");
  check(v.b, "friction.b");
  check(v.characteristic_slip, "friction.characteristic_slip");
  if (!varying.empty())
    throw std::invalid_argument(std::string(purpose) +
                                " needs friction parameters that are the same at every node, but " +
                                varying + (grid.nodes_z == 1 ? " vary along x" : " vary over the interface") +
                                " (a profile in [friction]); it describes homogeneous steady sliding only");
  return grid.nodes() == 0 ? scalars : friction_at_node(scalars, v, 0);
}

}  // namespace slipstrip
