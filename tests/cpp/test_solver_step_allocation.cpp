// A whole time step does not allocate (the time loop's contract): every heap
// allocation of this program is counted (allocation_counter.hpp: operator new,
// malloc and the aligned forms FFTW uses, from any library) while a Simulation
// or a Simulation3d steps, for the identical in-plane strip pair (modal and
// block history), the identical antiplane pair, the identical half-space pair,
// a dissimilar antiplane pair (block and modal bodies), a dissimilar in-plane
// pair (per-node normal stress, sigma_eff regularised over a slip), a
// dissimilar half-space pair, the same strip pair through an open phase, and a
// 2D interface (identical and dissimilar bodies).
//
// Warm-up: the counted steps start after a few steps, so that what a solver
// does once on its first steps (the t = 0 half-weight sample, the first
// pass through each branch) is not counted; each window then spans more steps
// than the history operator's period (block length B, or the pair's period),
// so every far-field update and every FFT level of the block operators runs
// inside it.
//
// OpenMP: each case runs with one thread and with two, the thread pool started
// before counting (the runtime's one start per process).  libgomp (GCC 12)
// allocates a new team at every parallel region of one thread (it caches the
// team only for more than one), so no per-step code path may open a parallel
// region that runs one thread: the solver's per-step loops run serially then
// (simd/parallel_for.hpp; the block operators test the thread count
// themselves), and the counts below are zero with no exemption.
#include <doctest/doctest.h>
#include <omp.h>

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/inplane_pair_history.hpp"
#include "kernels/two_body_history.hpp"
#include "solver/simulation.hpp"
#include "solver/simulation_3d.hpp"
#include "solver_test_configs.hpp"

using namespace slipstrip;
using slipstrip_test::allocations;
using slipstrip_test::with_threads;

namespace {

// Steps before counting (above).
constexpr int kWarmUp = 4;

// Table S1 strips H = 0.1 m, L = 0.8 m, 32 nodes, with a large perturbation
// (max |v| several v0 within the window: every branch of the law runs).
SimulationConfig strip_pair() {
  SimulationConfig c = testing::short_strip_pair(0.8, 32, 0.2);
  testing::add_large_perturbation(c, 0.3);
  return c;
}

// The same top strip on a dissimilar bottom strip (its normal stress changes
// node by node); the friction sees sigma_eff relaxed over half D_c.
SimulationConfig dissimilar_pair() {
  SimulationConfig c = testing::with_dissimilar_bottom(strip_pair());
  c.interface.normal_stress_slip = 0.5 * c.friction.characteristic_slip;
  return c;
}

// Runs body() with one and with two OpenMP threads (with_threads).
template <class Body>
void with_one_and_two_threads(Body body) {
  for (int threads : {1, 2}) with_threads(threads, body);
}

// What a counted window saw: the allocations, and the largest slip rate
// (that the run left steady sliding, so the law's nonlinear branches ran).
struct Window {
  long allocations = 0;
  double largest_slip_rate = 0.0;
};

// Allocations during `steps` steps of `sim` after kWarmUp steps.
template <class Sim>
Window count_in_steps(Sim& sim, int steps, const std::string& what) {
  for (int n = 0; n < kWarmUp; ++n) sim.step();
  Window w;
  const long before = allocations();
  for (int n = 0; n < steps; ++n) {
    sim.step();
    w.largest_slip_rate = std::max(w.largest_slip_rate, sim.max_slip_rate());
  }
  w.allocations = allocations() - before;
  MESSAGE(what << ", " << omp_get_max_threads() << " thread(s): allocations in " << steps << " steps after "
               << kWarmUp << ": " << w.allocations << "; max v = "
               << w.largest_slip_rate / sim.config().loading.driving_velocity << " v0");
  return w;
}

// The counted steps leave steady sliding and allocate nothing.
template <class Sim>
void check_no_allocation(Sim& sim, int steps, const std::string& what) {
  const Window w = count_in_steps(sim, steps, what);
  CHECK(w.allocations == 0);
  CHECK(w.largest_slip_rate > 2.0 * sim.config().loading.driving_velocity);
}

// The counted window: more than two periods of the operator (above), and at
// least 600 steps, in which the large perturbation grows past 2 v0 (checked).
int window(int period) { return std::max(600, 2 * period + 3); }

}  // namespace

TEST_CASE("the allocation counter sees a step's kind of allocation") {
  // Without this the zero counts below could come from a counter that never counts.
  const long before = allocations();
  {
    std::vector<double> values(1000);
    void* volatile escaped = values.data();  // the allocation cannot be elided
    (void)escaped;
  }
  CHECK(allocations() - before >= 1);
}

TEST_CASE("identical in-plane strip pair: a step does not allocate (modal and block history)") {
  with_one_and_two_threads([] {
    SimulationConfig c = strip_pair();
    c.time.history = HistoryAlgorithm::modal;
    Simulation modal(c);
    REQUIRE(dynamic_cast<const BlockStripHistory*>(&modal.history_operator()) == nullptr);
    check_no_allocation(modal, window(1), "identical pair, modal history");

    c.time.history = HistoryAlgorithm::block;
    Simulation block(c);
    const auto* op = dynamic_cast<const BlockStripHistory*>(&block.history_operator());
    REQUIRE(op != nullptr);
    check_no_allocation(block, window(op->block()), "identical pair, block history B = " + std::to_string(op->block()));
  });
}

TEST_CASE("identical antiplane strip pair: a step does not allocate") {
  with_one_and_two_threads([] {
    SimulationConfig c = strip_pair();
    c.material.plane = PlaneCondition::antiplane;
    Simulation sim(c);
    const auto* op = dynamic_cast<const BlockStripHistory*>(&sim.history_operator());
    check_no_allocation(sim, window(op ? op->block() : 1), "identical antiplane pair");
  });
}

TEST_CASE("identical half-space pair: a step does not allocate") {
  with_one_and_two_threads([] {
    SimulationConfig c = strip_pair();
    c.geometry.height = std::numeric_limits<double>::infinity();
    Simulation sim(c);
    check_no_allocation(sim, window(1), "identical half-space pair");
  });
}

TEST_CASE("dissimilar in-plane pair, regularised normal stress: a step does not allocate") {
  with_one_and_two_threads([] {
    // 128 nodes: two chunks of the parallel friction solve, so that with two
    // threads its parallel loop runs.
    SimulationConfig c = dissimilar_pair();
    c.geometry.nodes = 128;
    Simulation sim(c);
    REQUIRE(sim.variable_normal_stress());
    const auto* pair = dynamic_cast<const InplanePairHistory*>(&sim.history_operator());
    REQUIRE(pair != nullptr);
    check_no_allocation(sim, window(pair->period()), "dissimilar pair");
    // The normal stress did change node by node, so the per-node friction path ran.
    const auto sigma = sim.normal_stress();
    const auto [low, high] = std::minmax_element(sigma.begin(), sigma.end());
    REQUIRE(*high - *low > 1e-6 * c.loading.normal_stress);
  });
}

TEST_CASE("dissimilar antiplane pair (one operator per body): a step does not allocate") {
  with_one_and_two_threads([] {
    for (const HistoryAlgorithm history : {HistoryAlgorithm::block, HistoryAlgorithm::modal}) {
      SimulationConfig c = testing::with_dissimilar_bottom(strip_pair());
      c.material.plane = PlaneCondition::antiplane;
      c.time.history = history;
      c.time.antiplane_pair = AntiplanePairOperator::bodies;
      Simulation sim(c);
      const auto* bodies = dynamic_cast<const TwoBodyHistory*>(&sim.history_operator());
      REQUIRE(bodies != nullptr);
      // block: each body at body_block_length's B (1024), the far field inside the window.
      REQUIRE(bodies->period() == (history == HistoryAlgorithm::block ? kBodyBlockLength : 1));
      check_no_allocation(sim, window(bodies->period()),
                          std::string("dissimilar antiplane pair, ") +
                              (history == HistoryAlgorithm::block ? "block" : "modal") + " bodies");
    }
  });
}

TEST_CASE("dissimilar antiplane pair (one combined operator): a step does not allocate") {
  with_one_and_two_threads([] {
    for (const HistoryAlgorithm history : {HistoryAlgorithm::block, HistoryAlgorithm::modal}) {
      SimulationConfig c = testing::with_dissimilar_bottom(strip_pair());
      c.material.plane = PlaneCondition::antiplane;
      c.time.history = history;
      REQUIRE(c.time.antiplane_pair == AntiplanePairOperator::combined);
      Simulation sim(c);
      REQUIRE(dynamic_cast<const TwoBodyHistory*>(&sim.history_operator()) == nullptr);
      const auto* block = dynamic_cast<const BlockStripHistory*>(&sim.history_operator());
      REQUIRE((block != nullptr) == (history == HistoryAlgorithm::block));
      // block: body_block_length's B (1024), the far field inside the window.
      if (block) REQUIRE(block->block() == kBodyBlockLength);
      check_no_allocation(sim, window(block ? block->block() : 1),
                          std::string("dissimilar antiplane pair, ") +
                              (history == HistoryAlgorithm::block ? "block" : "modal") + " combined");
    }
  });
}

TEST_CASE("dissimilar half-space pair: a step does not allocate") {
  // Two half-spaces of different materials (FaceHalfSpaceHistory each, its
  // slow exponentials advanced once per block): the window spans more than
  // two blocks, so every block end runs inside it.
  with_one_and_two_threads([] {
    SimulationConfig c = dissimilar_pair();
    c.geometry.height = std::numeric_limits<double>::infinity();
    c.bottom.height = std::numeric_limits<double>::infinity();
    Simulation sim(c);
    REQUIRE(sim.variable_normal_stress());
    const auto* pair = dynamic_cast<const InplanePairHistory*>(&sim.history_operator());
    REQUIRE(pair != nullptr);
    REQUIRE(pair->period() > 1);
    check_no_allocation(sim, window(pair->period()), "dissimilar half-space pair");
  });
}

TEST_CASE("dissimilar in-plane pair through an open phase: a step does not allocate") {
  // A softer, thicker bottom strip and a shear-load pulse of 5 sigma0 that
  // opens the interface (as test_solver_interface_opening): the opening
  // stress is pushed through the pair's operators while nodes are open.
  SimulationConfig c = testing::short_strip_pair(1.0, 64, 0.25);
  c.interface.load_pulse_amplitude = 5e6;
  c.interface.pulse_center = 0.5;
  c.interface.pulse_width = 0.05;
  c.interface.profile = TimeProfile::bump;
  c.interface.rise_time = 1e-4;
  c.bottom.body = BodyKind::elastic;
  c.bottom.shear_modulus = 3e9;
  c.bottom.height = 0.2;
  with_one_and_two_threads([&] {
    Simulation sim(c);
    int steps = 0;
    for (; sim.open_nodes() == 0 && steps < 3000; ++steps) sim.step();
    REQUIRE(sim.open_nodes() > 0);
    // Counted from the first open level on, over steps in which nodes open,
    // stay open and close again.
    const long before = allocations();
    int open_steps = 0;
    for (int n = 0; n < 400; ++n) {
      sim.step();
      open_steps += sim.open_nodes() > 0;
    }
    const long during = allocations() - before;
    MESSAGE("open phase, " << omp_get_max_threads() << " thread(s): opened after " << steps
                           << " steps; allocations in 400 steps ("
                           << open_steps << " with an open node): " << during);
    REQUIRE(open_steps > 0);
    CHECK(during == 0);
  });
}

TEST_CASE("2D interface: a step does not allocate (identical and dissimilar bodies)") {
  with_one_and_two_threads([] {
    SimulationConfig c = strip_pair();
    c.geometry.nodes_z = 4;
    c.geometry.width = 0.1;  // dz = 0.025 m = dx
    Simulation3d identical(c);
    check_no_allocation(identical, window(1), "2D interface, identical bodies");

    SimulationConfig d = dissimilar_pair();
    d.geometry.nodes_z = 4;
    d.geometry.width = 0.1;
    Simulation3d dissimilar(d);
    REQUIRE(dissimilar.variable_normal_stress());
    check_no_allocation(dissimilar, window(1), "2D interface, dissimilar bodies");
  });
}

TEST_CASE("2D interface of 8192 nodes (node loops on the threads): a step does not allocate") {
  // 32 x 256 nodes: at or above the count from which Simulation3d's node
  // loops and RealFft2d's paired transforms run on the OpenMP threads.
  with_one_and_two_threads([] {
    SimulationConfig c = strip_pair();
    c.geometry.nodes_z = 256;
    c.geometry.width = 0.64;  // dz = 2.5 mm
    Simulation3d sim(c);
    REQUIRE(sim.nodes() == 8192);
    check_no_allocation(sim, window(1), "2D interface, 32 x 256 nodes");
  });
}
