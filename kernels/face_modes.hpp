#pragma once
// Exact normal-mode (Mittag-Leffler) expansion of a finite body's 2x2 face
// response (docs/inplane_bodies.md §4):
//     K(k, s) = K(k, 0) - sum_m W_m s^2 / (s^2 + omega_m^2),
// a sum over the modes of the body with its face held fixed (u = 0 at y = 0)
// and its outer face driven or clamped.  The poles s = +-i omega_m are simple,
// each residue matrix is rank one and negative semidefinite (W_m <= 0: the body
// is lossless and passive), and the series converges like sum 1/omega_m^2
// (W_m tends to a constant), so no separate echo comb is needed.
//
// In the time domain a mode contributes -W_m int_0^t (1 - cos omega_m (t - t'))
// v(t') dt' to the face traction t = K u (as the strip modes of
// kernels/strip_response.hpp, now with a matrix weight).
#include <vector>

#include "kernels/face_response.hpp"

namespace slipstrip {

struct FaceMode {
  double frequency;  // omega_m [rad/s]
  FaceMatrix weight; // W_m = (residue of K in s^2) / omega_m^2 [Pa/m], rank one, <= 0
};

// Every mode with 0 < omega_m <= max_frequency, in increasing frequency, of the
// finite body of this height and outer face at wavenumber k (either sign; the
// weights' off-diagonal entries are odd in k).  For k = 0 the uniform mode's 1D
// shear and P resonances (diagonal weights).  For k != 0 the modes are the
// zeros of an entire function of s^2 bracketed on a grid of 1/16 of a half
// wavelength in both the shear and the P vertical wavenumber (grid_divisions = 16
// per half wavelength; tests use a finer grid to show nothing is missed) and
// polished by bisection; throws std::invalid_argument for a half-space.
std::vector<FaceMode> face_modes(const ElasticMaterial& material, double height,
                                 OuterFace outer_face, double wavenumber, double max_frequency,
                                 int grid_divisions = 16);

}  // namespace slipstrip
