#include "parallel/distributed_fft.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace slipstrip {

DistributedRealFft2d::DistributedRealFft2d(int nodes_x, int nodes_z, MPI_Comm comm)
    : nodes_x_(nodes_x), nodes_z_(nodes_z) {
  if (nodes_x < 2 || nodes_z < 2)
    throw std::invalid_argument("DistributedRealFft2d: nodes_x = " + std::to_string(nodes_x) +
                                ", nodes_z = " + std::to_string(nodes_z) + " must both be >= 2");
  // r2c: the sizes are those of the complex array, nodes_z x (nodes_x/2 + 1).
  const ptrdiff_t half_x = nodes_x / 2 + 1;
  const ptrdiff_t complex_count = fftw_mpi_local_size_2d_transposed(
      nodes_z, half_x, comm, &rows_, &first_row_, &columns_, &first_column_);
  // Every process must hold rows and columns; all of them decide alike.
  int empty[2] = {rows_ == 0, columns_ == 0};
  MPI_Allreduce(MPI_IN_PLACE, empty, 2, MPI_INT, MPI_LOR, comm);
  int processes = 0;
  MPI_Comm_size(comm, &processes);
  if (empty[0])
    throw std::invalid_argument("geometry.nodes_z = " + std::to_string(nodes_z) + " leaves some of the " +
                                std::to_string(processes) +
                                " MPI processes without a row z: use fewer processes or more rows");
  if (empty[1])
    throw std::invalid_argument("geometry.nodes = " + std::to_string(nodes_x) + " (" + std::to_string(half_x) +
                                " Fourier columns) leaves some of the " + std::to_string(processes) +
                                " MPI processes without a column of modes: use fewer processes or more nodes");
  real_ = make_fftw_buffer<double>(2 * static_cast<std::size_t>(complex_count));
  spectral_ = make_fftw_buffer<fftw_complex>(static_cast<std::size_t>(complex_count));
  // FFTW_ESTIMATE for reproducible plans (kernels/fft.cpp).
  forward_plan_ = owned_plan(fftw_mpi_plan_dft_r2c_2d(nodes_z, nodes_x, real_.get(), spectral_.get(), comm,
                                                      FFTW_ESTIMATE | FFTW_MPI_TRANSPOSED_OUT),
                             "DistributedRealFft2d");
  inverse_plan_ = owned_plan(fftw_mpi_plan_dft_c2r_2d(nodes_z, nodes_x, spectral_.get(), real_.get(), comm,
                                                      FFTW_ESTIMATE | FFTW_MPI_TRANSPOSED_IN),
                             "DistributedRealFft2d");
}

void DistributedRealFft2d::forward(std::span<const double> in, std::span<std::complex<double>> out) {
  const std::size_t padded = 2 * static_cast<std::size_t>(nodes_x_ / 2 + 1);
  for (ptrdiff_t r = 0; r < rows_; ++r)
    std::copy_n(in.begin() + r * nodes_x_, nodes_x_, real_.get() + r * padded);
  fftw_execute(forward_plan_.get());
  const auto* s = reinterpret_cast<const std::complex<double>*>(spectral_.get());
  std::copy(s, s + local_modes(), out.begin());
}

void DistributedRealFft2d::inverse(std::span<const std::complex<double>> in, std::span<double> out) {
  // c2r destroys its input: transform a copy in our own buffer.
  std::copy_n(in.begin(), local_modes(), reinterpret_cast<std::complex<double>*>(spectral_.get()));
  fftw_execute(inverse_plan_.get());
  const std::size_t padded = 2 * static_cast<std::size_t>(nodes_x_ / 2 + 1);
  const double scale = 1.0 / (static_cast<double>(nodes_x_) * nodes_z_);
  for (ptrdiff_t r = 0; r < rows_; ++r)
    for (int ix = 0; ix < nodes_x_; ++ix) out[r * nodes_x_ + ix] = real_[r * padded + ix] * scale;
}

}  // namespace slipstrip
