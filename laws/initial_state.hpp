#pragma once
// The initial state phi(x, 0): steady sliding at v0 (phi_ss per node) plus the
// [initial] perturbations, phi_ss [1 + noise + sine + Gaussian bump].
//
// Two kinds of noise (docs/config.md, [initial]):
//   noise_modes = 0 : independent normal numbers per node (white noise).  Its
//                     content moves to shorter wavelengths as the mesh is
//                     refined, and the same seed gives an unrelated field on
//                     another mesh, so two resolutions start from different
//                     states.
//   noise_modes = M : the first M Fourier modes of the interface with normal
//                     coefficients drawn in the order k = 1..M.  The same seed
//                     gives the same field on every mesh with M < N/2, so a
//                     refinement study changes the discretisation only, not the
//                     initial condition (docs/fig5_resolution.md).
// Both have expected pointwise variance noise_amplitude^2 and no k = 0 content
// in expectation (mode k = 0 is never drawn by the band-limited kind).
#include <span>
#include <vector>

#include "config/simulation_config.hpp"

namespace slipstrip {

// phi(x, 0) at the nodes x (period `length` [m]) around the steady states
// phi_ss (one per node).  Not on the hot path: called once per run.  Throws
// std::invalid_argument, naming the keys, if the perturbations make phi <= 0.
std::vector<double> perturbed_steady_state(const InitialConfig& init, std::span<const double> x,
                                           double length, std::span<const double> phi_ss);
// The same on a 2D interface, nodes at (x, z) with periods `length` and
// `width`: with init.local_width_z > 0 the Gaussian bump is also a Gaussian in
// z about init.local_center_z (a patch); otherwise every term is the one of x
// above, bit for bit.
std::vector<double> perturbed_steady_state(const InitialConfig& init, std::span<const double> x,
                                           std::span<const double> z, double length, double width,
                                           std::span<const double> phi_ss);

}  // namespace slipstrip
