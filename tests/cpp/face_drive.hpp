#pragma once
// Shared by the 2x2 face-operator tests: drive one Fourier mode (q = 1 unless
// told) of one body's operator (kernels/face_history.hpp) with a prescribed
// face displacement and compare the face traction with the inverse Laplace
// transform of K(k, s).
#include <complex>
#include <cstddef>
#include <vector>

#include "inverse_laplace.hpp"
#include "kernels/face_history.hpp"
#include "single_mode_drive.hpp"

namespace slipstrip::testing {

// Face traction t_n = E v_n + h_n of mode q (default 1) for the face displacement
// u = g(t) e_component (g the sin^4 bump over `rise`), n = 0..steps, as the real
// functions compared with the inverse Laplace transform: (t_x, t_y) for
// component x are (Re, Im) and for component y (Im, Re) (K_xy, K_yx are i times
// real functions).
struct FaceTractions {
  std::vector<double> x, y;
};
inline FaceTractions drive_face_mode(FaceHistory& history, int component, double rise, int steps,
                                     std::size_t q = 1) {
  using cd = std::complex<double>;
  const double dt = history.time_step();
  std::vector<cd> vx(history.modes(), 0.0), vy(history.modes(), 0.0);
  FaceTractions t{std::vector<double>(steps + 1), std::vector<double>(steps + 1)};
  for (int n = 0; n <= steps; ++n) {
    const double v = bump_rate(n * dt, rise);
    const cd ux = component == 0 ? v : 0.0, uy = component == 1 ? v : 0.0;
    const cd hx = n == 0 ? cd(0.0) : history.history_x()[q];
    const cd hy = n == 0 ? cd(0.0) : history.history_y()[q];
    const cd t_x = history.shear_impedance() * ux + hx, t_y = history.normal_impedance() * uy + hy;
    t.x[n] = component == 0 ? t_x.real() : t_x.imag();
    t.y[n] = component == 0 ? t_y.imag() : t_y.real();
    vx[q] = ux;
    vy[q] = uy;
    history.push(vx, vy);
  }
  return t;
}

// Relative L2 errors of the four responses (xx, yx from u_x; xy, yy from u_y)
// against Durbin's inverse of K(k, s) g^(s) (2^18 terms).  make_operator()
// returns a fresh operator, driven at mode q (default 1); stiffness(s) is K(k, s)
// at that mode's k.
struct FaceErrors {
  double xx, yx, xy, yy;
};
template <class MakeOperator, class Stiffness>
FaceErrors prescribed_face_errors(const MakeOperator& make_operator, const Stiffness& stiffness, double dt,
                                  double rise, int steps, std::size_t q = 1) {
  using cd = std::complex<double>;
  const cd i(0.0, 1.0);
  const auto reference = [&](auto entry) {
    return inverse_laplace([&](cd s) { return entry(stiffness(s)) * bump_laplace(s, rise); }, dt, 1 << 18,
                           steps + 1);
  };
  FaceErrors e{};
  auto x_operator = make_operator();
  const FaceTractions tx = drive_face_mode(x_operator, 0, rise, steps, q);
  e.xx = relative_l2_difference(tx.x, reference([](const FaceMatrix& K) { return K.xx; }));
  e.yx = relative_l2_difference(tx.y, reference([&](const FaceMatrix& K) { return K.yx / i; }));
  auto y_operator = make_operator();
  const FaceTractions ty = drive_face_mode(y_operator, 1, rise, steps, q);
  e.xy = relative_l2_difference(ty.x, reference([&](const FaceMatrix& K) { return K.xy / i; }));
  e.yy = relative_l2_difference(ty.y, reference([](const FaceMatrix& K) { return K.yy; }));
  return e;
}

}  // namespace slipstrip::testing
