#include "parallel/distributed_interface.hpp"

#include <complex>
#include <memory>
#include <numeric>

#include "kernels/block_strip_history.hpp"
#include "parallel/distributed_fft.hpp"

namespace slipstrip {

namespace {

// Half-spaces: the near-field fit over the whole grid's |k| (every process
// computes it from the whole list), as on one process.
HalfSpaceOperatorDesign whole_operator_half_space_design(const SimulationConfig& config, double time_step) {
  HalfSpaceOperatorDesign design;
  std::vector<double> h = interface_operator_wavevectors(interface_grid(config)).magnitude;
  const double cs = config.material.shear_wave_speed();
  for (double& value : h) value = cs * value * time_step;  // the expression HalfSpaceHistory uses
  set_near_field_range(design, h);
  return design;
}

class DistributedSpectralStep final : public InterfaceSpectralStep {
 public:
  DistributedSpectralStep(const SimulationConfig& config, double time_step, const CancelCheck& cancelled,
                          MPI_Comm comm)
      : comm_(comm),
        fft_(config.geometry.nodes, config.geometry.nodes_z, comm),
        history_(InterfaceHistory2d::build(
            config.material, config.geometry.height, interface_grid(config),
            interface_mode_columns(interface_grid(config), fft_.first_column(), fft_.columns()), time_step,
            cancelled,
            [&](const ElasticMaterial& body, const StripKernels& kernels) {
              // The whole operator's largest count of normal modes per Fourier
              // mode (collective: every process builds the in-plane, then the
              // antiplane operator).
              unsigned long long most = most_normal_modes(kernels);
              MPI_Allreduce(MPI_IN_PLACE, &most, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, comm_);
              return make_strip_history(body, kernels, config.time.history, cancelled,
                                        static_cast<std::size_t>(most));
            },
            whole_operator_half_space_design(config, time_step))),
        spectrum_x_(fft_.local_modes()), spectrum_z_(fft_.local_modes()) {}

  InterfaceSlab slab() const override { return {fft_.first_row(), fft_.rows()}; }
  void history(std::span<const double> rate_x, std::span<const double> rate_z, std::span<double> history_x,
               std::span<double> history_z) override {
    transform_push_invert(fft_, history_, spectrum_x_, spectrum_z_, rate_x, rate_z, history_x, history_z);
  }
  const InterfaceHistory2d& history_operator() const override { return history_; }
  InterfaceHistory2d& history_operator() override { return history_; }
  double sum(double local) const override {
    MPI_Allreduce(MPI_IN_PLACE, &local, 1, MPI_DOUBLE, MPI_SUM, comm_);
    return local;
  }
  double max(double local) const override {
    MPI_Allreduce(MPI_IN_PLACE, &local, 1, MPI_DOUBLE, MPI_MAX, comm_);
    return local;
  }

 private:
  MPI_Comm comm_;
  DistributedRealFft2d fft_;
  InterfaceHistory2d history_;
  std::vector<std::complex<double>> spectrum_x_, spectrum_z_;
};

}  // namespace

SpectralStepFactory distributed_spectral_step(MPI_Comm comm) {
  return [comm](const SimulationConfig& config, double time_step, const CancelCheck& cancelled) {
    return std::unique_ptr<InterfaceSpectralStep>(
        std::make_unique<DistributedSpectralStep>(config, time_step, cancelled, comm));
  };
}

std::vector<double> gather_rows(std::span<const double> local, MPI_Comm comm, int root) {
  int rank = 0, size = 0;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int count = static_cast<int>(local.size());
  std::vector<int> counts(rank == root ? size : 0), offsets(counts.size());
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, root, comm);
  std::vector<double> whole;
  if (rank == root) {
    std::exclusive_scan(counts.begin(), counts.end(), offsets.begin(), 0);
    whole.resize(static_cast<std::size_t>(offsets.back()) + counts.back());
  }
  // Processes hold consecutive slabs in rank order (FFTW's distribution).
  MPI_Gatherv(local.data(), count, MPI_DOUBLE, whole.data(), counts.data(), offsets.data(), MPI_DOUBLE, root,
              comm);
  return whole;
}

}  // namespace slipstrip
