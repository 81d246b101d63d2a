#pragma once
// A 2D interface (Simulation3d, docs/3d.md) split over the processes of an MPI
// communicator:
//   * real space: each process holds a slab of consecutive rows z of every
//     field and solves the friction of its own nodes (node-local);
//   * Fourier space: each process holds whole columns qx of Fourier modes
//     (DistributedRealFft2d's transposed layout), and the in-plane and
//     antiplane history operators of those modes only, built from the designs
//     of their own |k| (InterfaceHistory2d over an InterfaceModeSet); the
//     choice modal / block and the block length B are made from the whole
//     operator's largest normal-mode count, as on one process, and a
//     half-space's near-field fit spans the whole grid's |k|;
//   * dissimilar bodies: the pair operators of those modes (each body's 2x2
//     face operator, the antiplane pair, the normal stress; each half-space
//     body's fit over the whole grid's range of its own c_s |k| dt), the
//     normal stress's and opening stress's transforms distributed as the
//     others; the contact step is node-local;
//   * sums and maxima over the interface (mean slip, mean shear stress,
//     max |v|) by MPI_Allreduce.
// The results equal one process's to round-off (the FFT and the sums add in
// another order).  Every call of Simulation3d that steps or reduces is
// collective: every process makes it.
#include <mpi.h>

#include <span>
#include <vector>

#include "solver/simulation_3d.hpp"

namespace slipstrip {

// The spectral step of a Simulation3d split over `comm` (collective).  For
// Simulation3d(config, initial_state, cancelled, distributed_spectral_step(comm)).
SpectralStepFactory distributed_spectral_step(MPI_Comm comm);

// The whole field on process `root` (rows in order; empty on the others)
// from each process's slab [row][ix] of a field of nodes_x columns.  Collective.
std::vector<double> gather_rows(std::span<const double> local, MPI_Comm comm, int root = 0);

// gather_rows for a field gathered again and again (a run's snapshots): the
// slabs' sizes are exchanged once, at construction, and the whole field is
// written into a buffer the caller holds, so a gather allocates nothing.
class RowGather {
 public:
  // Collective.  local_count: this process's values of one field.
  RowGather(std::size_t local_count, MPI_Comm comm, int root = 0);
  // The values of all processes on `root` (size whole_count() there;
  // ignored elsewhere).  Collective.
  void gather(std::span<const double> local, std::span<double> whole) const;
  std::size_t whole_count() const { return whole_count_; }

 private:
  MPI_Comm comm_;
  int root_ = 0;
  int local_count_ = 0;
  std::size_t whole_count_ = 0;
  std::vector<int> counts_, offsets_;
};

}  // namespace slipstrip
