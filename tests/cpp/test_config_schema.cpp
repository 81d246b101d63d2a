// The config schema (config/config_schema.hpp): the table is consistent, and
// parsing, to_toml, the TOML table for Python and the docs all follow from it.
#include <doctest/doctest.h>

#include <set>
#include <sstream>
#include <string>

#include "config_test_helpers.hpp"
#include "config/config.hpp"
#include "config/config_docs.hpp"
#include "config/config_schema.hpp"
#include "stability/linear_stability.hpp"
#include "kernels/elastic_material.hpp"
#include "kernels/passivity.hpp"

using namespace slipstrip;
using slipstrip::testing::contains;

namespace {

std::string error_text(const std::string& toml_text) {
  try {
    (void)load_config_string(toml_text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("every key is declared once, in a known section, with a complete binding") {
  std::set<std::string> seen;
  for (const auto& k : config_keys()) {
    CAPTURE(k.full_name());
    CHECK(seen.insert(k.full_name()).second);
    CHECK(find_config_section(k.section) != nullptr);
    CHECK(find_config_key(k.section, k.name) == &k);
    CHECK(!k.help.empty());
    if (!k.alternative_to.empty()) {
      // The partner is a primary key of the same section.
      const ConfigKey* partner = find_config_key(k.section, k.alternative_to);
      REQUIRE(partner != nullptr);
      CHECK(partner->alternative_to.empty());
    }
    switch (k.type) {
      case KeyType::number:
      case KeyType::number_or_inf:
        CHECK(static_cast<bool>(k.bind.set_real));
        if (k.alternative_to.empty()) CHECK(static_cast<bool>(k.bind.get_real));
        break;
      case KeyType::friction_parameter:
        CHECK((k.bind.get_real && k.bind.set_real && k.bind.get_profile && k.bind.set_profile));
        break;
      case KeyType::integer: CHECK((k.bind.get_integer && k.bind.set_integer)); break;
      case KeyType::choice:
        CHECK((k.bind.get_text && k.bind.set_text && k.choices));
        if (k.choices) CHECK(!k.choices().empty());
        break;
      case KeyType::text: CHECK((k.bind.get_text && k.bind.set_text)); break;
      case KeyType::numbers: CHECK((k.bind.get_list && k.bind.set_list)); break;
    }
  }
  for (const auto& s : config_sections()) {
    bool has_key = false;
    for (const auto& k : config_keys()) has_key = has_key || k.section == s.name;
    CHECK_MESSAGE(has_key, s.name);
  }
}

TEST_CASE("to_toml writes every primary key once, and the defaults are the struct's") {
  const SimulationConfig defaults;
  const std::string text = to_toml(defaults);
  const toml::table parsed = toml::parse(text);
  for (const auto& k : config_keys()) {
    CAPTURE(k.full_name());
    const bool written = parsed[k.section][k.name].node() != nullptr;
    CHECK(written == k.alternative_to.empty());
  }
  // An empty file resolves to the default-constructed config.
  CHECK(to_toml(load_config_string("")) == text);
  // The TOML table for Python is what a reader of to_toml gets.
  CHECK(config_to_table(defaults) == parsed);
}

TEST_CASE("config_to_table writes profiles as tables and infinity as \"inf\"") {
  const auto c = load_config_string(
      "[geometry]\nheight = \"inf\"\nnodes = 16\n[time]\nbeta = 0.3\n"
      "[friction]\na = { profile = \"piecewise_constant\", x = [0.0, 2.0], values = [0.005, 0.01] }\n");
  const toml::table t = config_to_table(c);
  CHECK(t["geometry"]["height"].value<std::string>() == "inf");
  CHECK(t["friction"]["a"]["profile"].value<std::string>() == "piecewise_constant");
  CHECK(t == toml::parse(to_toml(c)));
}

TEST_CASE("allowed texts follow from the declared ranges") {
  CHECK(allowed_text(*find_config_key("geometry", "length")) == "a length > 0 [m]");
  CHECK(allowed_text(*find_config_key("geometry", "nodes")) == "an integer between 8 and 16777216");
  CHECK(allowed_text(*find_config_key("time", "beta")) == "0 < beta <= 0.4 (dt = beta dx / c_s)");
  CHECK(allowed_text(*find_config_key("initial", "sine_amplitude")) == "-1 < sine_amplitude < 1");
  CHECK(generous_text(*find_config_key("friction", "f0")) ==
        "f0 <= 10.0 (dimensionless; the physically generous range of docs/config.md)");
  CHECK(generous_text(*find_config_key("material", "density")) ==
        "a density between 0.001 and 1e+06 [kg/m^3] (the physically generous range of docs/config.md)");
}

TEST_CASE("physical limits come from the physics: one Poisson range, passivity limits of beta") {
  // The config and linear stability refuse the same Poisson ratios.
  for (const double nu : {kMinPoissonRatio, kMaxPoissonRatio, -0.1, 0.2, 0.49}) {
    CAPTURE(nu);
    std::ostringstream text;
    text << "[material]\npoisson_ratio = " << format_config_number(nu) << "\n";
    const bool config_accepts = error_text(text.str()).empty();
    CHECK(config_accepts == poisson_ratio_allowed(nu));
    SteadySliding sliding;
    sliding.material.poisson_ratio = nu;
    bool stability_accepts = true;
    try {
      (void)characteristic_function(sliding, 1.0, {1.0, 0.0});
    } catch (const std::invalid_argument&) {
      stability_accepts = false;
    }
    CHECK(stability_accepts == poisson_ratio_allowed(nu));
  }
  // beta: the strip operator's passivity limit for this material, from kernels/passivity.
  ElasticMaterial soft;
  soft.poisson_ratio = 0.45;
  const double limit = strip_passivity_beta_limit(soft.wave_speed_ratio_squared());
  CHECK(limit < kStripBetaLimit);
  const auto with_beta = [](double beta) {
    return "[material]\npoisson_ratio = 0.45\n[time]\nbeta = " + format_config_number(beta) + "\n";
  };
  CHECK(error_text(with_beta(limit * (1 - 1e-9))).empty());
  CHECK(contains(error_text(with_beta(limit * (1 + 1e-9))), "for this material"));
  // Half-space: kernels/passivity's limit of the corrected sampled kernel.
  CHECK(error_text("[geometry]\nheight = \"inf\"\n[time]\nbeta = " +
                   format_config_number(kHalfSpaceBetaLimit) + "\n")
            .empty());
  CHECK(contains(error_text("[geometry]\nheight = \"inf\"\n[time]\nbeta = 0.36\n"),
                 "for a half-space"));
}

TEST_CASE("update_config_docs fills every block and refuses broken or missing ones") {
  std::string doc;
  for (const auto& s : config_sections())
    doc += "### [" + std::string(s.name) + "]\n<!-- generated by slipstrip config-docs: keys " +
           std::string(s.name) + " -->\nstale\n<!-- end of generated block -->\n";
  const std::string filled = update_config_docs(doc);
  CHECK(filled.find("stale") == std::string::npos);
  for (const auto& k : config_keys())
    CHECK_MESSAGE(filled.find("| `" + std::string(k.name) + "` |") != std::string::npos,
                  k.full_name());
  // Idempotent: the check of docs/config.md compares a second pass with the file.
  CHECK(update_config_docs(filled) == filled);
  // A section without its block, an unknown block, an unterminated block.
  const auto without_output = doc.substr(0, doc.find("### [output]"));
  CHECK_THROWS_WITH_AS(update_config_docs(without_output),
                       doctest::Contains("no generated key table for [output]"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(update_config_docs(doc + "<!-- generated by slipstrip config-docs: keys gemoetry -->\n"),
                       doctest::Contains("unknown generated block 'keys gemoetry'"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(update_config_docs(doc + "<!-- generated by slipstrip config-docs: ranges -->\n"),
                       doctest::Contains("has no '<!-- end of generated block -->'"),
                       std::invalid_argument);
}
