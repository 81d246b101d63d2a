#pragma once
// The numbers that define where the local interface solve starts and when it
// stops, shared by the scalar solve (friction_law.cpp) and the vectorised batch
// solve (batch_kernels.inc).  The batch solve promises the scalar solve's
// result to within its tolerance (docs/friction.md, "Batch solve"), which holds
// only while both use these same values.
#include <limits>

namespace slipstrip::local_solve {

// Margin [in ln u] by which the bounds on the root are widened, so that
// round-off in the bounds can never put the root outside them.
inline constexpr double kBracketMargin = 1e-3;

// Accept when the Newton step |dw| in w = ln u is at most this: |g''| <= |g'|
// in w for every strength law, so the step leaves an error of at most ~dw^2/2
// in ln u, and taking it linearly in u adds another dw^2/2: the result is
// within 1e-12 relative of the root.
inline constexpr double kAcceptStep = 1e-6;

// Round-off floor: accept when |g| <= kRoundoffFloorFactor * eps * scale,
// scale being the size of the terms summed into g; below that the root is not
// defined more sharply than the rounding of those terms.
inline constexpr double kRoundoffFloorFactor = 8.0;
inline constexpr double kRoundoffFloor =
    kRoundoffFloorFactor * std::numeric_limits<double>::epsilon();

}  // namespace slipstrip::local_solve
