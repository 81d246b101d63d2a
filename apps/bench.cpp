#include "apps/bench.hpp"

#include <omp.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

#include "config/resource_estimate.hpp"
#include "solver/simulation.hpp"
#include "solver/simulation_3d.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/half_space_history.hpp"
#include "kernels/inplane_pair_history.hpp"
#include "kernels/two_body_history.hpp"
#include "kernels/elastic_material.hpp"
#include "friction/batch_solve.hpp"
#include "friction/friction_law.hpp"
#include "kernels/fft.hpp"
#include "simd/instruction_set.hpp"

namespace slipstrip {
namespace {

// CPU time of the whole process [s].  On a machine shared with other jobs the
// wall clock also counts the time spent waiting for a core; with one thread
// the CPU time per step does not (it still feels shared caches).
double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double peak_rss_mib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return std::numeric_limits<double>::quiet_NaN();
}

struct BenchCase {
  int nodes;
  double height;  // inf = half-space
  PlaneCondition plane = PlaneCondition::strain;
  // A pair of different bodies (in-plane: per-body 2x2 operators; antiplane:
  // one combined scalar operator of the two strips, history "pair_combined_*",
  // or of the two half-spaces, "pair_half_space_combined"; one per body,
  // TwoBodyHistory, with time.antiplane_pair = "bodies"): the bottom body has the
  // same height and wave speeds, twice mu and rho (twice the impedances).  A
  // pair of half-spaces (height = inf) with equal wave speeds and different
  // densities has a Stoneley wave, which the combined operator does not carry
  // (docs/inplane_bodies.md §7): there the bottom body has four times mu and
  // the same rho (twice the impedances again, twice the wave speeds), in-plane
  // and antiplane alike (the antiplane row is of the same two bodies; its
  // combined operator, time.antiplane_pair, has two branch cuts there).
  bool dissimilar = false;
};

struct BenchResult {
  double us_per_step = std::numeric_limits<double>::quiet_NaN();
  double floor_us_per_step = std::numeric_limits<double>::quiet_NaN();
  double cpu_us_per_step = std::numeric_limits<double>::quiet_NaN();
  double floor_cpu_us_per_step = std::numeric_limits<double>::quiet_NaN();
};

// The configuration a case runs (its estimate guards the memory, bench_case runs it).
SimulationConfig bench_config(const BenchCase& c, const BenchOptions& options) {
  SimulationConfig config;
  config.geometry = {4.0, c.height, c.nodes};
  config.material.plane = c.plane;
  config.time.beta = 0.25;
  config.time.history = options.history;
  config.initial.noise_amplitude = 1e-3;
  config.time.half_space_pair = options.half_space_pair;
  config.time.antiplane_pair = options.antiplane_pair;
  if (c.dissimilar) {
    const bool half_spaces = std::isinf(c.height);
    config.bottom.body = BodyKind::elastic;
    config.bottom.shear_modulus = (half_spaces ? 4.0 : 2.0) * config.material.shear_modulus;
    config.bottom.poisson_ratio = config.material.poisson_ratio;
    config.bottom.density = (half_spaces ? 1.0 : 2.0) * config.material.density;
    config.bottom.height = c.height;
  }
  // A typical statistics run (100 L/c_s), in case an operator is sized by the
  // run's horizon; the timed steps are far fewer.
  config.time.duration = 100.0 * config.geometry.length / config.material.shear_wave_speed();
  return config;
}

BenchResult bench_case(const BenchCase& c, const BenchOptions& options) {
  using clock = std::chrono::steady_clock;
  const SimulationConfig config = bench_config(c, options);
  const double dt = strip_time_step(config.material, c.height, config.geometry.length / c.nodes,
                                    config.time.beta);
  const auto t_setup = clock::now();
  Simulation sim(config);  // includes the kernel precompute (closed-form modes)
  const double setup_ms = std::chrono::duration<double, std::milli>(clock::now() - t_setup).count();
  for (int i = 0; i < 10; ++i) sim.step();
  // The block operator does its far-field work once per block of B steps and
  // its level convolutions on a pattern that repeats every B steps, and the
  // half-space advances its slow exponentials once per block: time a whole
  // number of blocks so the average is the true one.
  int steps = options.steps;
  int block_steps = 1;
  if (const auto* block = dynamic_cast<const BlockStripHistory*>(&sim.history_operator()))
    block_steps = block->block();
  if (const auto* half_space = dynamic_cast<const HalfSpaceHistory*>(&sim.history_operator()))
    block_steps = half_space->period();
  if (const auto* pair = dynamic_cast<const InplanePairHistory*>(&sim.history_operator()))
    block_steps = pair->period();
  if (const auto* bodies = dynamic_cast<const TwoBodyHistory*>(&sim.history_operator()))
    block_steps = bodies->period();
  steps = ((std::max(steps, block_steps) + block_steps - 1) / block_steps) * block_steps;
  const auto t0 = clock::now();
  const double cpu0 = process_cpu_seconds();
  for (int i = 0; i < steps; ++i) sim.step();
  const double cpu_us_per_step = 1e6 * (process_cpu_seconds() - cpu0) / steps;
  const double us_per_step =
      std::chrono::duration<double, std::micro>(clock::now() - t0).count() / steps;

  // Floor: the work every spectral BIM step must do whatever its kernels --
  // one forward and one inverse FFT and the local interface solve (predictor
  // + corrector, two state updates) at every node -- timed in this binary,
  // through the same batch routine (and OpenMP loop) as Simulation::step.
  RealFft fft(c.nodes);
  std::vector<double> v(sim.slip_rate().begin(), sim.slip_rate().end()), phi(sim.state().begin(), sim.state().end());
  std::vector<double> v_new(c.nodes), phi_new(c.nodes), tau_history(c.nodes);
  std::vector<double> field(c.nodes);
  std::vector<std::complex<double>> spectrum(c.nodes / 2 + 1);
  const LocalSolveParameters params{config.friction, config.loading.normal_stress, sim.radiation_damping()};
  const double eta = params.eta;
  const double load = sim.reference_shear_stress() + eta * config.loading.driving_velocity;
  const auto t1 = clock::now();
  const double cpu1 = process_cpu_seconds();
  for (int s = 0; s < options.steps; ++s) {
    fft.forward(v, spectrum);
    fft.inverse(spectrum, field);
    for (int i = 0; i < c.nodes; ++i) tau_history[i] = load + 1e-9 * field[i];
    predictor_corrector_parallel(params, dt, tau_history, v, phi, v_new, phi_new);
    v.swap(v_new);
    phi.swap(phi_new);
  }
  const double floor_cpu_us = 1e6 * (process_cpu_seconds() - cpu1) / options.steps;
  const double floor_us =
      std::chrono::duration<double, std::micro>(clock::now() - t1).count() / options.steps;
  const double rss = peak_rss_mib();
  const auto stats = sim.history_operator().stats();
  const std::string height = std::isinf(c.height) ? "null" : std::to_string(c.height);
  const auto* pair = dynamic_cast<const InplanePairHistory*>(&sim.history_operator());
  const auto* bodies = dynamic_cast<const TwoBodyHistory*>(&sim.history_operator());
  const char* algorithm = pair ? (pair->combined()                  ? "pair_half_space_combined"
                                  : std::isinf(c.height)             ? "pair_half_space"
                                  : pair->period() > 1               ? "pair_block"
                                                                     : "pair_modal")
                          : bodies ? (std::isinf(c.height) ? "pair_half_space" : bodies->period() > 1 ? "pair_block" : "pair_modal")
                          // An antiplane pair of different half-spaces as one operator (time.antiplane_pair).
                          : c.dissimilar && dynamic_cast<const HalfSpaceHistory*>(&sim.history_operator())
                              ? "pair_half_space_combined"
                          : dynamic_cast<const BlockStripHistory*>(&sim.history_operator())
                              ? (c.dissimilar ? "pair_combined_block" : "block")
                              : (std::isinf(c.height) ? "half_space" : c.dissimilar ? "pair_combined_modal" : "modal");
  const std::string plane = std::string(kPlaneConditionNames[static_cast<std::size_t>(c.plane)]) + (c.dissimilar ? "-2b" : "");
  if (options.json) {
    std::printf(
        "{\"N\": %d, \"height\": %s, \"length\": 4.0, \"plane\": \"%s\", \"us_per_step\": %.3f, "
        "\"floor_us_per_step\": %.3f, "
        "\"ratio_to_floor\": %.3f, \"rss_mib\": %.2f, \"oscillators\": %zu, \"operator_mib\": %.2f, "
        "\"dt\": %.6g, \"threads\": %d, \"steps\": %d, \"setup_ms\": %.2f, \"history\": \"%s\", "
        "\"cpu_us_per_step\": %.3f, \"floor_cpu_us_per_step\": %.3f, \"cpu_ratio_to_floor\": %.3f, "
        "\"simd\": \"%s\"}\n",
        c.nodes, height.c_str(), plane.c_str(), us_per_step, floor_us, us_per_step / floor_us, rss, stats.oscillators,
        stats.memory_bytes / 1048576.0, dt, options.threads, steps, setup_ms, algorithm, cpu_us_per_step,
        floor_cpu_us, cpu_us_per_step / floor_cpu_us, std::string(simd::to_string(simd::instruction_set())).c_str());
  } else {
    std::printf("%6d  %-8s  %-9s  %12.1f  %12.1f  %8.2f  %9.1f  %12zu  %10.1f  %s\n", c.nodes,
                std::isinf(c.height) ? "inf" : std::to_string(c.height).substr(0, 5).c_str(), plane.c_str(), us_per_step,
                floor_us, us_per_step / floor_us, rss, stats.oscillators, setup_ms, algorithm);
  }
  std::fflush(stdout);
  return {us_per_step, floor_us, cpu_us_per_step, floor_cpu_us};
}

// Runs one case in a forked child (so its peak resident memory is its own) and
// waits for it; false if the fork failed.  A failing case reports on stderr.
template <class Case>
bool in_child(const BenchOptions& options, const std::string& label, Case&& run_case) {
  const pid_t pid = fork();
  if (pid < 0) return false;
  if (pid == 0) {
    omp_set_num_threads(options.threads);
    try {
      run_case();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench %s failed: %s\n", label.c_str(), e.what());
      _exit(1);
    }
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return true;
}

// A 2D interface of c.nodes x nodes_z nodes: Simulation3d's step against its
// floor, timed in this binary through the same FFT class and batch routine.
void bench_case_3d(const BenchCase& c, const BenchOptions& options) {
  using clock = std::chrono::steady_clock;
  SimulationConfig config;
  config.geometry.length = 4.0;
  config.geometry.height = c.height;
  config.geometry.nodes = c.nodes;
  config.geometry.nodes_z = options.nodes_z;
  config.geometry.width = 4.0 * options.nodes_z / c.nodes;
  // Half-spaces: below the 2D-interface limit 0.35/sqrt(2) = 0.247 (docs/3d.md).
  config.time.beta = std::isinf(c.height) ? 0.24 : 0.25;
  config.time.history = options.history;
  config.initial.noise_amplitude = 1e-3;
  const auto t_setup = clock::now();
  Simulation3d sim(config);
  const double setup_ms = std::chrono::duration<double, std::milli>(clock::now() - t_setup).count();
  for (int i = 0; i < 10; ++i) sim.step();
  // Whole blocks of the block operators and of the half-space's slow
  // exponentials (their work repeats every block; as the 1D rows).
  const auto& history = sim.history_operator();
  int block_steps = 1;
  for (const HistoryOperator* op : {&history.inplane(), &history.antiplane()}) {
    if (const auto* block = dynamic_cast<const BlockStripHistory*>(op)) block_steps = std::max(block_steps, block->block());
    if (const auto* half_space = dynamic_cast<const HalfSpaceHistory*>(op))
      block_steps = std::max(block_steps, half_space->period());
  }
  const int steps = ((std::max(options.steps, block_steps) + block_steps - 1) / block_steps) * block_steps;
  const auto t0 = clock::now();
  const double cpu0 = process_cpu_seconds();
  for (int i = 0; i < steps; ++i) sim.step();
  const double cpu_us_per_step = 1e6 * (process_cpu_seconds() - cpu0) / steps;
  const double us_per_step = std::chrono::duration<double, std::micro>(clock::now() - t0).count() / steps;

  const std::size_t n = sim.nodes();
  RealFft2d fft(c.nodes, options.nodes_z);
  std::vector<double> vx(sim.slip_rate_x().begin(), sim.slip_rate_x().end());
  std::vector<double> vz(sim.slip_rate_z().begin(), sim.slip_rate_z().end());
  std::vector<double> phi(sim.state().begin(), sim.state().end()), speed(n), speed_new(n), phi_new(n);
  std::vector<double> hx(n), hz(n), load(n);
  std::vector<std::complex<double>> spectrum_x(fft.modes()), spectrum_z(fft.modes());
  for (std::size_t i = 0; i < n; ++i) speed[i] = std::hypot(vx[i], vz[i]);
  const LocalSolveParameters params{config.friction, config.loading.normal_stress, sim.radiation_damping()};
  // The bench's friction is uniform: every node has the same tau_0.
  const double drive = sim.reference_shear_stress().front() + params.eta * config.loading.driving_velocity;
  const double dt = sim.time_step();
  const auto t1 = clock::now();
  const double cpu1 = process_cpu_seconds();
  for (int s = 0; s < options.steps; ++s) {
    fft.forward_pair(vx, spectrum_x, vz, spectrum_z);
    fft.inverse_pair(spectrum_x, hx, spectrum_z, hz);
    for (std::size_t i = 0; i < n; ++i) {
      const double lx = drive - 1e-9 * hx[i], lz = -1e-9 * hz[i];
      load[i] = std::sqrt(lx * lx + lz * lz);
    }
    predictor_corrector_parallel(params, dt, load, speed, phi, speed_new, phi_new);
    for (std::size_t i = 0; i < n; ++i) {
      vx[i] = speed_new[i] * (drive - 1e-9 * hx[i]) / load[i];
      vz[i] = speed_new[i] * (-1e-9 * hz[i]) / load[i];
    }
    speed.swap(speed_new);
    phi.swap(phi_new);
  }
  const double floor_cpu_us = 1e6 * (process_cpu_seconds() - cpu1) / options.steps;
  const double floor_us = std::chrono::duration<double, std::micro>(clock::now() - t1).count() / options.steps;
  // The history operator alone (the part the floor does not have), fed the
  // spectra of the last fields, over the same whole blocks as the step.
  fft.forward(sim.slip_rate_x(), spectrum_x);
  fft.forward(sim.slip_rate_z(), spectrum_z);
  const auto t2 = clock::now();
  const double cpu2 = process_cpu_seconds();
  for (int s = 0; s < steps; ++s) sim.history_operator_for_timing().push(spectrum_x, spectrum_z);
  const double operator_cpu_us = 1e6 * (process_cpu_seconds() - cpu2) / steps;
  const double operator_us = std::chrono::duration<double, std::micro>(clock::now() - t2).count() / steps;
  const double rss = peak_rss_mib();
  const auto stats = history.stats();
  auto name = [](const HistoryOperator& op) {
    return dynamic_cast<const BlockStripHistory*>(&op) ? "block"
           : dynamic_cast<const HalfSpaceHistory*>(&op) ? "half_space"
                                                         : "modal";
  };
  const std::string algorithm = std::string(name(history.inplane())) + "/" + name(history.antiplane());
  const double bytes_per_node = static_cast<double>(stats.memory_bytes) / static_cast<double>(n);
  if (options.json) {
    std::printf(
        "{\"N\": %d, \"nodes_z\": %d, \"height\": %s, \"length\": 4.0, \"us_per_step\": %.3f, "
        "\"floor_us_per_step\": %.3f, \"ratio_to_floor\": %.3f, \"cpu_us_per_step\": %.3f, "
        "\"floor_cpu_us_per_step\": %.3f, \"cpu_ratio_to_floor\": %.3f, \"operator_us_per_step\": %.3f, "
        "\"operator_cpu_us_per_step\": %.3f, \"rss_mib\": %.2f, \"oscillators\": %zu, "
        "\"operator_mib\": %.2f, \"operator_bytes_per_node\": %.1f, \"dt\": %.6g, \"threads\": %d, "
        "\"steps\": %d, \"setup_ms\": %.2f, \"history\": \"%s\"}\n",
        c.nodes, options.nodes_z, std::isinf(c.height) ? "null" : std::to_string(c.height).c_str(), us_per_step,
        floor_us, us_per_step / floor_us, cpu_us_per_step, floor_cpu_us, cpu_us_per_step / floor_cpu_us,
        operator_us, operator_cpu_us, rss, stats.oscillators, stats.memory_bytes / 1048576.0, bytes_per_node, dt,
        options.threads, steps, setup_ms, algorithm.c_str());
  } else {
    std::printf("%6d x %-5d  %-8s  %12.1f  %12.1f  %6.2f  %12.1f  %6.2f  %12.1f  %9.1f  %12zu  %8.0f  %10.1f  %s\n",
                c.nodes, options.nodes_z,
                std::isinf(c.height) ? "inf" : std::to_string(c.height).substr(0, 5).c_str(), us_per_step,
                floor_us, us_per_step / floor_us, cpu_us_per_step, cpu_us_per_step / floor_cpu_us, operator_us,
                rss, stats.oscillators, bytes_per_node, setup_ms, algorithm.c_str());
  }
  std::fflush(stdout);
}

}  // namespace

int run_bench(const BenchOptions& options) {
  if (options.nodes_z > 1) {
    if (!options.json)
      std::printf("# 2D interface: L_x = 4 m, dz = dx, beta = 0.25 (half-space 0.24), Table S1 friction, %d thread(s), %d steps\n"
                  "# (cpu: process CPU time per step and its ratio to the floor's; operator: the history operator's push alone;\n"
                  "#  B/node: the history operators' memory per interface node; history: in-plane/antiplane algorithm)\n"
                  "#      N x N_z  H [m]     us/step     floor us/step  ratio  cpu us/step  ratio   operator us  RSS [MiB]  oscillators  B/node  setup [ms]  history\n",
                  options.threads, options.steps);
    std::fflush(stdout);  // before the forks, or each child prints it again
    for (int n : options.nodes)
      for (double height : options.heights) {
        SimulationConfig config;
        config.geometry.length = 4.0;
        config.geometry.height = height;
        config.geometry.nodes = n;
        config.geometry.nodes_z = options.nodes_z;
        config.geometry.width = 4.0 * options.nodes_z / n;
        config.time.beta = std::isinf(height) ? 0.24 : 0.25;  // as bench_case_3d
        config.time.history = options.history;
        const double gib = estimate_resources(config).operator_bytes / (1024.0 * 1024.0 * 1024.0);
        if (gib > options.max_operator_gib) {
          std::printf(options.json ? "{\"N\": %d, \"nodes_z\": %d, \"height\": %g, \"skipped\": \"estimated "
                                     "operator memory %.1f GiB > %.1f GiB (--max-gib)\"}\n"
                                   : "%6d x %-5d  %-8g  skipped: estimated operator memory %.1f GiB > %.1f GiB\n",
                      n, options.nodes_z, height, gib, options.max_operator_gib);
          std::fflush(stdout);
          continue;
        }
        const std::string label = "N=" + std::to_string(n) + " x " + std::to_string(options.nodes_z) + " H=" + std::to_string(height);
        if (!in_child(options, label, [&] { bench_case_3d({n, height}, options); })) return 1;
      }
    return 0;
  }
  if (!options.json)
    std::printf("# L = 4 m, beta = 0.25, Table S1 friction, %d thread(s), %d steps per case, "
                "instruction set %s (friction solve: %zu doubles per vector)\n"
                "#    N  H [m]     plane          us/step   floor us/step  ratio  RSS [MiB]  oscillators  setup [ms]  history\n",
                options.threads, options.steps, std::string(simd::to_string(simd::instruction_set())).c_str(), batch_width());
  std::fflush(stdout);
  for (int n : options.nodes) {
    for (double height : options.heights) {
     std::vector<std::pair<BenchCase, BenchResult>> results;
     std::vector<BenchCase> cases;
     for (PlaneCondition plane : options.planes) cases.push_back({n, height, plane});
     if (options.dissimilar)
       for (PlaneCondition plane : options.planes) cases.push_back({n, height, plane, true});
     for (const BenchCase& bench : cases) {
      // Thick strips hold O(N H/dx) normal modes: estimate the operator's
      // memory before building it, as a run does (estimate_resources: each
      // operator at the block length Simulation gives it, checked against the
      // built operators in tests/cpp/test_solver_reliability.cpp).
      if (!std::isinf(height)) {
        const double gib = estimate_resources(bench_config(bench, options)).operator_bytes / (1024.0 * 1024.0 * 1024.0);
        if (gib > options.max_operator_gib) {
          if (options.json)
            std::printf("{\"N\": %d, \"height\": %g, \"length\": 4.0, \"us_per_step\": null, "
                        "\"floor_us_per_step\": null, \"rss_mib\": null, \"skipped\": "
                        "\"estimated operator memory %.1f GiB > %.1f GiB (--max-gib)\"}\n",
                        n, height, gib, options.max_operator_gib);
          else
            std::printf("%6d  %-8g  skipped: estimated operator memory %.1f GiB > %.1f GiB\n", n, height,
                        gib, options.max_operator_gib);
          std::fflush(stdout);
          continue;
        }
      }
      // Each case in a child process (peak RSS per case); the timings come
      // back through a pipe for the ratio lines.
      int channel[2];
      if (pipe(channel) != 0) return 1;
      const pid_t pid = fork();
      if (pid < 0) return 1;
      if (pid == 0) {
        close(channel[0]);
        omp_set_num_threads(options.threads);
        BenchResult result;
        try {
          result = bench_case(bench, options);
        } catch (const std::exception& e) {
          std::fprintf(stderr, "bench N=%d H=%g failed: %s\n", n, height, e.what());
          _exit(1);
        }
        const bool sent = write(channel[1], &result, sizeof result) == static_cast<ssize_t>(sizeof result);
        _exit(sent ? 0 : 1);
      }
      close(channel[1]);
      BenchResult result;
      if (read(channel[0], &result, sizeof result) == static_cast<ssize_t>(sizeof result))
        results.emplace_back(bench, result);
      close(channel[0]);
      int status = 0;
      waitpid(pid, &status, 0);
     }
      // The antiplane and the dissimilar in-plane rows against the identical
      // in-plane one at the same N and height, and the antiplane pair of
      // different bodies against the in-plane one.
      const BenchResult* inplane = nullptr;
      const BenchResult* antiplane = nullptr;
      const BenchResult* dissimilar = nullptr;
      const BenchResult* dissimilar_antiplane = nullptr;
      for (const auto& [bench, result] : results) {
        const bool is_antiplane = bench.plane == PlaneCondition::antiplane;
        (bench.dissimilar ? (is_antiplane ? dissimilar_antiplane : dissimilar)
                          : (is_antiplane ? antiplane : inplane)) = &result;
      }
      // Both from the CPU time of one thread (the figure to quote on a shared
      // machine) and from the wall clock.
      const auto ratio_line = [&](const BenchResult* row, const char* key, const char* words,
                                  const BenchResult* reference) {
        if (!reference || !row) return;
        const double ratio = row->us_per_step / reference->us_per_step;
        const double cpu_ratio = row->cpu_us_per_step / reference->cpu_us_per_step;
        if (options.json)
          std::printf("{\"N\": %d, \"height\": %s, \"%s\": %.3f, \"cpu_%s\": %.3f}\n", n,
                      std::isinf(height) ? "null" : std::to_string(height).c_str(), key, ratio, key, cpu_ratio);
        else
          std::printf("#      %s time per step: %.2f (CPU time: %.2f)\n", words, ratio, cpu_ratio);
        std::fflush(stdout);
      };
      ratio_line(antiplane, "antiplane_over_inplane", "antiplane / in-plane", inplane);
      ratio_line(dissimilar, "dissimilar_over_identical", "dissimilar pair / identical pair (in-plane)", inplane);
      ratio_line(dissimilar_antiplane, "dissimilar_antiplane_over_inplane",
                 "dissimilar pair: antiplane / in-plane", dissimilar);
    }
  }
  return 0;
}

}  // namespace slipstrip
