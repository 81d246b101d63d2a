// The half-space operator's mode loop compiled for each instruction set
// (simd/instruction_set.hpp): every copy this CPU can run gives the baseline
// copy's history.  A portable binary runs the baseline (SSE2), AVX2 or
// AVX-512 copy depending on the machine; test_kernels_half_space_operator.cpp
// verifies the operator itself with the copy chosen for this CPU.
//
// Tolerance: 1e-13 of the largest history value.  The copies are the same C++
// compiled with different flags and no reassociation (no -ffast-math), so the
// sums run in the same order; they differ only where AVX2/AVX-512 contract
// a * b + c into one FMA, which rounds once instead of twice (<= 1 ulp of the
// term per operation).  Each history value sums ~300 exponentials and up to a
// few hundred stored lags, and the damped rotations (|pole| < 1) do not
// amplify an earlier rounding: a few hundred eps, ~1e-14, of the largest
// value, at most (measured 1.7-1.9e-16).  A wrong copy (a skipped mode, a
// wrong index) differs at O(1).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include "kernels/half_space_history.hpp"
#include "simd/instruction_set.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;

TEST_CASE("half-space operator: every usable instruction set gives the baseline history") {
  for (const PlaneCondition plane : {PlaneCondition::strain, PlaneCondition::antiplane}) {
    ElasticMaterial m;
    m.plane = plane;
    const int N = 128;
    const double L = 4.0, dt = 0.25 * (L / N) / m.shear_wave_speed();
    HalfSpaceOperatorDesign baseline_design;
    baseline_design.instruction_set = simd::InstructionSet::baseline;
    HalfSpaceHistory baseline(m, L, N, dt, baseline_design);
    const int steps = 2 * baseline.slow_block() + 40;  // ends inside a block
    for (const auto set : simd::usable_instruction_sets()) {
      if (set == simd::InstructionSet::baseline) continue;
      HalfSpaceOperatorDesign design;
      design.instruction_set = set;
      HalfSpaceHistory wide(m, L, N, dt, design);
      HalfSpaceHistory reference(m, L, N, dt, baseline_design);
      std::mt19937 rng(17);
      std::normal_distribution<double> normal;
      double worst = 0.0, largest = 0.0;
      for (int n = 0; n < steps; ++n) {
        std::vector<cplx> v(reference.modes());
        for (auto& x : v) x = cplx(normal(rng), normal(rng));
        reference.push(v);
        wide.push(v);
        for (int q = 0; q < reference.modes(); ++q) {
          worst = std::max(worst, std::abs(reference.history()[q] - wide.history()[q]));
          largest = std::max(largest, std::abs(reference.history()[q]));
        }
      }
      MESSAGE(simd::to_string(set) << ", plane condition " << static_cast<int>(plane)
                                   << ": max |difference| / max |history| = " << worst / largest
                                   << " over " << steps << " steps");
      CHECK(largest > 0.0);
      CHECK(worst <= 1e-13 * largest);
    }
  }
}
