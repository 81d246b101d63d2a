#include "apps/cli.hpp"

#include <sys/statvfs.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <csignal>
#include <cstdio>

#include "config/resource_estimate.hpp"
#include "io/messages.hpp"

namespace slipstrip::cli {
namespace {

volatile std::sig_atomic_t interrupt_signal = 0;
extern "C" void on_interrupt(int sig) { interrupt_signal = sig; }

std::string format_duration(double seconds) {
  if (!(seconds >= 0) || seconds > 1e7) return "--:--";
  const long s = static_cast<long>(seconds + 0.5);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  return buf;
}

void print_progress(const RunProgress& p, bool tty) {
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

}  // namespace

const CLI::Validator& finite_positive() {
  static const CLI::Validator validator(
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
  return validator;
}

void catch_interrupts() {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
}

bool interrupted() { return interrupt_signal != 0; }

int signal_exit_code() {
  const int sig = interrupt_signal;
  return sig > 0 ? 128 + sig : 128 + SIGTERM;
}

const char* interrupt_name() {
  const int sig = interrupt_signal;
  return sig == SIGTERM ? "SIGTERM" : sig == SIGINT ? "SIGINT" : "a signal";
}

RunHooks run_hooks(bool quiet, bool tty, long long stop_after_steps) {
  RunHooks hooks;
  if (!quiet) hooks.progress = [tty](const RunProgress& p) { print_progress(p, tty); };
  hooks.progress_interval = tty ? 0.25 : 5.0;
  hooks.stop_requested = [] { return interrupted(); };
  hooks.stop_after_steps = stop_after_steps;
  hooks.warning = [](const std::string& text) { std::fprintf(stderr, "warning: %s\n", io::one_line(text).c_str()); };
  return hooks;
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

void warn_if_disk_too_small(const SimulationConfig& config, const std::string& out_path) {
  const auto estimate = estimate_resources(config);
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


}  // namespace slipstrip::cli
