#include "parallel/distributed_interface.hpp"

#include <complex>
#include <memory>
#include <numeric>

#include "kernels/block_strip_history.hpp"
#include "parallel/distributed_fft.hpp"

namespace slipstrip {

namespace {

// A half-space body of c_s = `material`'s: the near-field fit over the whole
// grid's h = c_s |k| dt (every process computes it from the whole list), as on
// one process.
HalfSpaceOperatorDesign whole_operator_half_space_design(const SimulationConfig& config,
                                                         const ElasticMaterial& material, double time_step) {
  HalfSpaceOperatorDesign design;
  std::vector<double> h = interface_operator_wavevectors(interface_grid(config)).magnitude;
  const double cs = material.shear_wave_speed();
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
        history_(build_history(config, time_step, cancelled)),
        spectrum_x_(fft_.local_modes()), spectrum_z_(fft_.local_modes()) {
    if (history_.variable_normal_stress()) {
      spectrum_opening_.assign(fft_.local_modes(), 0.0);
      spectrum_normal_.assign(fft_.local_modes(), 0.0);
    }
  }

  InterfaceSlab slab() const override { return {fft_.first_row(), fft_.rows()}; }
  void history(std::span<const double> rate_x, std::span<const double> rate_z, std::span<double> history_x,
               std::span<double> history_z) override {
    transform_push_invert(fft_, history_, spectrum_x_, spectrum_z_, rate_x, rate_z, history_x, history_z);
  }
  bool variable_normal_stress() const override { return history_.variable_normal_stress(); }
  // Collective, as the transforms are: every process passes an opening stress
  // or none alike (Simulation3d decides from its own nodes, so the processes
  // agree on it below).
  void history(std::span<const double> rate_x, std::span<const double> rate_z,
               std::span<const double> opening_stress, std::span<double> history_x, std::span<double> history_z,
               std::span<double> normal_stress) override {
    int any_opening = opening_stress.empty() ? 0 : 1;
    MPI_Allreduce(MPI_IN_PLACE, &any_opening, 1, MPI_INT, MPI_LOR, comm_);
    // A process whose own nodes carry no opening stress transforms zeros
    // when another process's do (its part of the whole field).
    if (any_opening && opening_stress.empty()) opening_stress = zero_opening_;
    transform_push_invert(fft_, history_, spectrum_x_, spectrum_z_, spectrum_opening_, spectrum_normal_, rate_x,
                          rate_z, any_opening ? opening_stress : std::span<const double>(), history_x, history_z,
                          normal_stress);
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
  // This process's modes' operators, each choice made as on one process.
  InterfaceHistory2d build_history(const SimulationConfig& config, double time_step, const CancelCheck& cancelled) {
    const InterfaceGrid2d grid = interface_grid(config);
    const InterfaceModeSet modes = interface_mode_columns(grid, fft_.first_column(), fft_.columns());
    // The whole operator's largest count of normal modes per Fourier mode
    // decides modal / block and B (collective: every process builds the
    // strip operators in the same order).
    const auto strip_operator = [&](const ElasticMaterial& body, const StripKernels& kernels) {
      unsigned long long most = most_normal_modes(kernels);
      MPI_Allreduce(MPI_IN_PLACE, &most, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, comm_);
      return make_strip_history(body, kernels, config.time.history, cancelled, static_cast<std::size_t>(most));
    };
    if (config.bottom.body == BodyKind::mirror)
      return InterfaceHistory2d::build(config.material, config.geometry.height, grid, modes, time_step, cancelled,
                                       strip_operator,
                                       whole_operator_half_space_design(config, config.material, time_step));
    // Dissimilar bodies: each half-space body's near-field fit over the whole
    // grid's range of its own h (its own c_s); the passivity correction is per
    // |k|, so a process's modes get the one-process corrections.
    InterfaceHistory2d::PairPart part;
    part.top_half_space = whole_operator_half_space_design(config, config.material, time_step);
    if (config.bottom.body == BodyKind::elastic)
      part.bottom_half_space = whole_operator_half_space_design(config, bottom_material(config), time_step);
    part.any_process = [this](bool flag) {
      int any = flag ? 1 : 0;
      MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_LOR, comm_);
      return any != 0;
    };
    zero_opening_.assign(fft_.local_nodes(), 0.0);
    return interface_pair_history(config, time_step, cancelled, modes, strip_operator, part);
  }

  MPI_Comm comm_;
  DistributedRealFft2d fft_;
  std::vector<double> zero_opening_;  // dissimilar bodies: a slab of zeros (see history())
  InterfaceHistory2d history_;
  std::vector<std::complex<double>> spectrum_x_, spectrum_z_, spectrum_opening_, spectrum_normal_;
};

}  // namespace

SpectralStepFactory distributed_spectral_step(MPI_Comm comm) {
  return [comm](const SimulationConfig& config, double time_step, const CancelCheck& cancelled) {
    return std::unique_ptr<InterfaceSpectralStep>(
        std::make_unique<DistributedSpectralStep>(config, time_step, cancelled, comm));
  };
}

RowGather::RowGather(std::size_t local_count, MPI_Comm comm, int root)
    : comm_(comm), root_(root), local_count_(static_cast<int>(local_count)) {
  int rank = 0, size = 0;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  counts_.assign(rank == root ? size : 0, 0);
  offsets_.assign(counts_.size(), 0);
  MPI_Gather(&local_count_, 1, MPI_INT, counts_.data(), 1, MPI_INT, root, comm);
  if (rank == root) {
    std::exclusive_scan(counts_.begin(), counts_.end(), offsets_.begin(), 0);
    whole_count_ = static_cast<std::size_t>(offsets_.back()) + counts_.back();
  }
}

void RowGather::gather(std::span<const double> local, std::span<double> whole) const {
  // Processes hold consecutive slabs in rank order (FFTW's distribution).
  MPI_Gatherv(local.data(), local_count_, MPI_DOUBLE, whole.data(), counts_.data(), offsets_.data(), MPI_DOUBLE,
              root_, comm_);
}

std::vector<double> gather_rows(std::span<const double> local, MPI_Comm comm, int root) {
  const RowGather gather(local.size(), comm, root);
  std::vector<double> whole(gather.whole_count());
  gather.gather(local, whole);
  return whole;
}

}  // namespace slipstrip
