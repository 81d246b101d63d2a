#pragma once
// Damped exponentials present in a sampled signal (matrix pencil): the growth
// rates measured from simulations and compared with linear stability
// (test_solver_growth_rates, test_solver_interface_2d_bodies).
#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <cstddef>
#include <type_traits>
#include <vector>

namespace slipstrip::testing {

struct Pole {
  std::complex<double> rate;  // Lambda [1/s]
  double initial_amplitude;   // |amplitude| at the window start
  double final_amplitude;     // |amplitude| at the window end
};

// Estimator (b): matrix pencil on samples y[first], y[first+d], ... (< last).
// Model order = number of singular values above rank_tolerance * largest.
// A real signal gives conjugate pairs (one of each is kept); a complex one (a
// Fourier mode's complex amplitude) keeps every pole, so waves travelling in
// opposite directions at the same |frequency| are told apart by the sign.
template <class Scalar>
std::vector<Pole> matrix_pencil(const std::vector<Scalar>& y, double dt, std::size_t first,
                                std::size_t last, std::size_t decimation,
                                double rank_tolerance) {
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  constexpr bool real_signal = std::is_same_v<Scalar, double>;
  std::vector<Scalar> s;
  for (std::size_t n = first; n < last; n += decimation) s.push_back(y[n]);
  const auto m = static_cast<Eigen::Index>(s.size());
  const Eigen::Index p = m / 3;  // pencil parameter, M/3 is the usual noise-robust choice
  Matrix hankel(m - p, p + 1);
  for (Eigen::Index i = 0; i < m - p; ++i)
    for (Eigen::Index j = 0; j <= p; ++j) hankel(i, j) = s[static_cast<std::size_t>(i + j)];
  Eigen::BDCSVD<Matrix> svd(hankel, Eigen::ComputeThinV);
  const auto& sv = svd.singularValues();
  Eigen::Index order = 0;
  while (order < sv.size() && sv(order) > rank_tolerance * sv(0)) ++order;
  // Hankel = U S V^H: the rows of V^H span those of the Vandermonde factor
  // (z_m^j), so V spans its conjugate; real V is its own conjugate.
  const Matrix v = svd.matrixV().leftCols(order).conjugate();
  const Matrix shifted =
      v.topRows(p).completeOrthogonalDecomposition().solve(v.bottomRows(p));
  Eigen::VectorXcd z;
  if constexpr (real_signal)
    z = Eigen::EigenSolver<Matrix>(shifted).eigenvalues();
  else
    z = Eigen::ComplexEigenSolver<Matrix>(shifted).eigenvalues();
  // amplitudes by least squares on the Vandermonde system
  Eigen::MatrixXcd vandermonde(m, order);
  for (Eigen::Index j = 0; j < order; ++j) {
    std::complex<double> power = 1.0;
    for (Eigen::Index i = 0; i < m; ++i) {
      vandermonde(i, j) = power;
      power *= z(j);
    }
  }
  Eigen::VectorXcd samples(m);
  for (Eigen::Index i = 0; i < m; ++i) samples(i) = s[static_cast<std::size_t>(i)];
  const Eigen::VectorXcd amplitude = vandermonde.colPivHouseholderQr().solve(samples);
  const double step = dt * static_cast<double>(decimation);
  std::vector<Pole> poles;
  for (Eigen::Index j = 0; j < order; ++j) {
    if (real_signal && z(j).imag() < 0.0) continue;  // real signal: keep one of each conjugate pair
    poles.push_back({std::log(z(j)) / step, std::abs(amplitude(j)),
                     std::abs(amplitude(j)) * std::pow(std::abs(z(j)), double(m - 1))});
  }
  return poles;
}

}  // namespace slipstrip::testing
