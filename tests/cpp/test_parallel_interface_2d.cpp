// A 2D interface split over MPI processes (parallel/distributed_interface.hpp,
// docs/3d.md "Across machines") against the same run on one process
// (Simulation3d with its serial spectral step): every field at every node,
// and the interface's maximum and means, every 25 steps of a run that leaves
// steady sliding.  ctest runs this program with 1 and with 2 processes
// (with 1 the distributed FFT and the reductions still go through FFTW's MPI
// interface and MPI_Allreduce).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "kernels/block_strip_history.hpp"
#include "kernels/half_space_history.hpp"
#include "kernels/inplane_pair_history.hpp"
#include "kernels/two_body_history.hpp"
#include "field_test_helpers.hpp"
#include "parallel/distributed_interface.hpp"
#include "parallel/mpi_session.hpp"
#include "solver/simulation_3d.hpp"
#include "friction/friction_law.hpp"

using namespace slipstrip;

namespace {

// Table S1 defaults; strips of H = 0.1 m (about 48 in-plane normal modes per
// Fourier mode) or half-spaces, L_x = 0.8 m, dz = dx.
SimulationConfig grid_config(int nodes_x, int nodes_z, double height, HistoryAlgorithm history) {
  SimulationConfig c;
  c.geometry.length = 0.8;
  c.geometry.height = height;
  c.geometry.nodes = nodes_x;
  c.geometry.nodes_z = nodes_z;
  c.geometry.width = nodes_z * c.geometry.length / nodes_x;
  c.time.beta = 0.2;
  c.time.history = history;
  return c;
}

// A smooth initial state without symmetry in x or z (test_solver_interface_2d's).
std::vector<double> initial_state(const SimulationConfig& c, double amplitude = 1.0) {
  const int nx = c.geometry.nodes, nz = c.geometry.nodes_z;
  const double phi_ss = steady_state(c.friction, c.loading.driving_velocity);
  std::vector<double> phi(static_cast<std::size_t>(nx) * nz);
  for (int iz = 0; iz < nz; ++iz)
    for (int ix = 0; ix < nx; ++ix) {
      const double x = 2 * std::numbers::pi * ix / nx, z = 2 * std::numbers::pi * iz / nz;
      const double f = 0.8 * std::exp(std::cos(x - 0.4) + 0.7 * std::cos(z)) / std::exp(1.7) +
                       0.2 * std::sin(x) * std::cos(2 * z) + 0.15 * std::cos(x + z) + 0.15 * std::cos(x - z) +
                       0.2 * std::sin(z + 0.3) * std::cos(x);
      phi[static_cast<std::size_t>(iz) * nx + ix] = phi_ss * (1.0 + amplitude * f);
    }
  return phi;
}

// The config of grid_config(16, 8, 0.1, automatic) on a bottom body of
// another material (stiffer, denser, another Poisson ratio: c_s of the bottom
// is the top's, so a finite bottom's echo is a whole number of steps at twice
// the top's height): `height` (finite, clamped outer face; +inf a
// half-space), or a rigid base (height NaN).  Dissimilar bodies: the normal
// stress changes with the slip.
SimulationConfig bodies_config(double height, HistoryAlgorithm history) {
  SimulationConfig c = grid_config(16, 8, 0.1, history);
  if (std::isnan(height)) {
    c.bottom.body = BodyKind::rigid;
    return c;
  }
  c.bottom.body = BodyKind::elastic;
  c.bottom.shear_modulus = 18e9;
  c.bottom.density = 2400.0;
  c.bottom.poisson_ratio = 0.25;
  c.bottom.height = height;
  c.bottom.outer_face = OuterFace::clamped;
  return c;
}

// What a run must reach for the comparison not to be vacuous.
struct Reached {
  double speed = 2.0;           // max |v| / v0 above this
  double speed_z = 1e-3;        // max |v_z| / v0 above this
  double normal_change = 0.0;   // dissimilar bodies: max |sigma - sigma0| / sigma0 at least this
  bool opens = false;           // some node opens
};

// Runs `steps` steps split over MPI_COMM_WORLD and (on rank 0) on one process;
// returns on rank 0 the largest difference of any field relative to its scale.
void check_split_equals_serial(const SimulationConfig& c, int steps, const std::string& what,
                               const Reached& reached = {}, double amplitude = 1.0) {
  const MPI_Comm world = MPI_COMM_WORLD;
  const bool root = mpi_rank(world) == 0;
  const std::vector<double> phi = initial_state(c, amplitude);
  Simulation3d split(c, phi, {}, distributed_spectral_step(world));
  std::unique_ptr<Simulation3d> serial = root ? std::make_unique<Simulation3d>(c, phi) : nullptr;
  // The split operator is the one-process operator: same algorithm per
  // operator and, for the block one, the same block length.
  if (root) {
    for (auto [a, b] : {std::pair{&split.history_operator().inplane(), &serial->history_operator().inplane()},
                        std::pair{&split.history_operator().antiplane(), &serial->history_operator().antiplane()}}) {
      const auto* block_a = dynamic_cast<const BlockStripHistory*>(a);
      const auto* block_b = dynamic_cast<const BlockStripHistory*>(b);
      REQUIRE((block_a != nullptr) == (block_b != nullptr));
      if (block_a) REQUIRE(block_a->block() == block_b->block());
    }
    // Dissimilar bodies: the pairs' periods (the longest block of their
    // bodies' operators) are the same.
    const auto* pair_a = dynamic_cast<const TwoBodyHistory*>(&split.history_operator().antiplane());
    const auto* pair_b = dynamic_cast<const TwoBodyHistory*>(&serial->history_operator().antiplane());
    REQUIRE((pair_a != nullptr) == (pair_b != nullptr));
    if (pair_a) REQUIRE(pair_a->period() == pair_b->period());
    const auto* inplane_a = dynamic_cast<const InplanePairHistory*>(&split.history_operator().inplane());
    const auto* inplane_b = dynamic_cast<const InplanePairHistory*>(&serial->history_operator().inplane());
    REQUIRE((inplane_a != nullptr) == (inplane_b != nullptr));
    if (inplane_a) REQUIRE(inplane_a->period() == inplane_b->period());
  }
  const double v0 = c.loading.driving_velocity;
  double worst = 0.0, largest = 0.0, largest_z = 0.0, worst_reduction = 0.0, normal_change = 0.0;
  long long open_nodes = 0;  // node-steps with a gap
  for (int n = 0; n <= steps; ++n) {
    if (n % 25 == 0 || n == steps) {
      // (name, split field, serial field, the scale it is compared with)
      struct Field {
        const char* name;
        std::span<const double> (Simulation3d::*get)() const;
        std::span<const double> (Simulation3d::*scale)() const;
      };
      std::vector<Field> fields = {{"slip_x", &Simulation3d::slip_x, &Simulation3d::slip_x},
                              {"slip_z", &Simulation3d::slip_z, &Simulation3d::slip_x},
                              {"slip_rate_x", &Simulation3d::slip_rate_x, &Simulation3d::speed},
                              {"slip_rate_z", &Simulation3d::slip_rate_z, &Simulation3d::speed},
                              {"speed", &Simulation3d::speed, &Simulation3d::speed},
                              {"state", &Simulation3d::state, &Simulation3d::state},
                              {"shear_stress_x", &Simulation3d::shear_stress_x, &Simulation3d::shear_stress_x},
                              {"shear_stress_z", &Simulation3d::shear_stress_z, &Simulation3d::shear_stress_x}};
      // Dissimilar bodies: the normal stress, the one the friction sees, and
      // the opening (its own scale; compared absolutely while it is 0).
      if (split.variable_normal_stress())
        fields.insert(fields.end(),
                      {{"normal_stress", &Simulation3d::normal_stress, &Simulation3d::normal_stress},
                       {"effective_normal_stress", &Simulation3d::effective_normal_stress,
                        &Simulation3d::normal_stress},
                       {"opening", &Simulation3d::opening, &Simulation3d::opening},
                       {"opening_rate", &Simulation3d::opening_rate, &Simulation3d::opening_rate}});
      for (const Field& f : fields) {
        const std::vector<double> whole = gather_rows((split.*f.get)(), world);
        if (!root) continue;
        const auto reference = (serial.get()->*f.get)();
        REQUIRE(whole.size() == reference.size());
        const double scale = max_abs((serial.get()->*f.scale)());
        const double d = scale > 0 ? max_abs_difference(whole, reference) / scale : max_abs_difference(whole, reference);
        INFO(what << ": step " << n << ", " << f.name << " differs by " << d << " of its scale");
        // Tolerance 1e-11 of the field's scale (|v| for slip rates, |slip_x|
        // and tau_x for the z components): the distributed FFT adds the same
        // terms in another order and the means add partial sums per process,
        // so the runs differ by rounding (~1e-16 relative per step), carried
        // by a growing, nonlinear run; as test_solver_interface_2d's (a).
        CHECK(d < 1e-11);
        worst = std::max(worst, d);
      }
      // The reductions: every process gets the whole interface's values.
      const double reductions[3] = {split.max_slip_rate(), split.mean_slip_x(), split.mean_shear_stress_x()};
      double expected[3] = {0, 0, 0};
      if (root) expected[0] = serial->max_slip_rate(), expected[1] = serial->mean_slip_x(),
                expected[2] = serial->mean_shear_stress_x();
      MPI_Bcast(expected, 3, MPI_DOUBLE, 0, world);
      for (int r = 0; r < 3; ++r) {
        const double d =
            reductions[r] == expected[r] ? 0.0 : std::abs(reductions[r] - expected[r]) / std::abs(expected[r]);
        // The maximum is exact up to the fields' own round-off; the means add in
        // another order (1e-11 as the fields).
        CHECK(d < 1e-11);
        worst_reduction = std::max(worst_reduction, d);
      }
      if (root) {
        largest = std::max(largest, serial->max_slip_rate());
        largest_z = std::max(largest_z, max_abs(serial->slip_rate_z()));
        if (serial->variable_normal_stress()) {
          const double sigma0 = c.loading.normal_stress;
          for (double sigma : serial->normal_stress()) normal_change = std::max(normal_change, std::abs(sigma - sigma0) / sigma0);
        }
      }
    }
    if (n == steps) break;
    split.step();
    if (root) {
      serial->step();
      for (double gap : serial->opening()) open_nodes += gap > 0.0 ? 1 : 0;
    }
  }
  if (root) {
    MESSAGE(what << " on " << mpi_size(world) << " processes, " << steps << " steps: max |v| = " << largest / v0
                 << " v0, max |v_z| = " << largest_z / v0 << " v0; largest field difference " << worst
                 << ", reductions " << worst_reduction << "; max |sigma - sigma0| = " << normal_change
                 << " sigma0, open node-steps " << open_nodes);
    // The run really leaves steady sliding, in both directions, so the comparison is not vacuous.
    CHECK(largest > reached.speed * v0);
    CHECK(largest_z > reached.speed_z * v0);
    CHECK(normal_change >= reached.normal_change);
    if (reached.opens) CHECK(open_nodes > 0);
  }
}

}  // namespace

TEST_CASE("2D interface split over MPI processes = one process (modal strips, 16 x 8)") {
  check_split_equals_serial(grid_config(16, 8, 0.1, HistoryAlgorithm::modal), 500, "modal 16 x 8");
}

TEST_CASE("2D interface split over MPI processes = one process (block strips, 16 x 8)") {
  check_split_equals_serial(grid_config(16, 8, 0.1, HistoryAlgorithm::block), 500, "block 16 x 8");
}

TEST_CASE("2D interface split over MPI processes = one process (odd grid 15 x 9, uneven slabs)") {
  check_split_equals_serial(grid_config(15, 9, 0.1, HistoryAlgorithm::modal), 500, "modal 15 x 9");
}

TEST_CASE("2D interface split over MPI processes = one process (half-spaces, 16 x 8)") {
  check_split_equals_serial(grid_config(16, 8, std::numeric_limits<double>::infinity(), HistoryAlgorithm::automatic), 500,
                            "half-spaces 16 x 8");
}

// Dissimilar bodies: the in-plane pair (each body's 2x2 face operator), the
// antiplane pair and the normal stress (a third pair of distributed
// transforms), each process holding its own modes' operators.
TEST_CASE("2D interface split over MPI processes = one process (dissimilar strips, 16 x 8)") {
  check_split_equals_serial(bodies_config(0.2, HistoryAlgorithm::automatic), 500, "dissimilar strips 16 x 8",
                            {1.5, 1e-3, 1e-3});
}

TEST_CASE("2D interface split over MPI processes = one process (dissimilar strips, block, 16 x 8)") {
  check_split_equals_serial(bodies_config(0.2, HistoryAlgorithm::block), 200, "dissimilar block strips 16 x 8",
                            {1.5, 1e-3, 1e-3});
}

TEST_CASE("2D interface split over MPI processes = one process (strip on a half-space, 16 x 8)") {
  check_split_equals_serial(bodies_config(std::numeric_limits<double>::infinity(), HistoryAlgorithm::automatic), 500,
                            "strip on a half-space 16 x 8", {1.5, 1e-3, 1e-3});
}

TEST_CASE("2D interface split over MPI processes = one process (strip on a rigid base, 15 x 9)") {
  SimulationConfig c = bodies_config(std::numeric_limits<double>::quiet_NaN(), HistoryAlgorithm::automatic);
  c.geometry.nodes = 15;
  c.geometry.nodes_z = 9;
  c.geometry.width = 9 * c.geometry.length / 15;
  check_split_equals_serial(c, 500, "strip on a rigid base 15 x 9", {1.5, 1e-3, 1e-3});
}

TEST_CASE("2D interface split over MPI processes = one process (dissimilar strips that open, 16 x 8)") {
  // A soft bottom strip (1/12 of the top's shear modulus, the top's density
  // and Poisson ratio), f0 = 1.5, a = 0.02 and twice the initial perturbation:
  // the slip unloads the normal stress through the bodies' dissimilarity
  // until faces open (measured: 57 node-steps open in 400 steps, max |v| =
  // 1.4e3 v0), so the contact step and the opening stress's transform run on
  // every process.
  SimulationConfig c = bodies_config(0.2, HistoryAlgorithm::automatic);
  c.bottom.shear_modulus = 0.75e9;
  c.bottom.density = 1200.0;
  c.bottom.poisson_ratio = 0.33;
  c.friction.f0 = 1.5;
  c.friction.a = 0.02;
  check_split_equals_serial(c, 400, "dissimilar strips that open 16 x 8", {100.0, 10.0, 1.0, true}, 2.0);
}
