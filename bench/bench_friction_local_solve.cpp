// Microbenchmark of the local interface solve (not a test): N nodes sliding
// near v0 with loads and states that drift slowly from step to step, each
// solve warm-started from that node's previous slip rate, as in the time loop.
// Prints ns per solve and the mean iteration count for each strength law.
// Both wall-clock and thread CPU time are reported: on a shared machine the
// wall-clock figure includes time the process spent waiting for a core.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "friction/batch_solve.hpp"
#include "friction/friction_law.hpp"

using namespace slipstrip;

namespace {
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
}  // namespace

int main() {
  constexpr int nodes = 4096;
  constexpr int steps = 400;
  const double sigma0 = 1e6;
  const double eta = 9e9 / (2 * std::sqrt(9e9 / 1200.0));
  const double v0 = 2e-3;

  for (auto law : {StrengthLaw::paper, StrengthLaw::dieterich_ruina, StrengthLaw::regularized}) {
    FrictionParameters p;
    p.strength_law = law;
    if (law != StrengthLaw::paper) {
      p.f0 = 0.6;
      p.a = 0.01;
      p.b = 0.015;
      p.characteristic_slip = 1e-5;
      p.v_star = 1e-6;
    }
    std::vector<double> slip_rate(nodes), state(nodes), tau0(nodes);
    for (int i = 0; i < nodes; ++i) {
      // Spread the nodes over three decades of slip rate around v0.
      const double v = v0 * std::pow(10.0, -1.5 + 3.0 * i / nodes);
      state[i] = steady_state(p, v);
      tau0[i] = eta * v + frictional_strength(p, sigma0, v, state[i]);
      slip_rate[i] = v;
    }
    long iterations = 0;
    double checksum = 0.0;
    const double cpu_start = thread_cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < steps; ++k) {
      const double drift = 1e-3 * std::sin(0.05 * k);
      for (int i = 0; i < nodes; ++i) {
        const auto s = solve_slip_rate_counted(p, sigma0, eta, tau0[i] * (1 + drift), state[i],
                                               slip_rate[i]);
        slip_rate[i] = s.slip_rate;
        iterations += s.iterations;
      }
    }
    const auto stop = std::chrono::steady_clock::now();
    const double cpu_ns = (thread_cpu_seconds() - cpu_start) * 1e9;
    for (double v : slip_rate) checksum += v;
    const double solves = static_cast<double>(nodes) * steps;
    const double ns = std::chrono::duration<double, std::nano>(stop - start).count() / solves;
    std::printf("%-16s %7.1f ns/solve CPU  %7.1f ns/solve wall  %.2f iterations/solve  "
                "(%d nodes x %d steps, checksum %.6e)\n",
                std::string(to_string(law)).c_str(), cpu_ns / solves, ns, iterations / solves, nodes,
                steps, checksum);

    // The same solves through the batch routine (friction/batch_solve.hpp):
    // one call per step over all nodes, warm-started the same way.
    for (int i = 0; i < nodes; ++i) {
      const double v = v0 * std::pow(10.0, -1.5 + 3.0 * i / nodes);
      slip_rate[i] = v;
    }
    const LocalSolveParameters params{p, sigma0, eta};
    std::vector<double> tau(nodes);
    BatchCounts counts;
    const double batch_cpu_start = thread_cpu_seconds();
    const auto batch_start = std::chrono::steady_clock::now();
    for (int k = 0; k < steps; ++k) {
      const double drift = 1e-3 * std::sin(0.05 * k);
      for (int i = 0; i < nodes; ++i) tau[i] = tau0[i] * (1 + drift);
      counts += solve_slip_rate_batch(params, tau, state, slip_rate, slip_rate);
    }
    const auto batch_stop = std::chrono::steady_clock::now();
    const double batch_cpu_ns = (thread_cpu_seconds() - batch_cpu_start) * 1e9;
    double batch_checksum = 0.0;
    for (double v : slip_rate) batch_checksum += v;
    const double batch_ns =
        std::chrono::duration<double, std::nano>(batch_stop - batch_start).count() / solves;
    // Iterations: residual evaluations of the vector path per node it solved;
    // nodes handed to the scalar solve (all of them for the laws without a
    // vector path) are counted separately.
    const double vector_nodes = static_cast<double>(counts.solves - counts.scalar_nodes);
    std::printf("%-16s %7.1f ns/solve CPU  %7.1f ns/solve wall  %.2f iterations/solve  "
                "(%d nodes x %d steps, checksum %.6e, %lld of %lld solves scalar)\n",
                (std::string(to_string(law)) + " batch").c_str(), batch_cpu_ns / solves, batch_ns,
                vector_nodes > 0 ? counts.evaluations / vector_nodes : 0.0, nodes, steps,
                batch_checksum, counts.scalar_nodes, counts.solves);
  }
  return 0;
}
