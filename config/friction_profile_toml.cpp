// TOML <-> ParameterProfile (see friction_profile_toml.hpp and docs/config.md).
#include "config/friction_profile_toml.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "io/messages.hpp"
#include "io/output_paths.hpp"

namespace slipstrip {
namespace {

// A node file holds one number per node (<= 2^24 nodes, ~25 bytes each).
constexpr std::uintmax_t kMaxNodeFileBytes = std::uintmax_t{1} << 29;

[[noreturn]] void invalid(std::string_view key, const std::string& message) {
  throw std::invalid_argument(io::one_line(std::string(key) + " = {...}: " + message));
}

std::string shortest(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".eEn") == std::string::npos) text += ".0";  // a TOML float
  return text;
}

std::vector<double> number_array(const toml::table& table, std::string_view name,
                                 std::string_view key) {
  const toml::node* node = table.get(name);
  if (node == nullptr)
    invalid(key, std::string("missing '") + std::string(name) + "' (an array of numbers)");
  const toml::array* array = node->as_array();
  if (array == nullptr || array->empty())
    invalid(key, std::string("'") + std::string(name) + "' must be a non-empty array of numbers");
  std::vector<double> out;
  out.reserve(array->size());
  for (std::size_t k = 0; k < array->size(); ++k) {
    const toml::node& item = *array->get(k);
    double value = 0.0;
    if (const auto* f = item.as_floating_point()) value = f->get();
    else if (const auto* i = item.as_integer()) value = static_cast<double>(i->get());
    else invalid(key, std::string("'") + std::string(name) + "'[" + std::to_string(k) + "] is not a number");
    if (!std::isfinite(value))
      invalid(key, std::string("'") + std::string(name) + "'[" + std::to_string(k) + "] = " + shortest(value) +
                       " is not finite");
    out.push_back(value);
  }
  return out;
}

std::string text_value(const toml::table& table, std::string_view name, std::string_view key) {
  const toml::node* node = table.get(name);
  if (node == nullptr || !node->is_string())
    invalid(key, std::string("'") + std::string(name) + "' must be a string");
  return std::string(node->as_string()->get());
}

}  // namespace

std::vector<double> read_node_file(const std::filesystem::path& path, std::string_view key) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (const std::string what = io::not_a_regular_file(path.string()); !what.empty())
    invalid(key, "node file " + io::quoted_input(path.string(), 160) + " " + what);
  if (fs::file_size(path, ec) > kMaxNodeFileBytes)
    invalid(key, "node file '" + path.string() + "' is larger than 512 MiB");
  std::ifstream file(path);
  if (!file) invalid(key, "cannot open node file '" + path.string() + "'");
  std::vector<double> values;
  std::string line;
  for (std::size_t number = 1; std::getline(file, line); ++number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto last = line.find_last_not_of(" \t\r");
    const std::string_view text(line.data() + first, last - first + 1);
    double value = 0.0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
      invalid(key, "node file " + io::quoted_input(path.string(), 160) + " line " + std::to_string(number) + ": " +
                       io::quoted_input(text, 60) + " is not one finite number");
    values.push_back(value);
  }
  if (file.bad()) invalid(key, "cannot read node file '" + path.string() + "'");
  return values;
}

ParameterProfile parse_parameter_profile(const toml::node& node, std::string_view key) {
  const toml::table* table = node.as_table();
  if (table == nullptr) invalid(key, "a profile must be a table");
  const std::string kind = text_value(*table, "profile", key);
  ParameterProfile p;
  const auto allow_only = [&](std::initializer_list<std::string_view> names) {
    for (const auto& [name, value] : *table) {
      bool known = false;
      for (auto n : names) known = known || name.str() == n;
      if (!known) {
        std::string list;
        for (auto n : names) list += (list.empty() ? "" : ", ") + std::string(n);
        invalid(key, std::string("unknown field '") + std::string(name.str()) + "' for profile = \"" + kind +
                         "\"; allowed: " + list);
      }
    }
  };
  if (kind == "piecewise_constant" || kind == "piecewise_linear") {
    allow_only({"profile", "x", "z", "values"});
    p.kind = kind == "piecewise_linear" ? ParameterProfile::Kind::piecewise_linear
                                        : ParameterProfile::Kind::piecewise_constant;
    // The points lie along x, or (a 2D interface) along z: exactly one of them.
    const bool along_x = table->contains("x"), along_z = table->contains("z");
    if (along_x && along_z)
      invalid(key, "both 'x' and 'z' given: expected one of them (a profile varies along x or along z; "
                   "different parameters may use different axes)");
    if (!along_x && !along_z)
      invalid(key, "missing 'x' (or 'z' on a 2D interface): the points, an array of numbers [m]");
    p.axis = along_z ? ParameterProfile::Axis::z : ParameterProfile::Axis::x;
    const std::string axis(to_string(p.axis));
    p.x = number_array(*table, axis, key);
    p.values = number_array(*table, "values", key);
    if (p.x.size() != p.values.size())
      invalid(key, "'" + axis + "' has " + std::to_string(p.x.size()) + " points but 'values' has " +
                       std::to_string(p.values.size()) + ": expected the same number");
    for (std::size_t k = 1; k < p.x.size(); ++k)
      if (!(p.x[k] > p.x[k - 1]))
        invalid(key, "'" + axis + "' must be strictly increasing, but " + axis + "[" + std::to_string(k) +
                         "] = " + shortest(p.x[k]) + " <= " + axis + "[" + std::to_string(k - 1) + "] = " +
                         shortest(p.x[k - 1]));
    return p;
  }
  if (kind == "node_file") {
    allow_only({"profile", "path"});
    namespace fs = std::filesystem;
    fs::path path = text_value(*table, "path", key);
    if (path.empty()) invalid(key, "'path' is empty");
    if (path.is_relative()) {
      const auto& source = node.source().path;
      // A relative path in a file is relative to that file; an override
      // ("override '...'") or TOML text has no file: the working directory.
      if (source && !source->empty() && source->rfind("override '", 0) != 0)
        path = fs::path(*source).parent_path() / path;
      path = fs::absolute(path);
    }
    p.kind = ParameterProfile::Kind::node_file;
    p.path = path.lexically_normal().string();
    p.values = read_node_file(p.path, key);
    if (p.values.empty()) invalid(key, "node file '" + p.path + "' holds no values");
    return p;
  }
  invalid(key, "profile = \"" + kind +
                   "\" is not allowed: expected \"piecewise_constant\", \"piecewise_linear\" or "
                   "\"node_file\"");
}

std::string parameter_profile_toml(const ParameterProfile& p) {
  std::ostringstream out;
  out << "{ profile = \"" << to_string(p.kind) << "\"";
  if (p.kind == ParameterProfile::Kind::node_file) {
    // The path as a TOML literal string would break on a quote; a basic
    // string needs only \ and " escaped.
    std::string escaped;
    for (char c : p.path) escaped += (c == '\\' || c == '"') ? std::string("\\") + c : std::string(1, c);
    out << ", path = \"" << escaped << "\" }";
    return out.str();
  }
  const auto array = [&out](const std::vector<double>& v) {
    out << "[";
    for (std::size_t k = 0; k < v.size(); ++k) out << (k ? ", " : "") << shortest(v[k]);
    out << "]";
  };
  out << ", " << to_string(p.axis) << " = ";
  array(p.x);
  out << ", values = ";
  array(p.values);
  out << " }";
  return out.str();
}

}  // namespace slipstrip
