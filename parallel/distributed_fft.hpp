#pragma once
// The 2D real-to-complex FFT of an interface field split over the processes
// of an MPI communicator (FFTW's MPI interface), plans made once (RAII).
//
// Real space: each process holds a slab of consecutive rows z, [row][ix]
// (x fastest), rows first_row() .. first_row() + rows() - 1.  Fourier space
// (FFTW_MPI_TRANSPOSED_OUT / _IN): each process holds the columns
// qx = first_column() .. first_column() + columns() - 1 of RealFft2d's modes,
// every qz, stored [qx][qz] (interface_mode_columns), so a Fourier mode and
// its history live on one process; the transposes between the two layouts
// are FFTW's (all-to-all messages inside the transforms).  Same
// normalisation as RealFft2d; the sums run in another order, so the results
// equal RealFft2d's to round-off, not bit for bit.
#include <mpi.h>
#include <fftw3-mpi.h>

#include <complex>
#include <cstddef>
#include <span>

#include "kernels/fft.hpp"

namespace slipstrip {

class DistributedRealFft2d {
 public:
  // Collective over `comm`.  Throws std::invalid_argument when some process
  // would hold no row or no column (too many processes for the grid),
  // naming geometry.nodes_z or geometry.nodes: the same message on every process.
  DistributedRealFft2d(int nodes_x, int nodes_z, MPI_Comm comm);
  DistributedRealFft2d(const DistributedRealFft2d&) = delete;
  DistributedRealFft2d& operator=(const DistributedRealFft2d&) = delete;

  int nodes_x() const { return nodes_x_; }
  int nodes_z() const { return nodes_z_; }
  int first_row() const { return static_cast<int>(first_row_); }
  int rows() const { return static_cast<int>(rows_); }
  int first_column() const { return static_cast<int>(first_column_); }
  int columns() const { return static_cast<int>(columns_); }
  std::size_t local_nodes() const { return static_cast<std::size_t>(rows_) * nodes_x_; }
  std::size_t local_modes() const { return static_cast<std::size_t>(columns_) * nodes_z_; }

  // Collective.  Unnormalised forward transform of this process's rows into
  // its columns of modes.
  void forward(std::span<const double> in, std::span<std::complex<double>> out);
  // Collective.  Inverse including the 1/(nodes_x nodes_z) factor.
  void inverse(std::span<const std::complex<double>> in, std::span<double> out);

 private:
  int nodes_x_, nodes_z_;
  ptrdiff_t rows_ = 0, first_row_ = 0, columns_ = 0, first_column_ = 0;
  FftwBuffer<double> real_;  // rows of 2 (nodes_x/2 + 1) doubles (FFTW's padded r2c layout)
  FftwBuffer<fftw_complex> spectral_;
  FftwPlan forward_plan_, inverse_plan_;
};

}  // namespace slipstrip
