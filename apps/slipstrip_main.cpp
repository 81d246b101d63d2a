// slipstrip command-line program: run, stability, events, bench (and the
// Python-backed analyze / scan, see python/slipstrip).
#include <fcntl.h>
#include <hdf5.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <cstdlib>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <map>
#include <string>
#include <vector>

#include "apps/bench.hpp"
#include "solver/checkpoint.hpp"
#include "config/config.hpp"
#include "config/config_schema.hpp"
#include "config/resource_estimate.hpp"
#include "solver/run.hpp"
#include "solver/run_output.hpp"
#include "kernels/history_convolution.hpp"
#include "stability/steady_sliding.hpp"
#include "events/catalog_io.hpp"
#include "stability/linear_stability.hpp"
#include "slipstrip/version.hpp"

namespace {

// The one piece of process-wide mutable state: a signal handler can only talk
// to the program through a volatile sig_atomic_t.  It lives in the CLI, not in
// the library, so a process embedding several simulations is unaffected.
volatile std::sig_atomic_t interrupt_signal = 0;
extern "C" void on_interrupt(int sig) { interrupt_signal = sig; }

std::string format_duration(double seconds) {
  if (!(seconds >= 0) || seconds > 1e7) return "--:--";
  const long s = static_cast<long>(seconds + 0.5);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  return buf;
}

void print_progress(const slipstrip::RunProgress& p, bool tty) {
  const double fraction = p.duration > 0 ? std::min(1.0, p.time / p.duration) : 1.0;
  const int width = 28;
  const int filled = static_cast<int>(fraction * width);
  const double eta = fraction > 0 ? p.wall_seconds * (1 - fraction) / fraction : -1;
  std::string bar(filled, '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "%s[%s] %5.1f%%  t = %.4e s  step %lld  max v = %.3e m/s  elapsed %s  ETA %s%s",
               tty ? "\r" : "", bar.c_str(), 100 * fraction, p.time, p.step, p.max_slip_rate,
               format_duration(p.wall_seconds).c_str(), format_duration(eta).c_str(), tty ? "" : "\n");
  std::fflush(stderr);
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

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string json_array(const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + json_number(v[i]);
  return s + "]";
}

// Exit code of a run stopped by a signal: the shell's 128 + signal number
// (SIGINT 130, SIGTERM 143); docs/reliability.md.
// --stop-after-steps stops the run as SIGTERM would, so it exits as SIGTERM.
int signal_exit_code() {
  const int sig = interrupt_signal;
  return sig > 0 ? 128 + sig : 128 + SIGTERM;
}

const char* signal_name(int sig) { return sig == SIGTERM ? "SIGTERM" : sig == SIGINT ? "SIGINT" : "a signal"; }

std::string errno_text(int err) { return std::strerror(err); }

// Everything about --out that can be checked before the (possibly long)
// set-up: never the config itself, never an existing file without
// --overwrite, and the directory must exist and accept a new file.  Throws
// std::invalid_argument (exit 2) naming the path and the errno text.
void check_output_path(const std::string& out_path, const std::string& config_path, bool overwrite) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path out(out_path);
  const auto status = fs::status(out, ec);
  const bool exists = fs::exists(status);
  if (exists && fs::equivalent(out, fs::path(config_path), ec))
    throw std::invalid_argument("--out '" + out_path + "' is the config file '" + config_path +
                                "': refusing to write the run over its own input (even with --overwrite)");
  if (exists && fs::is_directory(status))
    throw std::invalid_argument("--out '" + out_path + "' is a directory: expected a file name");
  if (exists && !overwrite)
    throw std::invalid_argument("--out '" + out_path +
                                "' already exists: refusing to overwrite it (give --overwrite to replace it, "
                                "or choose another --out)");
  const fs::path dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
  struct stat dir_stat {};
  if (::stat(dir.c_str(), &dir_stat) != 0)
    throw std::invalid_argument("--out '" + out_path + "': output directory '" + dir.string() +
                                "' is not usable: " + errno_text(errno));
  if (!S_ISDIR(dir_stat.st_mode))
    throw std::invalid_argument("--out '" + out_path + "': '" + dir.string() + "' is not a directory");
  // The real test of writability (permissions, read-only file system, quota):
  // open the file for writing as the run will, without truncating anything.
  const int fd = exists ? ::open(out_path.c_str(), O_WRONLY)
                        : ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0)
    throw std::invalid_argument("--out '" + out_path + "' cannot be written: " + errno_text(errno));
  ::close(fd);
  if (!exists) ::unlink(out_path.c_str());
}

// The first line where two resolved configs differ, for the message of a
// refused --resume.
std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream sa(a), sb(b);
  std::string la, lb;
  while (true) {
    const bool more_a = static_cast<bool>(std::getline(sa, la)), more_b = static_cast<bool>(std::getline(sb, lb));
    if (!more_a && !more_b) return "";
    if (!more_a) la = "(end)";
    if (!more_b) lb = "(end)";
    if (la != lb) return "'" + la + "' given, the run has '" + lb + "'";
  }
}

int report_result(const slipstrip::RunResult& result, const std::string& out_path, bool quiet, bool tty) {
  if (!quiet && tty) std::fprintf(stderr, "\n");
  std::fprintf(stderr, "%s after %lld steps (dt = %.6g s), simulated %.6g s in %.2f s wall; output %s\n",
               result.status.c_str(), result.steps, result.time_step, result.simulated_time,
               result.wall_seconds, out_path.c_str());
  if (!result.restart_point.empty())
    std::fprintf(stderr, "restart point %s: continue with `slipstrip run --resume %s`\n",
                 result.restart_point.c_str(), out_path.c_str());
  if (result.status == "completed") return 0;
  if (result.status == "interrupted") return signal_exit_code();
  return 3;  // diverged
}

// `slipstrip run --resume RUN.h5 [CONFIG [--set ...]]`: the run continues
// with the resolved config stored in RUN.h5.  A config (and --set) given as
// well is only checked, never applied: it must resolve to exactly the stored
// config, else exit 2 (so a scan or job script can pass its usual command line).
int resume_command(const std::string& run_path, const std::string& config_path,
                   const std::vector<std::string>& overrides, bool quiet, long long stop_after_steps) {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  const auto header = slipstrip::read_run_file_header(run_path);
  if (header.status == "completed") {
    std::fprintf(stderr, "%s: the run is already completed; nothing to resume\n", run_path.c_str());
    return 0;
  }
  if (!config_path.empty()) {
    const auto given = slipstrip::to_toml(slipstrip::load_config_file(config_path, overrides));
    if (given != header.config_toml)
      throw std::invalid_argument("--resume '" + run_path + "': config '" + config_path +
                                  (overrides.empty() ? "" : "' with its --set overrides") +
                                  "' differs from the run's stored config (" +
                                  first_difference(given, header.config_toml) +
                                  "); a resumed run always continues with the stored config, give "
                                  "--resume alone");
  } else if (!overrides.empty()) {
    throw std::invalid_argument("--resume '" + run_path +
                                "' with --set but no config: a resumed run continues with its stored "
                                "config and cannot change it (give the original config and --set "
                                "only to have them checked)");
  }
  const bool tty = isatty(fileno(stderr));
  slipstrip::RunHooks hooks;
  if (!quiet) hooks.progress = [tty](const slipstrip::RunProgress& p) { print_progress(p, tty); };
  hooks.progress_interval = tty ? 0.25 : 5.0;
  hooks.stop_requested = [] { return interrupt_signal != 0; };
  hooks.stop_after_steps = stop_after_steps;
  std::fprintf(stderr, "slipstrip %s (%s): resuming %s\n", slipstrip::code_version, slipstrip::git_hash,
               run_path.c_str());
  slipstrip::RunResult result;
  try {
    result = slipstrip::resume_simulation(run_path, hooks);
  } catch (const slipstrip::SetupCancelled& e) {
    std::fprintf(stderr, "interrupted by %s during the set-up (%s); %s and its restart point are unchanged\n",
                 signal_name(interrupt_signal), e.what(), run_path.c_str());
    return signal_exit_code();
  }
  std::fprintf(stderr, "resumed from step %lld\n", result.resumed_from_step);
  return report_result(result, run_path, quiet, tty);
}

int run_command(const std::string& config_path, const std::vector<std::string>& overrides,
                std::string out_path, bool quiet, bool overwrite, const slipstrip::ResourceLimits& limits,
                long long stop_after_steps) {
  // Signals first: from here on SIGINT/SIGTERM stop the run within about a
  // second, set-up included.
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  const auto config = slipstrip::load_config_file(config_path, overrides);
  if (out_path.empty()) {
    auto base = config_path.substr(config_path.find_last_of('/') + 1);
    if (auto dot = base.rfind('.'); dot != std::string::npos) base = base.substr(0, dot);
    out_path = base + ".h5";
  }
  check_output_path(out_path, config_path, overwrite);
  slipstrip::check_resources(config, limits);
  {
    // Advisory only: snapshots are compressed, so the estimate is an upper bound.
    const auto estimate = slipstrip::estimate_resources(config);
    const std::filesystem::path out(out_path);
    struct statvfs fs {};
    const std::string dir = out.has_parent_path() ? out.parent_path().string() : ".";
    if (::statvfs(dir.c_str(), &fs) == 0) {
      const double free_bytes = static_cast<double>(fs.f_bavail) * static_cast<double>(fs.f_frsize);
      if (estimate.output_bytes > free_bytes)
        std::fprintf(stderr,
                     "warning: the output may need up to %.3g GiB (uncompressed estimate) but '%s' has "
                     "%.3g GiB free; the run stops with exit code 4 if the disk fills up\n",
                     estimate.output_bytes / 1073741824.0, dir.c_str(), free_bytes / 1073741824.0);
    }
  }
  const bool tty = isatty(fileno(stderr));
  slipstrip::RunHooks hooks;
  if (!quiet) hooks.progress = [tty](const slipstrip::RunProgress& p) { print_progress(p, tty); };
  hooks.progress_interval = tty ? 0.25 : 5.0;
  hooks.stop_requested = [] { return interrupt_signal != 0; };
  hooks.stop_after_steps = stop_after_steps;
  // A new run: a restart point left by an earlier run of this name (replaced
  // with --overwrite) must not be taken for this run's.
  slipstrip::remove_checkpoint(out_path);
  std::fprintf(stderr, "slipstrip %s (%s): %s -> %s\n", slipstrip::code_version, slipstrip::git_hash,
               config_path.c_str(), out_path.c_str());
  slipstrip::RunResult result;
  try {
    result = slipstrip::run_simulation(config, out_path, hooks);
  } catch (const slipstrip::SetupCancelled& e) {
    std::fprintf(stderr, "interrupted by %s during the set-up (%s); no output written\n",
                 signal_name(interrupt_signal), e.what());
    return signal_exit_code();
  }
  return report_result(result, out_path, quiet, tty);
}

int stability_command(const std::string& config_path, const std::vector<std::string>& overrides,
                      const std::string& wavelengths_text, const std::string& height_range,
                      const std::string& out_path, bool json) {
  const auto config = slipstrip::load_config_file(config_path, overrides);
  const auto sliding = slipstrip::steady_sliding_of(config);
  std::ostringstream table, csv, js;
  if (!height_range.empty()) {
    // Hmin:Hmax:n, n evenly spaced values including both ends.
    double hmin, hmax;
    int n;
    char c1, c2;
    std::istringstream is(height_range);
    if (!(is >> hmin >> c1 >> hmax >> c2 >> n) || c1 != ':' || c2 != ':' || n < 1 || !(hmin > 0) || !(hmax >= hmin))
      throw std::invalid_argument("--height-range = '" + height_range +
                                  "' is invalid: expected Hmin:Hmax:n with 0 < Hmin <= Hmax [m] and n >= 1");
    std::vector<double> heights;
    for (int i = 0; i < n; ++i) heights.push_back(n == 1 ? hmin : hmin + (hmax - hmin) * i / (n - 1));
    const auto lc = slipstrip::critical_wavelength_vs_height(sliding, heights);
    table << "# critical wavelength Lc(H); H = inf: " ;
    auto half = sliding;
    half.strip_height = std::numeric_limits<double>::infinity();
    const auto lc_inf = slipstrip::critical_wavelength_vs_height(half, {std::numeric_limits<double>::infinity()});
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
    const auto rates = slipstrip::growth_rates(sliding, wavelengths);
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
  if (!out_path.empty()) {
    std::ofstream f(out_path);
    if (!f) throw std::runtime_error("cannot write --out " + out_path);
    f << csv.str();
    f.close();
    std::fprintf(stderr, "wrote %s\n", out_path.c_str());
    // The figure (Fig. S2 style) comes from the Python package, next to the CSV.
    std::string png = out_path;
    if (auto dot = png.rfind('.'); dot != std::string::npos && png.find('/', dot) == std::string::npos)
      png = png.substr(0, dot);
    png += ".png";
    std::string python_path = SLIPSTRIP_PYTHON_DIR;
    if (const char* existing = std::getenv("PYTHONPATH")) python_path += std::string(":") + existing;
    const std::string command = "PYTHONPATH='" + python_path + "' /usr/bin/python3 -m slipstrip plot-stability '" +
                                out_path + "' --out '" + png + "' >&2";
    if (std::system(command.c_str()) != 0)
      std::fprintf(stderr, "warning: could not plot %s (the CSV is written)\n", png.c_str());
  }
  return 0;
}

int events_command(const std::string& run_path, double alpha, const std::string& out_path,
                   const std::string& csv_path) {
  slipstrip::events::EventDetectionOptions options;
  options.alpha = alpha;
  slipstrip::events::EventCatalog catalog;
  try {
    catalog = slipstrip::events::detect_events_in_file(run_path, options);
  } catch (const std::runtime_error& e) {
    // An HDF5 read failure (truncated or damaged file) is bad input, not a bug: exit 2.
    throw std::invalid_argument("run file '" + run_path + "' cannot be read: " + e.what());
  }
  const std::string target = out_path.empty() ? run_path : out_path;
  slipstrip::events::write_event_catalog(target, catalog);
  if (!csv_path.empty()) slipstrip::events::write_event_catalog_csv(csv_path, catalog);
  std::printf("%llu nodal slips, %llu events detected, %zu kept (alpha = %g, waiting-time threshold %.4g s); catalog in %s:/events\n",
              static_cast<unsigned long long>(catalog.n_nodal_slips),
              static_cast<unsigned long long>(catalog.n_events_detected), catalog.n_events(), alpha,
              catalog.waiting_time_threshold, target.c_str());
  return 0;
}

}  // namespace

// analyze / scan / plot live in the Python package: run Debian's interpreter
// on it, with the package directory of this source tree on PYTHONPATH (an
// installed package is found anyway).
int forward_to_python(const std::string& command, const std::vector<std::string>& args) {
  std::string python_path = SLIPSTRIP_PYTHON_DIR;
  if (const char* existing = std::getenv("PYTHONPATH")) python_path += std::string(":") + existing;
  setenv("PYTHONPATH", python_path.c_str(), 1);
  if (!std::getenv("SLIPSTRIP_BIN")) {
    char self[4096];
    const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n > 0) {
      self[n] = 0;
      setenv("SLIPSTRIP_BIN", self, 1);
    }
  }
  std::vector<std::string> argv_strings = {"/usr/bin/python3", "-m", "slipstrip", command};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv_ptrs;
  for (auto& a : argv_strings) argv_ptrs.push_back(a.data());
  argv_ptrs.push_back(nullptr);
  execv(argv_ptrs[0], argv_ptrs.data());
  std::perror("slipstrip: cannot start /usr/bin/python3");
  return 1;
}

// docs/config.md's key tables are generated from the config schema
// (config/config_schema.hpp): rewrite them in place, or with --check report
// (exit 1) that the file differs from what the schema gives.
int config_docs_command(const std::string& path, bool check) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("config-docs: cannot read '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string current = text.str();
  const std::string updated = slipstrip::update_config_docs(current);
  if (check) {
    if (updated == current) return 0;
    std::istringstream want(updated), have(current);
    std::string want_line, have_line;
    int line = 1;
    while (std::getline(want, want_line) && std::getline(have, have_line) && want_line == have_line)
      ++line;
    std::fprintf(stderr,
                 "error: %s is out of date with the config schema (config/config_schema.cpp), first "
                 "at line %d: run `slipstrip config-docs %s`\n",
                 path.c_str(), line, path.c_str());
    return 1;
  }
  if (updated != current) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << updated;
    out.close();
    if (!out) throw std::runtime_error("config-docs: cannot write '" + path + "'");
  }
  return 0;
}

// The config's spelling of the history algorithms (config/simulation_config.hpp).
std::map<std::string, slipstrip::HistoryAlgorithm> history_algorithms_by_name() {
  std::map<std::string, slipstrip::HistoryAlgorithm> out;
  for (std::size_t i = 0; i < std::size(slipstrip::kHistoryAlgorithmNames); ++i)
    out.emplace(slipstrip::kHistoryAlgorithmNames[i], static_cast<slipstrip::HistoryAlgorithm>(i));
  return out;
}

int main(int argc, char** argv) {
  CLI::App app{"slipstrip: spectral boundary-integral solver for frictional sliding between two "
               "elastic strips of height H (rate-and-state friction). SI units throughout."};
  app.set_version_flag("--version", std::string(slipstrip::code_version) + " (" + slipstrip::git_hash + ")");
  app.require_subcommand(1);
  // Usage errors in one line (CLI11's default adds "Run with --help ..." on a second line).
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    std::string message = e.what();
    std::replace(message.begin(), message.end(), '\n', ' ');
    return "error: " + message + " (see --help)\n";
  });
  // CLI::PositiveNumber prints its range as 0 ... 1.8e308 in %f, 300 digits.
  const CLI::Validator finite_positive(
      [](std::string& text) -> std::string {
        try {
          std::size_t used = 0;
          const double v = std::stod(text, &used);
          if (used == text.size() && std::isfinite(v) && v > 0) return {};
        } catch (const std::exception&) {
        }
        return "expected a finite number > 0, got '" + text + "'";
      },
      "POSITIVE");

  std::string config_path, out_path, csv_path, wavelengths, height_range;
  std::vector<std::string> overrides;
  bool quiet = false, json = false, overwrite = false;
  slipstrip::ResourceLimits limits;
  double alpha = 15.0;

  auto* run = app.add_subcommand("run", "Run a simulation from a TOML config and write one HDF5 file "
                                        "(see docs/config.md and docs/output.md). Ctrl-C stops cleanly "
                                        "and leaves a restart point for --resume.");
  std::string resume_path;
  long long stop_after_steps = -1;
  run->add_option("config", config_path, "TOML config file (with --resume: optional, only checked)");
  run->add_option("--resume", resume_path,
                  "Continue the interrupted run RUN.h5 from its restart point RUN.h5.restart, appending "
                  "to RUN.h5 with the config stored in it (docs/reliability.md)");
  run->add_option("--stop-after-steps", stop_after_steps,
                  "Stop as SIGTERM does (restart point, status interrupted, exit 143) once this many "
                  "time steps from t = 0 are done (for tests of --resume)")
      ->check(finite_positive);
  run->add_option("--set", overrides, "Override a config key: section.key=value (repeatable)");
  run->add_option("--out", out_path, "Output HDF5 file (default: <config name>.h5)");
  run->add_flag("--quiet", quiet, "No progress bar");
  run->add_flag("--overwrite", overwrite, "Replace an existing --out file (never the config file itself)");
  run->add_option("--max-memory-gib", limits.max_operator_gib,
                  "Refuse runs whose estimated history-operator memory exceeds this [GiB]")
      ->capture_default_str()->check(finite_positive);
  run->add_option("--max-steps", limits.max_steps, "Refuse runs of more time steps than this")
      ->capture_default_str()->check(finite_positive);
  run->add_option("--max-output-gib", limits.max_output_gib,
                  "Refuse runs whose estimated output file exceeds this [GiB]")
      ->capture_default_str()->check(finite_positive);

  auto* stab = app.add_subcommand("stability", "Linear stability of steady sliding: growth rates vs wavelength, or Lc(H)");
  stab->add_option("config", config_path, "TOML config file (material, friction, loading, geometry.height)")->required();
  stab->add_option("--set", overrides, "Override a config key: section.key=value (repeatable)");
  stab->add_option("--wavelength", wavelengths, "Comma-separated wavelengths [m] (default: geometry.length)");
  stab->add_option("--height-range", height_range, "Hmin:Hmax:n -> Lc for n evenly spaced heights [m] (both ends included)");
  stab->add_option("--out", out_path, "Write the table as CSV");
  stab->add_flag("--json", json, "Print JSON instead of a table");

  auto* ev = app.add_subcommand("events", "Detect slip events from /slip_sampling (paper's slip-sampled procedure)");
  std::string run_path;
  ev->add_option("run", run_path, "Run file (or a file holding only /slip_sampling)")->required();
  ev->add_option("--alpha", alpha, "Waiting-time threshold factor alpha (threshold alpha*delta_th/(v0 N))");
  ev->add_option("--out", out_path, "Catalog HDF5 file (default: add /events to the run file)");
  ev->add_option("--csv", csv_path, "Also write the catalog as CSV");

  slipstrip::BenchOptions bench_options;
  auto* bench = app.add_subcommand("bench", "Time per step and memory for N = 256..16384, H/L = 0.025, 0.25 and half-space");
  bench->add_flag("--json", bench_options.json, "One JSON object per line");
  bench->add_option("--nodes", bench_options.nodes, "Node counts to time (comma-separated)")->delimiter(',');
  bench->add_option("--steps", bench_options.steps, "Time steps per measurement");
  bench->add_option("--threads", bench_options.threads, "OpenMP threads (default 1)");
  bench->add_option_function<std::vector<std::string>>(
          "--heights",
          [&](const std::vector<std::string>& values) {
            bench_options.heights.clear();
            for (const auto& v : values) {
              const double h = v == "inf" ? std::numeric_limits<double>::infinity() : std::stod(v);
              if (!(h > 0)) throw CLI::ValidationError("--heights", "each height must be > 0 or inf, got " + v);
              bench_options.heights.push_back(h);
            }
          },
          "Strip heights H [m] to time, comma-separated; inf = half-space (default 0.1,1,inf)")
      ->delimiter(',');
  bench->add_option("--history", bench_options.history,
                    "Strip history algorithm: auto, modal or block (same operator)")
      ->transform(CLI::CheckedTransformer(history_algorithms_by_name(), CLI::ignore_case));
  bench->add_option("--max-gib", bench_options.max_operator_gib,
                    "Skip cases whose estimated history-operator memory exceeds this [GiB]");

  std::string docs_path = "docs/config.md";
  bool docs_check = false;
  auto* docs = app.add_subcommand("config-docs", "Regenerate the key tables of docs/config.md from the "
                                                 "config schema (config/config_schema.cpp)");
  docs->add_option("file", docs_path, "The Markdown file holding the generated blocks")
      ->capture_default_str();
  docs->add_flag("--check", docs_check, "Change nothing; exit 1 if the file is out of date");

  for (const char* name : {"analyze", "scan", "plot", "export", "report", "transition"}) {
    auto* py = app.add_subcommand(name, std::string("Python: python3 -m slipstrip ") + name +
                                            " (see docs/analysis.md, docs/scans.md); arguments are forwarded");
    py->allow_extras();
    py->prefix_command();
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every usage error exits 2 (not CLI11's 104-114).
    return app.exit(e) == 0 ? 0 : 2;
  }
  // Our own messages name the cause; HDF5's stack dumps would bury them.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  try {
    if (*run) {
      if (!resume_path.empty()) {
        if (!out_path.empty() || overwrite)
          throw std::invalid_argument("--resume '" + resume_path +
                                      "' continues writing that file: --out and --overwrite do not apply");
        return resume_command(resume_path, config_path, overrides, quiet, stop_after_steps);
      }
      if (config_path.empty())
        throw std::invalid_argument("run: config is required (a TOML config file; or --resume RUN.h5 to continue a run; see --help)");
      return run_command(config_path, overrides, out_path, quiet, overwrite, limits, stop_after_steps);
    }
    if (*stab) return stability_command(config_path, overrides, wavelengths, height_range, out_path, json);
    if (*ev) return events_command(run_path, alpha, out_path, csv_path);
    if (*bench) return slipstrip::run_bench(bench_options);
    if (*docs) return config_docs_command(docs_path, docs_check);
    for (const char* name : {"analyze", "scan", "plot", "export", "report", "transition"})
      if (auto* py = app.get_subcommand(name); *py) return forward_to_python(name, py->remaining());
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const slipstrip::OutputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    std::fflush(stderr);
    // A file whose H5Fclose failed stays open inside HDF5, whose exit handler
    // would retry the close and crash (exit 139 on a full disk): leave
    // without running it.  Nothing of ours is buffered.
    std::fflush(stdout);
    std::_Exit(4);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
