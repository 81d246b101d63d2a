// Event-catalog build on ~1e7 nodal slips (N = 2048, ~5000 levels).
//
// A child process generates a synthetic stick-slip history and writes it to
// an HDF5 file holding only /slip_sampling; the parent (whose peak memory is
// then the detector's alone) times detect_events_in_file on one core and
// prints the wall time and VmHWM.  A second child times the in-memory path.
//
// Usage: bench_events_catalog [target_nodal_slips=1e7] [file=/tmp/slipstrip_bench_events_<pid>.h5]
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "events/catalog_io.hpp"

using namespace slipstrip::events;

namespace {

constexpr std::size_t kNodes = 2048;

std::string vm_hwm() {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmHWM:", 0) == 0) return line.substr(6);
  return "?";
}

SlipSamplingInfo bench_info() {
  SlipSamplingInfo info;
  info.delta_th = 1e-8;
  info.L = 4.0;
  info.dx = info.L / kNodes;
  info.v0 = 2e-3;
  info.mu = 9e9;
  info.D = 5e-7;
  info.x.resize(kNodes);
  for (std::size_t i = 0; i < kNodes; ++i) info.x[i] = static_cast<double>(i) * info.dx;
  return info;
}

// Crack-like events nucleating preferentially where slip lags (best of four
// random candidates), with power-law half-widths, an elliptical slip profile,
// a rupture front and nodes slipping at 10-100 v0 from front arrival; sticking periods of order 1-10 ms between events, sprinkled with
// isolated creep NS (which the filters remove).
void generate(const std::string& path, std::uint64_t target) {
  const SlipSamplingInfo info = bench_info();
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::vector<double>> cols(kNodes);
  std::uint64_t total = 0;
  std::uint64_t n_events = 0;
  double t = 0.0;
  const double dt_front = info.dx / 3000.0;  // s per node: front at ~ the shear wave speed
  while (total < target) {
    t += 1e-3 * (1 + 9 * u(rng));
    // Creep: a few isolated NS during the sticking period.
    for (int c = 0; c < 3; ++c) {
      auto& col = cols[rng() % kNodes];
      const double tc = t - 5e-4 * u(rng);
      if (col.empty() || tc > col.back()) { col.push_back(tc); ++total; }
    }
    std::size_t centre = rng() % kNodes;
    for (int k = 0; k < 3; ++k) {
      const std::size_t cand = rng() % kNodes;
      if (cols[cand].size() < cols[centre].size()) centre = cand;
    }
    const double half = std::min<double>(kNodes / 2 - 1, 2.0 * std::pow(1 - u(rng), -1.0 / 1.2));
    const int w = static_cast<int>(half);
    const double peak_levels = std::max(2.0, 0.4 * half * (0.5 + u(rng)));
    // Slip rate 10-100 v0 inside the rupture: one level every delta_th / v.
    const double step = info.delta_th / (info.v0 * std::pow(10.0, 1.0 + u(rng)));
    double t_end = t;
    for (int d = -w; d <= w; ++d) {
      const double r = static_cast<double>(d) / (w + 1);
      const int levels = static_cast<int>(peak_levels * std::sqrt(1 - r * r) + u(rng));
      if (levels == 0) continue;
      auto& col = cols[(centre + kNodes + static_cast<std::size_t>(d + static_cast<int>(kNodes))) % kNodes];
      const double arrival = t + std::abs(d) * dt_front;
      for (int q = 0; q < levels; ++q) {
        double tq = arrival + (q + 0.5) * step;
        if (!col.empty() && tq <= col.back()) tq = col.back() + 1e-9;
        col.push_back(tq);
        t_end = std::max(t_end, tq);
      }
      total += static_cast<std::uint64_t>(levels);
    }
    t = t_end;
    ++n_events;
  }
  std::size_t n_levels = 0;
  for (const auto& c : cols) n_levels = std::max(n_levels, c.size());
  std::vector<double> m(n_levels * kNodes, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < kNodes; ++i)
    for (std::size_t j = 0; j < cols[i].size(); ++j) m[j * kNodes + i] = cols[i][j];
  cols.clear();
  cols.shrink_to_fit();
  write_slip_sampling(path, info, m, n_levels);
  std::printf("generated: %llu nodal slips, %llu synthetic ruptures, N = %zu, n_levels = %zu, simulated time %.3f s\n",
              static_cast<unsigned long long>(total), static_cast<unsigned long long>(n_events), kNodes,
              n_levels, t);
}

void print_catalog(const char* label, const EventCatalog& c, double seconds) {
  std::printf("%s: %.3f s, VmHWM %s\n", label, seconds, vm_hwm().c_str());
  std::printf("  nodal slips %llu, events detected %llu, excluded first/last %llu, below thresholds %llu, kept %zu,"
              " peak window rows %zu\n",
              static_cast<unsigned long long>(c.n_nodal_slips), static_cast<unsigned long long>(c.n_events_detected),
              static_cast<unsigned long long>(c.n_events_excluded_first_last),
              static_cast<unsigned long long>(c.n_events_below_thresholds), c.n_events(), c.peak_window_rows);
  std::fflush(stdout);
}

template <class F>
int in_child(F&& f) {
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid < 0) { std::perror("fork"); return 1; }
  if (pid == 0) {
    int rc = 0;
    try { f(); } catch (const std::exception& e) { std::fprintf(stderr, "error: %s\n", e.what()); rc = 1; }
    std::fflush(stdout);
    _exit(rc);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const auto target = static_cast<std::uint64_t>(argc > 1 ? std::atof(argv[1]) : 1e7);
  const std::string path = argc > 2 ? argv[2] : "/tmp/slipstrip_bench_events_" + std::to_string(getpid()) + ".h5";
  using clock = std::chrono::steady_clock;

  if (in_child([&] { generate(path, target); }) != 0) return 1;
  std::printf("file: %s (%.1f MB)\n", path.c_str(), std::filesystem::file_size(path) / 1e6);

  int rc = 0;
  try {
    const auto t0 = clock::now();
    const EventCatalog c = detect_events_in_file(path, {});
    const double s = std::chrono::duration<double>(clock::now() - t0).count();
    print_catalog("streaming from HDF5 (target < 30 s)", c, s);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    rc = 1;
  }

  rc |= in_child([&] {
    const Hdf5CrossingTimes src(path);
    std::vector<double> m(src.n_levels() * src.n_nodes());
    src.read_rows(0, src.n_levels(), m);
    const RowMajorCrossingTimes mem(m, src.n_levels(), src.n_nodes());
    const SlipSamplingInfo info = read_slip_sampling_info(path);
    const auto t0 = clock::now();
    const EventCatalog c = detect_events(mem, info, {});
    const double s = std::chrono::duration<double>(clock::now() - t0).count();
    print_catalog("in-memory matrix (VmHWM includes the whole matrix)", c, s);
  });
  if (argc <= 2) std::filesystem::remove(path);
  return rc;
}
