// slipstrip stability CONFIG: growth rates of steady sliding against
// wavelength, or the critical wavelength Lc(H) over a range of heights.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "apps/cli.hpp"
#include "apps/python_launcher.hpp"
#include "config/config.hpp"
#include "io/output_paths.hpp"
#include "stability/linear_stability.hpp"
#include "stability/steady_sliding.hpp"

namespace slipstrip::cli {
namespace {

struct StabilityOptions {
  std::string config_path, out_path, wavelengths, height_range;
  std::vector<std::string> overrides;
  bool json = false, overwrite = false;
};

// The figure written next to the CSV of --out: the same name with .png.
std::string figure_path(const std::string& out_path) {
  std::string png = out_path;
  if (auto dot = png.rfind('.'); dot != std::string::npos && png.find('/', dot) == std::string::npos)
    png = png.substr(0, dot);
  return png + ".png";
}

std::vector<double> parse_list(const std::string& text, const std::string& what) {
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      values.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw std::invalid_argument(what + " = '" + text + "': '" + item + "' is not a number (expected a comma-separated list of numbers in metres)");
    }
  }
  if (values.empty()) throw std::invalid_argument(what + " is empty: expected a comma-separated list of numbers");
  return values;
}

// --height-range Hmin:Hmax:n -> n evenly spaced heights including both ends.
std::vector<double> parse_height_range(const std::string& height_range) {
  double hmin, hmax;
  int n;
  char c1, c2;
  std::istringstream is(height_range);
  if (!(is >> hmin >> c1 >> hmax >> c2 >> n) || c1 != ':' || c2 != ':' || n < 1 || !(hmin > 0) || !(hmax >= hmin))
    throw std::invalid_argument("--height-range = '" + height_range +
                                "' is invalid: expected Hmin:Hmax:n with 0 < Hmin <= Hmax [m] and n >= 1");
  std::vector<double> heights;
  for (int i = 0; i < n; ++i) heights.push_back(n == 1 ? hmin : hmin + (hmax - hmin) * i / (n - 1));
  return heights;
}

// Writes the CSV of --out and its figure (the Python package's plot-stability).
void write_table(const std::string& out_path, const std::string& csv) {
  std::ofstream file(out_path);
  if (!file) throw std::runtime_error("cannot write --out " + out_path);
  file << csv;
  file.close();
  std::fprintf(stderr, "wrote %s\n", out_path.c_str());
  // The figure (Fig. S2 style) comes from the Python package, next to the
  // CSV; its path was checked before any computing, so the plot may replace it.
  const std::string png = figure_path(out_path);
  if (run_python_module({"plot-stability", out_path, "--out", png, "--overwrite"}) != 0)
    std::fprintf(stderr, "warning: could not plot %s (the CSV is written)\n", png.c_str());
}

// Lc against the top body's height for an in-plane pair of different bodies
// (docs/bodies.md §5): the bottom body stays as configured (strip, half-space or
// rigid base), the top body's height takes each value of the range, then inf.
int pair_height_scan(const SimulationConfig& config, const StabilityOptions& o) {
  const PairSliding pair = pair_sliding_of(config);
  const auto heights = parse_height_range(o.height_range);
  const double length = config.geometry.length;
  const double shortest = 1e-3 * length, longest = 1e3 * length;
  const auto lc = pair_critical_wavelength_vs_top_height(pair, heights, shortest, longest);
  const double lc_inf =
      pair_critical_wavelength_vs_top_height(pair, {std::numeric_limits<double>::infinity()}, shortest, longest)[0];
  std::ostringstream table, csv, js;
  table << "# in-plane pair of different bodies: Lc against the top body's height (bottom body fixed); "
           "top half-space: " << lc_inf << " m\n"
        << "    H [m]          Lc [m]\n";
  csv << "height_m,critical_wavelength_m\n";
  const auto cell = [](double v) { return std::isfinite(v) ? json_number(v) : std::string("nan"); };
  for (std::size_t i = 0; i < heights.size(); ++i) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%10.5g  %14.8g\n", heights[i], lc[i]);
    table << buf;
    csv << json_number(heights[i]) << "," << cell(lc[i]) << "\n";
  }
  csv << "inf," << cell(lc_inf) << "\n";
  js << "{\"heights\": " << json_array(heights) << ", \"critical_wavelength\": " << json_array(lc)
     << ", \"critical_wavelength_half_space\": " << json_number(lc_inf) << ", \"varied\": \"top\"}";
  std::cout << (o.json ? js.str() + "\n" : table.str());
  if (!o.out_path.empty()) write_table(o.out_path, csv.str());
  return 0;
}

// An in-plane pair of different bodies (docs/bodies.md §5): the generalised
// dispersion relation of stability/interface_stability, with the normal-stress
// coupling and the memory the solver uses.  Per wavelength the fastest unstable
// root (and how many there are: the pair has no x -> -x symmetry, so waves
// travelling either way grow at different rates), and the critical wavelength.
int pair_stability(const SimulationConfig& config, const StabilityOptions& o) {
  if (!o.height_range.empty()) return pair_height_scan(config, o);
  const PairSliding pair = pair_sliding_of(config);
  const auto wavelengths =
      parse_list(o.wavelengths.empty() ? std::to_string(config.geometry.length) : o.wavelengths, "--wavelength");
  const double length = config.geometry.length;
  const double critical = pair_critical_wavelength(pair, 1e-3 * length, 1e3 * length);
  std::ostringstream table, csv, js;
  table << "# in-plane pair of different bodies: critical wavelength Lc = " << critical
        << " m (shortest unstable wavelength in [1e-3, 1e3] x geometry.length)\n"
        << "  wavelength [m]   Re Lambda [1/s]   Im Lambda [rad/s]   phase velocity [m/s]   unstable roots\n";
  csv << "wavelength_m,growth_rate_per_s,frequency_rad_per_s,phase_velocity_m_per_s,unstable_roots\n";
  std::vector<double> w, g, f, c;
  std::ostringstream roots_js;
  roots_js << "[";
  for (std::size_t i = 0; i < wavelengths.size(); ++i) {
    const double wavelength = wavelengths[i];
    const auto roots = pair_unstable_roots(pair, wavelength);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double rate = roots.empty() ? nan : roots.front().real();
    const double im = roots.empty() ? nan : roots.front().imag();
    // A root travels along x at -Im(Lambda) / k.
    const double speed = roots.empty() ? nan : -im * wavelength / (2.0 * std::numbers::pi);
    char buf[160];
    std::snprintf(buf, sizeof buf, "%16.8g %17.8g %19.8g %22.8g %16zu\n", wavelength, rate, im, speed,
                  roots.size());
    table << buf;
    // No unstable root: "nan" in the CSV (Python's float reads it), null in JSON.
    const auto cell = [](double v) { return std::isfinite(v) ? json_number(v) : std::string("nan"); };
    csv << cell(wavelength) << "," << cell(rate) << "," << cell(std::abs(im)) << "," << cell(speed) << ","
        << roots.size() << "\n";
    w.push_back(wavelength);
    g.push_back(rate);
    f.push_back(std::abs(im));
    c.push_back(speed);
    roots_js << (i ? ", " : "") << "[";
    for (std::size_t j = 0; j < roots.size(); ++j)
      roots_js << (j ? ", " : "") << "[" << json_number(roots[j].real()) << ", " << json_number(roots[j].imag()) << "]";
    roots_js << "]";
  }
  roots_js << "]";
  js << "{\"wavelengths\": " << json_array(w) << ", \"growth_rate\": " << json_array(g)
     << ", \"frequency\": " << json_array(f) << ", \"phase_velocity\": " << json_array(c)
     << ", \"unstable_roots\": " << roots_js.str() << ", \"critical_wavelength\": " << json_number(critical) << "}";
  std::cout << (o.json ? js.str() + "\n" : table.str());
  if (!o.out_path.empty()) write_table(o.out_path, csv.str());
  return 0;
}

int stability(const StabilityOptions& o) {
  const std::string &config_path = o.config_path, &height_range = o.height_range, &out_path = o.out_path;
  const std::string& wavelengths_text = o.wavelengths;
  const bool json = o.json;
  const auto config = load_config_file(config_path, o.overrides);
  if (!out_path.empty()) {
    // The output-path rule (io/output_paths.hpp), before any computing.
    const io::OutputPath outputs[] = {{"--out", out_path}, {"the figure of --out", figure_path(out_path)}};
    const std::string inputs[] = {config_path};
    io::check_output_paths(outputs, inputs, o.overwrite);
  }
  if (config.bottom.body != BodyKind::mirror && !config.material.antiplane()) return pair_stability(config, o);
  const auto sliding = steady_sliding_of(config);
  std::ostringstream table, csv, js;
  if (!height_range.empty()) {
    const std::vector<double> heights = parse_height_range(height_range);
    const auto lc = critical_wavelength_vs_height(sliding, heights);
    table << "# critical wavelength Lc(H); H = inf: " ;
    auto half = sliding;
    half.strip_height = std::numeric_limits<double>::infinity();
    const auto lc_inf = critical_wavelength_vs_height(half, {std::numeric_limits<double>::infinity()});
    table << lc_inf[0] << " m\n" << "    H [m]          Lc [m]\n";
    csv << "height_m,critical_wavelength_m\n";
    for (std::size_t i = 0; i < heights.size(); ++i) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "%10.5g  %14.8g\n", heights[i], lc[i]);
      table << buf;
      csv << json_number(heights[i]) << "," << json_number(lc[i]) << "\n";
    }
    csv << "inf," << json_number(lc_inf[0]) << "\n";
    js << "{\"heights\": " << json_array(heights) << ", \"critical_wavelength\": " << json_array(lc)
       << ", \"critical_wavelength_half_space\": " << json_number(lc_inf[0]) << "}";
  } else {
    const auto wavelengths = parse_list(wavelengths_text.empty() ? std::to_string(config.geometry.length) : wavelengths_text, "--wavelength");
    const auto rates = growth_rates(sliding, wavelengths);
    table << "  wavelength [m]   Re Lambda [1/s]   Im Lambda [rad/s]\n";
    csv << "wavelength_m,growth_rate_per_s,frequency_rad_per_s\n";
    std::vector<double> w, g, f;
    for (const auto& r : rates) {
      char buf[128];
      std::snprintf(buf, sizeof buf, "%16.8g %17.8g %19.8g\n", r.wavelength, r.growth_rate, r.frequency);
      table << buf;
      csv << json_number(r.wavelength) << "," << json_number(r.growth_rate) << "," << json_number(r.frequency) << "\n";
      w.push_back(r.wavelength);
      g.push_back(r.growth_rate);
      f.push_back(r.frequency);
    }
    js << "{\"wavelengths\": " << json_array(w) << ", \"growth_rate\": " << json_array(g)
       << ", \"frequency\": " << json_array(f) << "}";
  }
  std::cout << (json ? js.str() + "\n" : table.str());
  if (!out_path.empty()) write_table(out_path, csv.str());
  return 0;
}

}  // namespace

Command add_stability_command(CLI::App& app) {
  auto o = std::make_shared<StabilityOptions>();
  auto* stab = app.add_subcommand("stability", "Linear stability of steady sliding: growth rates vs wavelength, or Lc(H)");
  stab->add_option("config", o->config_path, "TOML config file (material, friction, loading, geometry.height)")->required();
  stab->add_option("--set", o->overrides, "Override a config key: section.key=value (repeatable)");
  stab->add_option("--wavelength", o->wavelengths, "Comma-separated wavelengths [m] (default: geometry.length)");
  stab->add_option("--height-range", o->height_range,
                   "Hmin:Hmax:n -> Lc for n evenly spaced heights [m] (both ends included): the height of both "
                   "identical strips, or for an in-plane pair of different bodies the top body's height with the "
                   "bottom body fixed (docs/bodies.md)");
  stab->add_option("--out", o->out_path, "Write the table as CSV");
  stab->add_flag("--json", o->json, "Print JSON instead of a table");
  stab->add_flag("--overwrite", o->overwrite, "Replace an existing --out file and its figure");
  return {stab, [o] { return stability(*o); }};
}

}  // namespace slipstrip::cli
