#include "config/config.hpp"

#include "config/config_schema.hpp"
#include "config/friction_profile_toml.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <span>
#include <sstream>
#include <string_view>

namespace slipstrip {
namespace {

// ---------------------------------------------------------------------------
// The only sections and keys a config may contain are those of the schema
// (config/config_schema.cpp).  Everything else is rejected, because a silently
// ignored typo ("lenght") would run the default instead of what the user asked for.

// A config is a few kB of TOML; anything above this is not one.
constexpr std::uintmax_t kMaxConfigBytes = 1u << 20;

std::vector<std::string_view> keys_of(std::string_view section) {
  std::vector<std::string_view> names;
  for (const auto& k : config_keys())
    if (k.section == section) names.push_back(k.name);
  return names;
}

// ---------------------------------------------------------------------------
// Suggestions for misspelt names (Levenshtein distance).
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      const std::size_t substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({above + 1, row[j - 1] + 1, substitution});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// A suggestion is only useful when it is plausibly what was meant; beyond a
// third of the word the nearest name is noise, so we list the options instead.
bool close_enough(std::string_view given, std::size_t distance) {
  return distance <= std::max<std::size_t>(2, given.size() / 3);
}

std::string join(std::span<const std::string_view> names) {
  std::string out;
  for (const auto& n : names) {
    if (!out.empty()) out += ", ";
    out += n;
  }
  return out;
}

std::string section_names() {
  std::string out;
  for (const auto& s : config_sections()) {
    if (!out.empty()) out += ", ";
    out += s.name;
  }
  return out;
}

std::string unknown_section_message(std::string_view name) {
  std::string_view best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& s : config_sections()) {
    const std::size_t d = edit_distance(name, s.name);
    if (d < best_distance) best_distance = d, best = s.name;
  }
  std::string message = "unknown section '" + std::string(name) + "'";
  if (close_enough(name, best_distance))
    return message + "; did you mean '" + std::string(best) + "'?";
  return message + "; allowed sections: " + section_names();
}

std::string unknown_key_message(std::string_view section, std::string_view key) {
  const std::vector<std::string_view> keys = keys_of(section);
  std::string_view best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& k : keys) {
    const std::size_t d = edit_distance(key, k);
    if (d < best_distance) best_distance = d, best = k;
  }
  const std::string prefix = std::string(section) + ".";
  std::string message = "unknown key '" + prefix + std::string(key) + "'";
  if (close_enough(key, best_distance))
    return message + "; did you mean '" + prefix + std::string(best) + "'?";
  return message + "; allowed keys in [" + std::string(section) + "]: " + join(keys);
}

// A key written outside any section: point at the section it belongs to.
std::string top_level_key_message(std::string_view key) {
  std::string best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& k : config_keys()) {
    const std::size_t d = edit_distance(key, k.name);
    if (d < best_distance) best_distance = d, best = k.full_name();
  }
  std::string message = "unknown key '" + std::string(key) +
                        "' at top level (every key belongs to a section such as [geometry])";
  if (close_enough(key, best_distance)) return message + "; did you mean '" + best + "'?";
  return message + "; allowed sections: " + section_names();
}

// ---------------------------------------------------------------------------
// Formatting.

std::string format_number(double value) { return format_config_number(value); }
std::string quote(std::string_view text) { return quote_toml(text); }

// The value as the user wrote it, on one line (toml++ prints arrays and
// tables over several lines), for error messages.
std::string describe_unbounded(const toml::node& node) {
  if (const auto* s = node.as_string()) return quote(s->get());
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* f = node.as_floating_point()) return format_number(f->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  std::string out;
  if (const auto* a = node.as_array()) {
    out = "[";
    for (std::size_t k = 0; k < a->size() && out.size() < 200; ++k)
      out += (k ? ", " : "") + describe_unbounded(*a->get(k));
    return out + (out.size() >= 200 ? ", ...]" : "]");
  }
  if (const auto* t = node.as_table()) {
    out = "{";
    for (const auto& [key, value] : *t) {
      if (out.size() >= 200) return out + ", ...}";
      out += (out.size() > 1 ? ", " : " ") + std::string(key.str()) + " = " + describe_unbounded(value);
    }
    return out + " }";
  }
  std::ostringstream text;
  node.visit([&text](const auto& n) { text << n; });
  return text.str();
}

// ... and bounded: a value never takes over the message (io/messages.hpp).
std::string describe(const toml::node& node) { return io::one_line(describe_unbounded(node), 120); }

// "file:line: " when the node came from a file, "line N: " for text input.
std::string location(const toml::node* node) {
  if (node == nullptr) return {};
  const auto& source = node->source();
  if (source.begin.line == 0) return {};
  const std::string line = std::to_string(source.begin.line);
  // A value given with --set carries its override as its source (apply_override).
  if (source.path && source.path->rfind("override '", 0) == 0) return *source.path + ": ";
  if (source.path && !source.path->empty()) return *source.path + ":" + line + ": ";
  return "line " + line + ": ";
}

[[noreturn]] void fail(const toml::node* node, const std::string& message) {
  throw ConfigError(location(node) + message);
}

// ---------------------------------------------------------------------------
// Typed access to one section.  Every accessor names the key ("section.key")
// and the offending value in its error.
class Section {
 public:
  Section(const toml::table& root, std::string_view name) : name_(name) {
    table_ = root[name].as_table();
  }

  std::string full(std::string_view key) const { return name_ + "." + std::string(key); }
  const toml::node* node(std::string_view key) const {
    return table_ ? table_->get(key) : nullptr;
  }
  bool has(std::string_view key) const { return node(key) != nullptr; }

  [[noreturn]] void wrong_type(std::string_view key, std::string_view expected) const {
    const toml::node* n = node(key);
    fail(n, full(key) + " = " + describe(*n) + " has the wrong type: expected " +
                std::string(expected));
  }

  // Out-of-range value: "<key> = <value> is out of range: expected <allowed>".
  [[noreturn]] void out_of_range(std::string_view key, const std::string& value,
                                 std::string_view allowed) const {
    fail(node(key), full(key) + " = " + value + " is out of range: expected " +
                        std::string(allowed));
  }

  // A finite number (TOML integer or float).
  std::optional<double> number(std::string_view key) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    double value;
    if (const auto* f = n->as_floating_point()) {
      value = f->get();
    } else if (const auto* i = n->as_integer()) {
      value = static_cast<double>(i->get());
    } else {
      wrong_type(key, "a number");
    }
    if (!std::isfinite(value)) out_of_range(key, describe(*n), "a finite number");
    return value;
  }

  // A positive number or +infinity, written as the string "inf" or the TOML
  // float inf (used for lengths where infinity means "no limit").
  std::optional<double> number_or_inf(std::string_view key) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    if (const auto* s = n->as_string()) {
      if (s->get() == "inf") return std::numeric_limits<double>::infinity();
      fail(n, full(key) + " = " + describe(*n) +
                  " is not allowed: expected a number or the string \"inf\"");
    }
    double value;
    if (const auto* f = n->as_floating_point()) {
      value = f->get();
    } else if (const auto* i = n->as_integer()) {
      value = static_cast<double>(i->get());
    } else {
      wrong_type(key, "a number or the string \"inf\"");
    }
    if (std::isnan(value)) out_of_range(key, describe(*n), "a number or \"inf\"");
    return value;
  }

  std::optional<std::int64_t> integer(std::string_view key) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    if (const auto* i = n->as_integer()) return i->get();
    wrong_type(key, "an integer");
  }

  // An array of finite numbers.
  std::optional<std::vector<double>> numbers(std::string_view key) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    const auto* array = n->as_array();
    if (array == nullptr) wrong_type(key, "an array of numbers, e.g. [0.5, 1.0]");
    std::vector<double> out;
    for (const auto& element : *array) {
      double value;
      if (const auto* f = element.as_floating_point()) {
        value = f->get();
      } else if (const auto* i = element.as_integer()) {
        value = static_cast<double>(i->get());
      } else {
        wrong_type(key, "an array of numbers, e.g. [0.5, 1.0]");
      }
      if (!std::isfinite(value)) out_of_range(key, describe(*n), "an array of finite numbers");
      out.push_back(value);
    }
    return out;
  }

  // Free text (a path).
  std::optional<std::string> text(std::string_view key) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    if (const auto* t = n->as_string()) return t->get();
    wrong_type(key, "a string");
  }

  // One of a fixed list of names.
  std::optional<std::string> choice(std::string_view key,
                                    std::span<const std::string_view> allowed) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    const auto* s = n->as_string();
    if (s == nullptr) wrong_type(key, "a string, one of " + quoted_list(allowed));
    const std::string& value = s->get();
    if (std::find(allowed.begin(), allowed.end(), value) != allowed.end()) return value;
    std::string message = full(key) + " = " + quote(value) + " is not allowed: expected one of " +
                          quoted_list(allowed);
    std::string_view best;
    std::size_t best_distance = std::numeric_limits<std::size_t>::max();
    for (const auto& a : allowed) {
      const std::size_t d = edit_distance(value, a);
      if (d < best_distance) best_distance = d, best = a;
    }
    if (close_enough(value, best_distance)) message += "; did you mean " + quote(best) + "?";
    fail(n, message);
  }

  static std::string quoted_list(std::span<const std::string_view> names) {
    std::string out;
    for (const auto& n : names) {
      if (!out.empty()) out += ", ";
      out += quote(n);
    }
    return out;
  }

 private:
  std::string name_;
  const toml::table* table_ = nullptr;
};

// ---------------------------------------------------------------------------
// Structural check: unknown sections and keys, values where a section belongs,
// both keys of an alternative pair.
void check_names(const toml::table& root) {
  for (const auto& [key, node] : root) {
    const std::string_view name = key.str();
    if (find_config_section(name) == nullptr) {
      if (node.is_table()) fail(&node, unknown_section_message(name));
      fail(&node, top_level_key_message(name));
    }
    const auto* table = node.as_table();
    if (table == nullptr)
      fail(&node, "'" + std::string(name) + "' = " + describe(node) +
                      " must be a section [" + std::string(name) + "], not a value");
    for (const auto& [sub_key, sub_node] : *table)
      if (find_config_key(name, sub_key.str()) == nullptr)
        fail(&sub_node, unknown_key_message(name, sub_key.str()));
  }
  for (const auto& k : config_keys()) {
    if (k.alternative_to.empty()) continue;
    const Section s(root, k.section);
    if (s.has(k.alternative_to) && s.has(k.name))
      fail(s.node(k.name), s.full(k.alternative_to) + " = " + describe(*s.node(k.alternative_to)) +
                               " and " + s.full(k.name) + " = " + describe(*s.node(k.name)) +
                               " are alternatives: give exactly one of them");
  }
}

// ---------------------------------------------------------------------------
// Reading one key: its type, its allowed and generous ranges, its rule, then
// its member.  An absent key keeps the default of SimulationConfig.

void check_ranges(const Section& s, const ConfigKey& k, double value, const std::string& shown) {
  // +infinity is the one non-finite value a number_or_inf key accepts.
  const bool unlimited = k.type == KeyType::number_or_inf && std::isinf(value) && value > 0;
  if (!unlimited && !k.allowed.contains(value)) s.out_of_range(k.name, shown, allowed_text(k));
  // Infinity is its own allowed value (a half-space); the generous range is
  // about finite numbers.
  if (std::isfinite(value) && k.generous.bounded() && !k.generous.contains(value))
    s.out_of_range(k.name, shown, generous_text(k));
}

// A friction parameter given as a table: a profile along x, checked node by
// node by the [friction] section rule.
void read_profile(const Section& s, const ConfigKey& k, const toml::node& n, SimulationConfig& c) {
  ParameterProfile profile;
  try {
    profile = parse_parameter_profile(n, s.full(k.name));
  } catch (const std::invalid_argument& e) {
    fail(&n, e.what());
  }
  k.bind.set_profile(c, std::move(profile));
}

void read_key(const Section& s, const ConfigKey& k, SimulationConfig& c) {
  const toml::node* n = s.node(k.name);
  if (n == nullptr) return;
  switch (k.type) {
    case KeyType::friction_parameter:
      if (n->is_table()) return read_profile(s, k, *n, c);
      [[fallthrough]];
    case KeyType::number:
    case KeyType::number_or_inf: {
      const double v = *(k.type == KeyType::number_or_inf ? s.number_or_inf(k.name) : s.number(k.name));
      check_ranges(s, k, v, format_number(v));
      if (k.real_rule) k.real_rule(c, v);
      k.bind.set_real(c, v);
      return;
    }
    case KeyType::integer: {
      const std::int64_t v = *s.integer(k.name);
      check_ranges(s, k, static_cast<double>(v), std::to_string(v));
      if (k.integer_rule) k.integer_rule(c, v);
      k.bind.set_integer(c, v);
      return;
    }
    case KeyType::choice:
      k.bind.set_text(c, *s.choice(k.name, k.choices()));
      return;
    case KeyType::text:
      k.bind.set_text(c, *s.text(k.name));
      return;
    case KeyType::numbers: {
      const std::vector<double> v = *s.numbers(k.name);
      if (k.list_rule) k.list_rule(c, v);
      k.bind.set_list(c, v);
      return;
    }
  }
}

// A rule's exception as a ConfigError at the first of its keys the file gives.
template <typename Read>
void with_rule_errors(const Section& s, std::string_view key, Read read) {
  try {
    read();
  } catch (const KeyOutOfRange& e) {
    s.out_of_range(key, e.value, e.what());
  } catch (const ConfigRuleError& e) {
    for (const auto where : e.keys)
      if (s.has(where)) fail(s.node(where), e.what());
    throw ConfigError(e.what());
  }
}

std::string trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return std::string(text.substr(first, last - first + 1));
}

toml::table parse_text(const std::string& text, const std::string& source_path) {
  try {
    return toml::parse(text, source_path);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    std::string place = source_path.empty() ? std::string("line ") : source_path + ":";
    throw ConfigError(place + std::to_string(where.line) + ":" + std::to_string(where.column) +
                      ": invalid TOML: " + std::string(e.description()));
  }
}

SimulationConfig load(toml::table root, const std::vector<std::string>& overrides) {
  for (const auto& o : overrides) apply_override(root, o);
  return config_from_table(root);
}

}  // namespace

// ---------------------------------------------------------------------------

SimulationConfig config_from_table(const toml::table& root) {
  check_names(root);
  SimulationConfig c;
  // Sections in schema order (a rule reads only earlier sections); within a
  // section the primary keys first, so an alternative (dx, youngs_modulus,
  // duration_transits) is resolved with the keys it depends on already read.
  for (const auto& section : config_sections()) {
    const Section s(root, section.name);
    for (const bool alternatives : {false, true})
      for (const auto& k : config_keys())
        if (k.section == section.name && k.alternative_to.empty() != alternatives)
          with_rule_errors(s, k.name, [&] { read_key(s, k, c); });
    if (section.rule) with_rule_errors(s, {}, [&] { section.rule(c); });
  }
  return c;
}

// An override as it appears in messages: control characters (a newline would
// split the one-line message) are shown escaped.
std::string printable_override(const std::string& assignment) {
  std::string out;
  for (const unsigned char c : assignment) {
    if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else if (c == '\t') out += "\\t";
    else if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else out += static_cast<char>(c);
  }
  return out;
}

// A mirror bottom body (bottom.body absent or "mirror") must carry the top
// body's values (config_schema.cpp refuses others).  A resolved config (to_toml)
// writes them out, so an override of a top-body key is copied to the bottom
// key the table holds: the pair stays a mirror pair instead of being refused.
void carry_over_to_mirror(toml::table& root, const std::string& section_name, const std::string& key,
                          const std::string& text) {
  std::string bottom_key;
  if (section_name == "material" &&
      (key == "shear_modulus" || key == "youngs_modulus" || key == "poisson_ratio" || key == "density"))
    bottom_key = key;
  else if (section_name == "geometry" && key == "height")
    bottom_key = "height";
  if (bottom_key.empty()) return;
  const toml::table* bottom = root["bottom"].as_table();
  if (bottom == nullptr) return;
  const auto body = (*bottom)["body"].value<std::string>();
  if (body && *body != "mirror") return;
  const bool modulus = bottom_key == "shear_modulus" || bottom_key == "youngs_modulus";
  const bool present = bottom->contains(bottom_key) ||
                       (modulus && (bottom->contains("shear_modulus") || bottom->contains("youngs_modulus")));
  if (present) apply_override(root, "bottom." + bottom_key + "=" + text);
}

void apply_override(toml::table& root, const std::string& assignment) {
  const std::string shown = printable_override(assignment);
  const std::string context = "override '" + shown + "': ";
  const auto equals = assignment.find('=');
  if (equals == std::string::npos)
    throw ConfigError(context + "expected the form section.key=value");
  const std::string path = trim(std::string_view(assignment).substr(0, equals));
  const std::string text = trim(std::string_view(assignment).substr(equals + 1));
  if (printable_override(path) != path)
    throw ConfigError(context + "the key '" + printable_override(path) +
                      "' contains control characters: expected the form section.key=value");
  const auto dot = path.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == path.size() ||
      path.find('.', dot + 1) != std::string::npos)
    throw ConfigError(context + "expected the form section.key=value (got key '" + path + "')");
  const std::string section_name = path.substr(0, dot);
  const std::string key = path.substr(dot + 1);
  if (find_config_section(section_name) == nullptr)
    throw ConfigError(context + unknown_section_message(section_name));
  if (find_config_key(section_name, key) == nullptr)
    throw ConfigError(context + unknown_key_message(section_name, key));

  // The value as TOML; anything that is not a single TOML value is a string.
  toml::table parsed;
  bool as_toml = text.find_first_of("\n\r") == std::string::npos;
  if (as_toml) {
    try {
      parsed = toml::parse("value = " + text, "override '" + shown + "'");
      as_toml = parsed.size() == 1;
    } catch (const toml::parse_error&) {
      as_toml = false;
    }
  }
  if (!as_toml) {
    try {
      parsed = toml::parse("value = " + quote(text), "override '" + shown + "'");
    } catch (const toml::parse_error& e) {
      throw ConfigError(context + path + " = '" + printable_override(text) +
                        "' is not a valid value: " + std::string(e.description()));
    }
  }

  toml::node* existing = root.get(section_name);
  if (existing == nullptr) {
    root.insert(section_name, toml::table{});
    existing = root.get(section_name);
  }
  toml::table* table = existing->as_table();
  if (table == nullptr)
    throw ConfigError(context + "'" + section_name + "' is a value in the file, not a section");
  table->insert_or_assign(key, std::move(*parsed.get("value")));
  for (const auto& k : config_keys()) {
    if (k.section != section_name || k.alternative_to.empty()) continue;
    if (k.alternative_to == key) table->erase(k.name);
    if (k.name == key) table->erase(k.alternative_to);
  }
  carry_over_to_mirror(root, section_name, key, text);
}

SimulationConfig load_config_string(const std::string& toml_text,
                                    const std::vector<std::string>& overrides) {
  return load(parse_text(toml_text, ""), overrides);
}

SimulationConfig load_config_file(const std::string& path,
                                  const std::vector<std::string>& overrides) {
  // Only a regular file of sane size: a directory used to run the defaults,
  // and /dev/zero was read forever.
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec || !fs::exists(status))
    throw ConfigError("cannot open config file '" + path + "': " +
                      (ec ? ec.message() : std::string("no such file")));
  if (!fs::is_regular_file(status))
    throw ConfigError("config file '" + path + "' is not a regular file (" +
                      (fs::is_directory(status) ? std::string("a directory")
                                                : std::string("a device, FIFO or socket")) +
                      "): expected a TOML file");
  const auto size = fs::file_size(path, ec);
  if (!ec && size > kMaxConfigBytes)
    throw ConfigError("config file '" + path + "' is " + std::to_string(size) +
                      " bytes: allowed at most " + std::to_string(kMaxConfigBytes) +
                      " (1 MiB; a config is a few kB of TOML)");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw ConfigError("cannot open config file '" + path + "'");
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw ConfigError("cannot read config file '" + path + "'");
  return load(parse_text(text.str(), path), overrides);
}

std::string to_toml(const SimulationConfig& c) {
  std::ostringstream out;
  out << "# slipstrip resolved configuration: every key, SI units (docs/config.md)\n";
  for (const auto& section : config_sections()) {
    out << "\n[" << section.name << "]\n";
    for (const auto& k : config_keys()) {
      // An alternative is resolved into its partner, which is written instead.
      if (k.section != section.name || !k.alternative_to.empty()) continue;
      out << k.name << " = " << toml_value_text(k, c) << "  # ";
      if (k.type == KeyType::choice) {
        std::string names;
        for (const auto name : k.choices()) names += (names.empty() ? "" : " | ") + quote(name);
        out << names << (k.comment.empty() ? "" : " ");
      }
      out << k.comment;
      if (k.type == KeyType::friction_parameter && k.bind.get_profile(c)) {
        const ParameterProfile& profile = *k.bind.get_profile(c);
        out << (profile.kind == ParameterProfile::Kind::node_file ? " per node" : " along ")
            << (profile.kind == ParameterProfile::Kind::node_file ? "" : to_string(profile.axis));
      }
      out << "\n";
    }
  }
  return out.str();
}

}  // namespace slipstrip
