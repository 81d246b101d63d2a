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
std::vector<double> initial_state(const SimulationConfig& c) {
  const int nx = c.geometry.nodes, nz = c.geometry.nodes_z;
  const double phi_ss = steady_state(c.friction, c.loading.driving_velocity);
  std::vector<double> phi(static_cast<std::size_t>(nx) * nz);
  for (int iz = 0; iz < nz; ++iz)
    for (int ix = 0; ix < nx; ++ix) {
      const double x = 2 * std::numbers::pi * ix / nx, z = 2 * std::numbers::pi * iz / nz;
      const double f = 0.8 * std::exp(std::cos(x - 0.4) + 0.7 * std::cos(z)) / std::exp(1.7) +
                       0.2 * std::sin(x) * std::cos(2 * z) + 0.15 * std::cos(x + z) + 0.15 * std::cos(x - z) +
                       0.2 * std::sin(z + 0.3) * std::cos(x);
      phi[static_cast<std::size_t>(iz) * nx + ix] = phi_ss * (1.0 + f);
    }
  return phi;
}

// Runs `steps` steps split over MPI_COMM_WORLD and (on rank 0) on one process;
// returns on rank 0 the largest difference of any field relative to its scale.
void check_split_equals_serial(const SimulationConfig& c, int steps, const std::string& what) {
  const MPI_Comm world = MPI_COMM_WORLD;
  const bool root = mpi_rank(world) == 0;
  const std::vector<double> phi = initial_state(c);
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
  }
  const double v0 = c.loading.driving_velocity;
  double worst = 0.0, largest = 0.0, largest_z = 0.0, worst_reduction = 0.0;
  for (int n = 0; n <= steps; ++n) {
    if (n % 25 == 0 || n == steps) {
      // (name, split field, serial field, the scale it is compared with)
      struct Field {
        const char* name;
        std::span<const double> (Simulation3d::*get)() const;
        std::span<const double> (Simulation3d::*scale)() const;
      };
      const Field fields[] = {{"slip_x", &Simulation3d::slip_x, &Simulation3d::slip_x},
                              {"slip_z", &Simulation3d::slip_z, &Simulation3d::slip_x},
                              {"slip_rate_x", &Simulation3d::slip_rate_x, &Simulation3d::speed},
                              {"slip_rate_z", &Simulation3d::slip_rate_z, &Simulation3d::speed},
                              {"speed", &Simulation3d::speed, &Simulation3d::speed},
                              {"state", &Simulation3d::state, &Simulation3d::state},
                              {"shear_stress_x", &Simulation3d::shear_stress_x, &Simulation3d::shear_stress_x},
                              {"shear_stress_z", &Simulation3d::shear_stress_z, &Simulation3d::shear_stress_x}};
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
      }
    }
    if (n == steps) break;
    split.step();
    if (root) serial->step();
  }
  if (root) {
    MESSAGE(what << " on " << mpi_size(world) << " processes, " << steps << " steps: max |v| = " << largest / v0
                 << " v0, max |v_z| = " << largest_z / v0 << " v0; largest field difference " << worst
                 << ", reductions " << worst_reduction);
    // The run really leaves steady sliding, in both directions, so the comparison is not vacuous.
    CHECK(largest > 2 * v0);
    CHECK(largest_z > 1e-3 * v0);
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
