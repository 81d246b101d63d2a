#pragma once
// Real-to-complex FFT of the interface fields with plans made once (RAII).
// FFTW's planner is not thread-safe, so plans are created in the constructor
// only; execute() uses the new-array interface and may be called from the
// time loop without allocation.
#include <fftw3.h>

#include <complex>
#include <cstddef>
#include <memory>
#include <span>
#include <type_traits>

namespace slipstrip {

struct FftwFree {
  void operator()(void* p) const { fftw_free(p); }
};
template <class T>
using FftwBuffer = std::unique_ptr<T[], FftwFree>;

template <class T>
FftwBuffer<T> make_fftw_buffer(std::size_t n) {
  auto* p = static_cast<T*>(fftw_malloc(sizeof(T) * (n == 0 ? 1 : n)));
  if (!p) throw std::bad_alloc();
  return FftwBuffer<T>(p);
}

// An FFTW plan that destroys itself (fftw_plan is a pointer to FFTW's opaque
// plan struct).  Empty only after a move.
struct FftwPlanDestroy {
  void operator()(fftw_plan plan) const { fftw_destroy_plan(plan); }
};
using FftwPlan = std::unique_ptr<std::remove_pointer_t<fftw_plan>, FftwPlanDestroy>;

// Takes ownership of a plan just made; throws std::runtime_error "<who>: FFTW
// planning failed" if FFTW returned none.
FftwPlan owned_plan(fftw_plan plan, const char* who);

// A complex DFT plan of length n (sign FFTW_FORWARD or FFTW_BACKWARD,
// unnormalised, FFTW_ESTIMATE) for fftw_execute_dft from one fftw_malloc'd
// buffer of n values into another, distinct one.  Out of place because FFTW's
// in-place complex plans of 2048..32768 points take a work buffer from the heap
// at every execute (measured with FFTW 3.3.10), which the time loop must not;
// the out-of-place ones of every length take none
// (tests/cpp/test_kernels_time_loop_allocation.cpp).  Planned on buffers of its
// own: FFTW_ESTIMATE does not touch them, and any two fftw_malloc'd buffers
// have the alignment the plan was made for.
FftwPlan complex_dft_plan(int n, int sign, const char* who);
// The same for `howmany` transforms of length n interleaved point by point
// (value j of transform c at j howmany + c), in and out.
FftwPlan interleaved_dft_plan(int n, int howmany, int sign, const char* who);
// Two transforms of length n with any strides and distances (FFTW's
// "advanced" layout: value j of transform c at c dist + j stride), in and out.
// At 8192 and 16384 points FFTW_ESTIMATE plans a contiguous transform written
// or read with stride 2 in ~0.45x and ~0.6x the time of the all-contiguous
// one (its contiguous plan of these lengths is the slow one;
// docs/notes/2026-11-27-pair-bin-order.md), which FaceBlockHistory's largest
// levels use.
FftwPlan strided_pair_dft_plan(int n, int in_stride, int in_dist, int out_stride, int out_dist, int sign,
                               const char* who);

class RealFft {
 public:
  explicit RealFft(int nodes);
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;

  int nodes() const { return nodes_; }
  int modes() const { return nodes_ / 2 + 1; }
  // Unnormalised forward transform: out[q] = sum_j in[j] exp(-2 pi i q j / N).
  void forward(std::span<const double> in, std::span<std::complex<double>> out);
  // Inverse including the 1/N factor, so inverse(forward(f)) == f.
  void inverse(std::span<const std::complex<double>> in, std::span<double> out);

 private:
  int nodes_;
  FftwBuffer<double> real_;
  FftwBuffer<fftw_complex> spectral_;
  FftwPlan forward_plan_;
  FftwPlan inverse_plan_;
};

// Real-to-complex FFT of a field on an interface periodic in x and z, stored
// row-major as [iz][ix] (x fastest), with plans made once (as RealFft).  The
// spectrum is [qz][qx], qz = 0..nodes_z-1, qx = 0..nodes_x/2 (FFTW's r2c
// layout): wavenumber 2 pi qx / L_x along x and 2 pi qz' / L_z along z, with
// qz' = qz for qz <= nodes_z/2 and qz - nodes_z above.
class RealFft2d {
 public:
  RealFft2d(int nodes_x, int nodes_z);
  RealFft2d(const RealFft2d&) = delete;
  RealFft2d& operator=(const RealFft2d&) = delete;

  int nodes_x() const { return nodes_x_; }
  int nodes_z() const { return nodes_z_; }
  std::size_t nodes() const { return static_cast<std::size_t>(nodes_x_) * nodes_z_; }
  std::size_t modes() const { return static_cast<std::size_t>(nodes_x_ / 2 + 1) * nodes_z_; }
  // Unnormalised forward transform.
  void forward(std::span<const double> in, std::span<std::complex<double>> out);
  // Inverse including the 1/(nodes_x nodes_z) factor.
  void inverse(std::span<const std::complex<double>> in, std::span<double> out);
  // Two transforms at once (the interface's x and z components), each on an
  // OpenMP thread of its own when there are two or more.  Each runs the same
  // plan as forward() / inverse() on buffers of its own (FFTW's execute is
  // thread-safe for one plan on distinct arrays), so the results are theirs
  // bit for bit whatever the thread count.  Why: the 2D transforms are a third
  // of a 3D step's floor and FFTW_ESTIMATE plans are single-threaded, so
  // without this two threads leave them serial.
  void forward_pair(std::span<const double> in_a, std::span<std::complex<double>> out_a,
                    std::span<const double> in_b, std::span<std::complex<double>> out_b);
  void inverse_pair(std::span<const std::complex<double>> in_a, std::span<double> out_a,
                    std::span<const std::complex<double>> in_b, std::span<double> out_b);

 private:
  void forward_with(int buffers, std::span<const double> in, std::span<std::complex<double>> out);
  void inverse_with(int buffers, std::span<const std::complex<double>> in, std::span<double> out);

  int nodes_x_, nodes_z_;
  // Two sets of transform buffers: set 0 for forward() / inverse() and the
  // first of a pair, set 1 for the second.
  FftwBuffer<double> real_[2];
  FftwBuffer<fftw_complex> spectral_[2];
  FftwPlan forward_plan_;
  FftwPlan inverse_plan_;
};

}  // namespace slipstrip
