#include "parallel/distributed_run.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <span>
#include <sstream>
#include <vector>

#include "config/config.hpp"
#include "io/output_paths.hpp"
#include "parallel/distributed_interface.hpp"
#include "parallel/mpi_session.hpp"
#include "solver/checkpoint.hpp"
#include "solver/run_output.hpp"
#include "solver/simulation_3d.hpp"
#include "solver/slip_sampler.hpp"
#include "solver/stations.hpp"
#include "slipstrip/version.hpp"

namespace slipstrip {

static_assert(sizeof(hsize_t) == sizeof(unsigned long long), "crossings are sent as MPI_UNSIGNED_LONG_LONG");

void check_distributed_run(const SimulationConfig& config) {
  const auto refuse = [](const std::string& what) {
    throw CollectiveError(what + " (slipstrip-mpi run; docs/3d.md, \"Across machines\")", 0);
  };
  if (config.geometry.nodes_z < 2)
    refuse("geometry.nodes_z = " + std::to_string(config.geometry.nodes_z) +
           ": a run split over processes is a 2D interface only (nodes_z > 1); a line runs with `slipstrip run`");
}

namespace {

// `text` of process `root` on every process.  Collective.
std::string broadcast_string(std::string text, int root, MPI_Comm comm) {
  unsigned long long size = text.size();
  MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, root, comm);
  text.resize(size);
  MPI_Bcast(text.data(), static_cast<int>(size), MPI_CHAR, root, comm);
  return text;
}

// A refusal found on rank 0 (`refusal` non-empty there) thrown on every
// process.  Collective.
void throw_if_refused(const std::string& refusal, MPI_Comm comm) {
  const std::string text = broadcast_string(refusal, 0, comm);
  if (!text.empty()) throw CollectiveError(text, 0);
}


// Arrays of a restart point are sent in pieces of at most this many values
// (MPI counts are ints).
constexpr std::size_t kMessageValues = std::size_t{1} << 26;

void send_values(std::span<const double> values, int destination, MPI_Comm comm) {
  for (std::size_t begin = 0; begin < values.size(); begin += kMessageValues) {
    const std::size_t count = std::min(kMessageValues, values.size() - begin);
    MPI_Send(values.data() + begin, static_cast<int>(count), MPI_DOUBLE, destination, 0, comm);
  }
}

void receive_values(std::span<double> values, int source, MPI_Comm comm) {
  for (std::size_t begin = 0; begin < values.size(); begin += kMessageValues) {
    const std::size_t count = std::min(kMessageValues, values.size() - begin);
    MPI_Recv(values.data() + begin, static_cast<int>(count), MPI_DOUBLE, source, 0, comm, MPI_STATUS_IGNORE);
  }
}

// A history operator state from one process to another: its kind, counters
// and array names and sizes as text (names hold no line breaks), then each
// array's values.
void send_state(const HistoryOperatorState& state, int destination, MPI_Comm comm) {
  std::ostringstream header;
  header << state.kind << '\n' << state.counters.size() << ' ' << state.arrays.size() << '\n';
  for (const auto& [name, value] : state.counters) header << value << ' ' << name << '\n';
  for (const auto& [name, values] : state.arrays) header << values.size() << ' ' << name << '\n';
  const std::string text = header.str();
  const unsigned long long size = text.size();
  MPI_Send(&size, 1, MPI_UNSIGNED_LONG_LONG, destination, 0, comm);
  MPI_Send(text.data(), static_cast<int>(size), MPI_CHAR, destination, 0, comm);
  for (const auto& [name, values] : state.arrays) send_values(values, destination, comm);
}

HistoryOperatorState receive_state(int source, MPI_Comm comm) {
  unsigned long long size = 0;
  MPI_Recv(&size, 1, MPI_UNSIGNED_LONG_LONG, source, 0, comm, MPI_STATUS_IGNORE);
  std::string text(size, '\0');
  MPI_Recv(text.data(), static_cast<int>(size), MPI_CHAR, source, 0, comm, MPI_STATUS_IGNORE);
  std::istringstream header(text);
  HistoryOperatorState state;
  std::getline(header, state.kind);
  std::size_t counters = 0, arrays = 0;
  header >> counters >> arrays;
  const auto name_after_number = [&] {
    std::string name;
    header.get();  // the space
    std::getline(header, name);
    return name;
  };
  for (std::size_t c = 0; c < counters; ++c) {
    long long value = 0;
    header >> value;
    state.counters.emplace_back(name_after_number(), value);
  }
  for (std::size_t a = 0; a < arrays; ++a) {
    std::size_t count = 0;
    header >> count;
    state.arrays.emplace_back(name_after_number(), std::vector<double>(count));
  }
  for (auto& [name, values] : state.arrays) receive_values(values, source, comm);
  return state;
}

// Process r's part of a field of the whole interface held on rank 0 (`whole`,
// rows in order; ignored elsewhere), `local_count` values on each process:
// the inverse of gather_rows.  Collective.
template <class T>
std::vector<T> scatter_rows(std::span<const T> whole, std::size_t local_count, MPI_Datatype type, MPI_Comm comm) {
  const int rank = mpi_rank(comm);
  const int count = static_cast<int>(local_count);
  std::vector<int> counts(rank == 0 ? mpi_size(comm) : 0), offsets(counts.size());
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  if (rank == 0) std::exclusive_scan(counts.begin(), counts.end(), offsets.begin(), 0);
  std::vector<T> local(local_count);
  MPI_Scatterv(whole.data(), counts.data(), offsets.data(), type, local.data(), count, type, 0, comm);
  return local;
}

// The fields of a 2D interface's state (SimulationState) that a restart
// point of a run split over processes holds for the whole interface,
// gathered on rank 0 and scattered back by rows; the last four with dissimilar
// bodies only (a varying normal stress).
struct StateField {
  const char* name;
  std::vector<double> SimulationState::*field;
  bool normal_stress_only;
};
constexpr StateField kStateFields[] = {{"slip", &SimulationState::slip, false},
                                       {"slip_rate", &SimulationState::slip_rate, false},
                                       {"state", &SimulationState::state, false},
                                       {"shear_stress", &SimulationState::shear_stress, false},
                                       {"slip_z", &SimulationState::slip_z, false},
                                       {"slip_rate_z", &SimulationState::slip_rate_z, false},
                                       {"shear_stress_z", &SimulationState::shear_stress_z, false},
                                       {"speed", &SimulationState::speed, false},
                                       {"normal_stress", &SimulationState::normal_stress, true},
                                       {"effective_normal_stress", &SimulationState::effective_normal_stress, true},
                                       {"gap", &SimulationState::gap, true},
                                       {"opening_stress", &SimulationState::opening_stress, true}};

std::string rank_prefix(int rank) { return "rank" + std::to_string(rank) + "."; }

// What each process passes to rank 0 in a step: coordinates (for the slip
// sampling (level, node) pairs, for the rupture front nodes) and values,
// concatenated in rank order.  The buffers are kept between steps, so a step
// allocates only when more crossings than ever before arrive.
class RecordGather {
 public:
  RecordGather(MPI_Comm comm) : comm_(comm), rank_(mpi_rank(comm)), size_(mpi_size(comm)) {
    if (rank_ == 0) {
      counts_.resize(size_);
      offsets_.resize(size_);
    }
  }
  // Collective.  coordinates_per_value coordinates per value (2: crossings; 1: front nodes).
  void gather(std::span<const hsize_t> coordinates, std::span<const double> values, int coordinates_per_value) {
    const int count = static_cast<int>(values.size());
    MPI_Gather(&count, 1, MPI_INT, counts_.data(), 1, MPI_INT, 0, comm_);
    if (rank_ == 0) {
      std::exclusive_scan(counts_.begin(), counts_.end(), offsets_.begin(), 0);
      values_.resize(static_cast<std::size_t>(offsets_.back()) + counts_.back());
    }
    MPI_Gatherv(values.data(), count, MPI_DOUBLE, values_.data(), counts_.data(), offsets_.data(), MPI_DOUBLE, 0,
                comm_);
    if (rank_ == 0) {
      for (int r = 0; r < size_; ++r) {
        counts_[r] *= coordinates_per_value;
        offsets_[r] *= coordinates_per_value;
      }
      coordinates_.resize(values_.size() * static_cast<std::size_t>(coordinates_per_value));
    }
    MPI_Gatherv(coordinates.data(), count * coordinates_per_value, MPI_UNSIGNED_LONG_LONG, coordinates_.data(),
                counts_.data(), offsets_.data(), MPI_UNSIGNED_LONG_LONG, 0, comm_);
  }
  // On rank 0 after gather().
  std::span<const hsize_t> coordinates() const { return coordinates_; }
  std::span<const double> values() const { return values_; }

 private:
  MPI_Comm comm_;
  int rank_, size_;
  std::vector<int> counts_, offsets_;
  std::vector<hsize_t> coordinates_;
  std::vector<double> values_;
};

// The stations of a run split over processes by rows: each process takes
// the row terms (StationSampler2d) of the rows it holds, of every field;
// rank 0 gathers them and combines each station's two, so a station between
// two rows held by two processes (or between the last row and row 0) is
// taken as one process takes it, bit for bit.  The moment rate's sum of
// v_x is taken in the order of one process: rank 0 sums its rows and passes
// the partial sum to rank 1, which adds its own, and so on (one message per
// process and station row), the last process sending the total to rank 0.
// Every buffer is sized at construction: a station row allocates nothing.
class DistributedStations {
 public:
  // Collective.
  DistributedStations(const SimulationConfig& config, const Simulation3d& sim, MPI_Comm comm)
      : comm_(comm), rank_(mpi_rank(comm)), size_(mpi_size(comm)),
        sampler_(config.output.stations, config.output.stations_z, sim.dx(), sim.dz(),
                 static_cast<std::size_t>(sim.nodes_x()), static_cast<std::size_t>(sim.nodes_z())),
        first_row_(static_cast<std::size_t>(sim.slab().first_row)), fields_(interface_2d_fields(sim).size()),
        mu_dxdz_(config.material.shear_modulus * sim.dx() * sim.dz()) {
    const std::size_t rows = static_cast<std::size_t>(sim.slab().rows);
    std::vector<int> own;  // this process's row terms, in increasing order
    for (std::size_t t = 0; t < sampler_.terms(); ++t)
      if (sampler_.term_row(t) >= first_row_ && sampler_.term_row(t) < first_row_ + rows)
        own.push_back(static_cast<int>(t));
    own_terms_.assign(own.begin(), own.end());
    local_.resize(fields_ * own_terms_.size());
    // Rank 0: where each (field, term) lands in the gathered values.
    const int own_count = static_cast<int>(own.size());
    std::vector<int> term_counts(rank_ == 0 ? size_ : 0), term_offsets(term_counts.size());
    MPI_Gather(&own_count, 1, MPI_INT, term_counts.data(), 1, MPI_INT, 0, comm_);
    if (rank_ == 0) std::exclusive_scan(term_counts.begin(), term_counts.end(), term_offsets.begin(), 0);
    std::vector<int> all_terms(rank_ == 0 ? sampler_.terms() : 0);
    MPI_Gatherv(own.data(), own_count, MPI_INT, all_terms.data(), term_counts.data(), term_offsets.data(), MPI_INT,
                0, comm_);
    if (rank_ == 0) {
      counts_.resize(size_);
      offsets_.resize(size_);
      position_.resize(fields_ * sampler_.terms());
      int offset = 0;
      for (int r = 0; r < size_; ++r) {
        counts_[r] = term_counts[r] * static_cast<int>(fields_);
        offsets_[r] = offset;
        for (int k = 0; k < term_counts[r]; ++k) {
          const std::size_t term = static_cast<std::size_t>(all_terms[term_offsets[r] + k]);
          for (std::size_t f = 0; f < fields_; ++f)
            position_[f * sampler_.terms() + term] = static_cast<std::size_t>(offset) + f * term_counts[r] + k;
        }
        offset += counts_[r];
      }
      gathered_.resize(fields_ * sampler_.terms());
      values_.resize(fields_ * sampler_.size());
    }
  }

  // One station row of the current state, appended by rank 0 (`output`,
  // null elsewhere).  Collective.
  void record(const Simulation3d& sim, RunOutput* output) {
    const Interface2dFields fields = interface_2d_fields(sim);
    const std::size_t own = own_terms_.size();
    for (std::size_t f = 0; f < fields_; ++f)
      for (std::size_t k = 0; k < own; ++k)
        local_[f * own + k] = sampler_.row_term(fields[f], first_row_, own_terms_[k]);
    MPI_Gatherv(local_.data(), static_cast<int>(local_.size()), MPI_DOUBLE, gathered_.data(), counts_.data(),
                offsets_.data(), MPI_DOUBLE, 0, comm_);
    const double max_slip_rate = sim.max_slip_rate();  // collective
    double sum_rate = 0.0;
    if (rank_ > 0) MPI_Recv(&sum_rate, 1, MPI_DOUBLE, rank_ - 1, kSumTag, comm_, MPI_STATUS_IGNORE);
    for (double v : sim.slip_rate_x()) sum_rate += v;
    if (size_ > 1) {
      if (rank_ + 1 < size_) MPI_Send(&sum_rate, 1, MPI_DOUBLE, rank_ + 1, kSumTag, comm_);
      else MPI_Send(&sum_rate, 1, MPI_DOUBLE, 0, kSumTag, comm_);
      if (rank_ == 0) MPI_Recv(&sum_rate, 1, MPI_DOUBLE, size_ - 1, kSumTag, comm_, MPI_STATUS_IGNORE);
    }
    if (rank_ != 0) return;
    const std::size_t stations = sampler_.size(), terms = sampler_.terms();
    std::array<std::span<const double>, 9> at_stations;
    for (std::size_t f = 0; f < fields_; ++f) {
      const std::size_t* at = position_.data() + f * terms;
      for (std::size_t s = 0; s < stations; ++s)
        values_[f * stations + s] = sampler_.combine(s, gathered_[at[2 * s]], gathered_[at[2 * s + 1]]);
      at_stations[f] = std::span<const double>(values_).subspan(f * stations, stations);
    }
    output->append_stations(sim.time(), std::span<const std::span<const double>>(at_stations.data(), fields_),
                            max_slip_rate, mu_dxdz_ * sum_rate);
  }

 private:
  static constexpr int kSumTag = 1;  // the moment rate's partial sums
  MPI_Comm comm_;
  int rank_, size_;
  StationSampler2d sampler_;
  std::size_t first_row_, fields_;
  double mu_dxdz_;
  std::vector<std::size_t> own_terms_;
  std::vector<double> local_;     // fields x own terms, field-major
  std::vector<int> counts_, offsets_;  // rank 0: of the gather
  std::vector<std::size_t> position_;  // rank 0: fields x terms -> index in gathered_
  std::vector<double> gathered_;       // rank 0: every process's local_, in rank order
  std::vector<double> values_;         // rank 0: fields x stations, field-major
};

// The per-step control reduction (MPI_MAX over the processes): whether some
// process diverged, rank 0's stop request, rank 0's decision to write a
// restart point (its wall-clock timer), whether some process has level
// crossings or front arrivals to pass, and the largest |v| (for the progress).
constexpr std::size_t kDiverged = 0, kStop = 1, kRestartPoint = 2, kCrossings = 3, kFront = 4, kMaxSpeed = 5,
                      kControlSize = 6;

// The time loop of a new run (resuming = false) or of a resumed one (the
// restart point `resume_from` on rank 0, already checked against the run
// file; null on the other processes).  Collective.
RunResult drive(const SimulationConfig& config, const std::string& output_path, const RunHooks& hooks,
                MPI_Comm comm, bool resuming, const RunCheckpoint* resume_from) {
  using clock = std::chrono::steady_clock;
  const int rank = mpi_rank(comm), processes = mpi_size(comm);

  // The set-up is collective (the distributed operator's choices are made
  // over all processes), so it is not cancelled half-way on one process: a
  // stop requested on rank 0 during it is honoured right after, before the
  // file exists.  A friction solve that fails at t = 0 on some process is an
  // input error there (as run_simulation's).
  // A refusal met inside the set-up (e.g. a time step too long for a
  // half-space's operator) is not agreed on collectively: a process may meet
  // it while the others wait in one of the set-up's collectives, so it ends
  // the job through MPI_Abort (every process that met it prints it).
  const auto sim_owner = [&] {
    try {
      return std::make_unique<Simulation3d>(config, std::span<const double>(), CancelCheck{},
                                            distributed_spectral_step(comm));
    } catch (const SimulationError& e) {
      throw std::invalid_argument(
          std::string("the initial state (t = 0) cannot be solved for this combination of "
                      "[friction], [loading] and [initial] values: ") + e.what());
    }
  }();
  Simulation3d& sim = *sim_owner;
  int stop_in_setup = rank == 0 && hooks.stop_requested && hooks.stop_requested() ? 1 : 0;
  MPI_Bcast(&stop_in_setup, 1, MPI_INT, 0, comm);
  if (stop_in_setup) throw SetupCancelled("set-up cancelled (the stop was seen when the set-up ended)");

  const double step_count = std::ceil(config.time.duration / sim.time_step() - 0.5);
  if (!(step_count < 0.5 * static_cast<double>(std::numeric_limits<long long>::max())))
    throw CollectiveError("time.duration = " + std::to_string(config.time.duration) + " s is " +
                              std::to_string(step_count) + " time steps of dt = " + std::to_string(sim.time_step()) +
                              " s: the step count does not fit a 64-bit integer",
                          0);
  const long long total_steps = static_cast<long long>(step_count);
  const auto& out_cfg = config.output;
  const std::size_t first_node = static_cast<std::size_t>(sim.nodes_x()) * sim.slab().first_row;
  const std::size_t nodes = sim.nodes();  // this process's
  const std::size_t all_nodes = static_cast<std::size_t>(sim.nodes_x()) * static_cast<std::size_t>(sim.nodes_z());
  const std::string restart_path = checkpoint_path(output_path);

  // A resumed run: rank 0 checks the restart point against this run's time
  // step and step count, then each process receives its rows of the fields
  // and its own history operator state, and restores them.
  if (resuming) {
    std::string refusal;
    if (rank == 0) {
      try {
        validate_checkpoint(*resume_from, config, sim.time_step(), total_steps, output_path);
        for (const auto& f : kStateFields) {
          const std::size_t size = (resume_from->simulation.*f.field).size();
          const std::size_t expected = !f.normal_stress_only || sim.variable_normal_stress() ? all_nodes : 0;
          if (size != expected)
            throw std::invalid_argument("restart point '" + restart_path + "': simulation/" + f.name + " has " +
                                        std::to_string(size) + " values, expected " + std::to_string(expected) +
                                        (expected ? " (the interface's nodes)" : " (identical bodies)") +
                                        "; it cannot be resumed");
        }
      } catch (const std::invalid_argument& e) {
        refusal = e.what();
      }
      if (refusal.empty() && !resume_from->checksum_verified && hooks.warning)
        hooks.warning("restart point '" + restart_path +
                      "' has no checksum: its fields are checked, but damage to its data cannot be found");
    }
    throw_if_refused(refusal, comm);
    SimulationState local;
    double time = rank == 0 ? resume_from->simulation.time : 0.0;
    long long step = rank == 0 ? resume_from->simulation.step_index : 0;
    MPI_Bcast(&time, 1, MPI_DOUBLE, 0, comm);
    MPI_Bcast(&step, 1, MPI_LONG_LONG, 0, comm);
    local.time = time;
    local.step_index = step;
    for (const auto& f : kStateFields)
      if (!f.normal_stress_only || sim.variable_normal_stress())
        local.*f.field = scatter_rows<double>(
            rank == 0 ? std::span<const double>(resume_from->simulation.*f.field) : std::span<const double>(), nodes,
            MPI_DOUBLE, comm);
    // The history state: the whole operator's (the one-process layout, as
    // `slipstrip run` writes it), cut on rank 0 into each process's modes
    // after the layouts of every process's operator arrive (their per-mode
    // sizes place each mode in the whole arrays); or, from an earlier
    // version's restart point, each process's own state (kSplitHistoryKind,
    // written on as many processes: checked by resume_distributed).
    int per_process = rank == 0 && resume_from->simulation.history.kind == kSplitHistoryKind ? 1 : 0;
    MPI_Bcast(&per_process, 1, MPI_INT, 0, comm);
    if (per_process) {
      if (rank == 0) {
        const auto& split = resume_from->simulation.history;
        for (int r = 1; r < processes; ++r) send_state(split.part(rank_prefix(r), ""), r, comm);
        local.history = split.part(rank_prefix(0), "");
      } else {
        local.history = receive_state(0, comm);
      }
    } else {
      const HistoryOperatorState layout = sim.history_operator().save_mode_records(/*with_values=*/false);
      std::vector<HistoryOperatorState> parts;
      std::string split_refusal;
      if (rank == 0) {
        std::vector<HistoryOperatorState> layouts{layout};
        for (int r = 1; r < processes; ++r) layouts.push_back(receive_state(r, comm));
        try {
          parts = InterfaceHistory2d::split_state(resume_from->simulation.history, layouts);
        } catch (const std::invalid_argument& e) {
          split_refusal = "restart point '" + restart_path + "' cannot be resumed: " + e.what();
        }
      } else {
        send_state(layout, 0, comm);
      }
      throw_if_refused(split_refusal, comm);
      if (rank == 0) {
        for (int r = 1; r < processes; ++r) send_state(parts[r], r, comm);
        local.history = std::move(parts[0]);
      } else {
        local.history = receive_state(0, comm);
      }
    }
    // A per-process part gets the kind of this process's operator
    // (InterfaceHistory2d), whose restore_state checks every array by name and
    // size, and its slab is checked, so that a restart point of another split
    // is named as such; mode records are checked against this process's modes
    // (Simulation3d::restore_state).
    std::string error;
    try {
      if (per_process) {
        local.history.kind = sim.history_operator().save_state().kind;
        const long long first_row = local.history.counter("first_row"), rows = local.history.counter("rows");
        if (first_row != sim.slab().first_row || rows != sim.slab().rows)
          throw std::invalid_argument("process " + std::to_string(rank) + " held rows " + std::to_string(first_row) +
                                      ".." + std::to_string(first_row + rows - 1) + ", here rows " +
                                      std::to_string(sim.slab().first_row) + ".." +
                                      std::to_string(sim.slab().first_row + sim.slab().rows - 1));
      }
      sim.restore_state(local);
    } catch (const std::invalid_argument& e) {
      error = e.what();
    }
    throw_if_any_failed(error, "restart point '" + restart_path + "' cannot be resumed: ", comm);
  }

  // Rank 0 writes the file with run_simulation's writer and records.
  std::unique_ptr<RunOutput> output;
  std::vector<double> front_arrival;  // rank 0: the whole interface's
  if (rank == 0) {
    RunOutputOptions options = interface_2d_output_options(config, sim.variable_normal_stress());
    options.processes = processes;
    if (!resuming) {
      output = std::make_unique<RunOutput>(output_path, to_toml(config), interface_2d_sampling(config), options);
      if (out_cfg.front_slip_rate > 0.0) front_arrival.assign(all_nodes, std::numeric_limits<double>::quiet_NaN());
    }
  }
  // A resumed run cuts every record of the file back to the restart point
  // (as resume_simulation's); a file that does not fit it is refused.
  if (resuming) {
    std::string refusal;
    if (rank == 0) {
      try {
        RunOutputOptions options = interface_2d_output_options(config, sim.variable_normal_stress());
        options.processes = processes;
        output = std::make_unique<RunOutput>(output_path, resume_from->output, interface_2d_sampling(config),
                                             options);
        front_arrival = resume_from->output.rupture_front;  // sizes checked by RunOutput
      } catch (const std::invalid_argument& e) {
        refusal = e.what();
      }
    }
    throw_if_refused(refusal, comm);
  }

  // Each process dates the level crossings and the front arrivals of its own
  // nodes, numbered as the whole interface's.
  std::optional<SlipSampler> sampler;
  if (out_cfg.delta_th > 0.0) sampler.emplace(out_cfg.delta_th, nodes);
  std::vector<hsize_t> crossing_coordinates;
  std::vector<bool> front_reached(out_cfg.front_slip_rate > 0.0 ? nodes : 0, false);
  if (resuming && sampler) {
    // This process's nodes of the restart point's slip-sampling progress.
    int started = rank == 0 && resume_from->output.slip_recorded ? 1 : 0;
    MPI_Bcast(&started, 1, MPI_INT, 0, comm);
    static_assert(sizeof(std::uint64_t) == sizeof(unsigned long long), "levels are sent as MPI_UNSIGNED_LONG_LONG");
    const auto levels = scatter_rows<std::uint64_t>(
        rank == 0 ? std::span<const std::uint64_t>(resume_from->output.levels_reached)
                  : std::span<const std::uint64_t>(),
        nodes, MPI_UNSIGNED_LONG_LONG, comm);
    const auto thresholds = scatter_rows<double>(
        rank == 0 ? std::span<const double>(resume_from->output.next_threshold) : std::span<const double>(), nodes,
        MPI_DOUBLE, comm);
    const std::uint64_t highest = levels.empty() ? 0 : *std::max_element(levels.begin(), levels.end());
    sampler->restore(static_cast<std::size_t>(highest), started != 0, levels, thresholds);
  }
  if (resuming && !front_reached.empty()) {
    const auto arrival = scatter_rows<double>(
        rank == 0 ? std::span<const double>(front_arrival) : std::span<const double>(), nodes, MPI_DOUBLE, comm);
    for (std::size_t i = 0; i < nodes; ++i) front_reached[i] = !std::isnan(arrival[i]);
  }
  std::vector<hsize_t> front_nodes;
  std::vector<double> front_times;
  const auto find_front = [&] {
    front_nodes.clear();
    front_times.clear();
    const auto v = sim.speed();
    for (std::size_t i = 0; i < front_reached.size(); ++i)
      if (!front_reached[i] && std::abs(v[i]) > out_cfg.front_slip_rate) {
        front_reached[i] = true;
        front_nodes.push_back(first_node + i);
        front_times.push_back(sim.time());
      }
  };
  RecordGather gathered(comm);
  std::optional<DistributedStations> stations;
  if (!out_cfg.stations.empty()) stations.emplace(config, sim, comm);
  const auto pass_crossings = [&] {
    const auto local = sampler->pending_coordinates();
    crossing_coordinates.assign(local.begin(), local.end());
    for (std::size_t c = 1; c < crossing_coordinates.size(); c += 2) crossing_coordinates[c] += first_node;
    gathered.gather(crossing_coordinates, sampler->pending_times(), 2);
    sampler->clear_pending();
    if (rank == 0) output->record_crossings(gathered.coordinates(), gathered.values());
  };
  const auto pass_front = [&] {
    gathered.gather(front_nodes, front_times, 1);
    if (rank != 0) return;
    const auto where = gathered.coordinates();
    const auto when = gathered.values();
    for (std::size_t c = 0; c < when.size(); ++c) front_arrival[where[c]] = when[c];
    output->set_rupture_front(front_arrival);
  };
  // Collective: the time series' reductions, in this order on every process.
  const auto append_timeseries = [&] {
    const double max_rate = sim.max_slip_rate();
    const double mean_slip = sim.mean_slip_x();
    const double mean_stress = sim.mean_shear_stress_x();
    if (rank == 0) output->append_timeseries(sim.time(), max_rate, mean_slip, mean_stress);
  };
  // Collective: every field gathered on rank 0, in the file's order, into
  // buffers held for the whole run (a snapshot allocates nothing).
  const Interface2dFields snapshot_fields = interface_2d_fields(sim);
  const RowGather field_gather(snapshot_fields[0].size(), comm);
  std::vector<double> snapshot_buffer(field_gather.whole_count() * snapshot_fields.size());
  const auto write_snapshot = [&] {
    const Interface2dFields local = interface_2d_fields(sim);
    std::array<std::span<const double>, 9> spans;
    for (std::size_t f = 0; f < local.size(); ++f) {
      const std::span<double> whole(snapshot_buffer.data() + f * field_gather.whole_count(), field_gather.whole_count());
      field_gather.gather(local[f], whole);
      spans[f] = whole;
    }
    if (rank == 0) output->write_snapshot(sim.time(), std::span<const std::span<const double>>(spans.data(), local.size()));
  };
  std::array<double, kControlSize> control{};
  const auto reduce_control = [&] {
    MPI_Allreduce(MPI_IN_PLACE, control.data(), kControlSize, MPI_DOUBLE, MPI_MAX, comm);
  };

  RunResult result;
  result.time_step = sim.time_step();
  std::vector<double> previous_slip(sim.slip_x().begin(), sim.slip_x().end());
  double next_station = out_cfg.station_interval;
  double next_timeseries = out_cfg.timeseries_interval;
  double next_snapshot = out_cfg.snapshot_interval;
  double next_snapshot_slip = out_cfg.snapshot_slip_increment;  // rank 0's decides
  if (resuming) {
    // The records of t = 0 are in the file already; the triggers continue.
    std::array<double, 4> next{};
    if (rank == 0)
      next = {resume_from->next_station, resume_from->next_timeseries, resume_from->next_snapshot,
              resume_from->next_snapshot_slip};
    MPI_Bcast(next.data(), static_cast<int>(next.size()), MPI_DOUBLE, 0, comm);
    next_station = next[0];
    next_timeseries = next[1];
    next_snapshot = next[2];
    next_snapshot_slip = next[3];
    result.resumed_from_step = sim.step_index();
  } else {
    // t = 0, as run_simulation records it.
    if (stations) stations->record(sim, output.get());
    find_front();
    control = {};
    control[kFront] = front_nodes.empty() ? 0.0 : 1.0;
    reduce_control();
    if (control[kFront] > 0.0) pass_front();
    append_timeseries();
    if (out_cfg.snapshot_interval > 0.0 || out_cfg.snapshot_slip_increment > 0.0) write_snapshot();
  }

  // A restart point (collective), in the one file run_simulation writes
  // (solver/checkpoint.hpp), by rank 0 with its writer (temporary file,
  // fsync, rename) once every process's part has arrived: the run file
  // flushed, then the fields gathered in the one-process layout and each
  // process's history operator state by Fourier mode (its modes' records,
  // InterfaceHistory2d::save_mode_records), merged on rank 0 into the
  // one-process operator's state.  So the restart point is the one
  // `slipstrip run` writes, resumed on any number of processes or by
  // `slipstrip run --resume`.  force: also when a reader holds the run file
  // (the run is stopping); otherwise rank 0 postpones the restart point, on
  // every process, to its next timer check.  Allocates: only at restart
  // points, never per step.
  const auto write_restart_point = [&](bool force) {
    std::optional<RunOutputCursor> cursor;
    if (rank == 0) cursor = output->flush_for_checkpoint(force);
    int ready = rank == 0 && cursor ? 1 : 0;
    MPI_Bcast(&ready, 1, MPI_INT, 0, comm);
    if (!ready) return false;
    SimulationState local = sim.save_state();
    local.history = sim.history_operator().save_mode_records();
    RunCheckpoint checkpoint;
    for (const auto& f : kStateFields) {
      if (f.normal_stress_only && !sim.variable_normal_stress()) continue;
      auto whole = gather_rows(local.*f.field, comm);
      if (rank == 0) checkpoint.simulation.*f.field = std::move(whole);
    }
    if (rank != 0) {
      send_state(local.history, 0, comm);
      return true;
    }
    std::vector<HistoryOperatorState> parts;
    parts.push_back(std::move(local.history));
    for (int r = 1; r < processes; ++r) parts.push_back(receive_state(r, comm));
    checkpoint.simulation.history = InterfaceHistory2d::merge_mode_records(parts);
    checkpoint.config_toml = to_toml(config);
    checkpoint.git_hash = slipstrip::git_hash;
    checkpoint.simulation.time = sim.time();
    checkpoint.simulation.step_index = sim.step_index();
    checkpoint.output = std::move(*cursor);
    // Rank 0's writer learns of the first step's check of the initial slip
    // only with a crossing; the samplers that made it know.
    checkpoint.output.slip_recorded = sampler && sampler->started();
    checkpoint.next_timeseries = next_timeseries;
    checkpoint.next_snapshot = next_snapshot;
    checkpoint.next_snapshot_slip = next_snapshot_slip;
    checkpoint.next_station = next_station;
    write_checkpoint(output_path, checkpoint);
    result.restart_point = restart_path;
    return true;
  };

  const auto start = clock::now();
  auto last_flush = start, last_progress = start, last_checkpoint = start;
  const auto seconds_since = [](clock::time_point t) {
    return std::chrono::duration<double>(clock::now() - t).count();
  };
  std::string divergence;  // this process's
  while (sim.step_index() < total_steps) {
    std::copy(sim.slip_x().begin(), sim.slip_x().end(), previous_slip.begin());
    const double t_old = sim.time();
    bool crossed = false;
    try {
      sim.step();
      if (sampler) crossed = sampler->record(t_old, sim.time(), previous_slip, sim.slip_x());
      if (!front_reached.empty()) find_front();
    } catch (const SimulationError& e) {
      divergence = e.what();
    } catch (const SlipSamplingOverflow& e) {
      divergence = std::string(e.what()) + " (node numbered from node (0, " + std::to_string(sim.slab().first_row) +
                   "))";
    }
    control[kDiverged] = divergence.empty() ? 0.0 : 1.0;
    control[kStop] = rank == 0 && ((hooks.stop_requested && hooks.stop_requested()) ||
                                           (hooks.stop_after_steps >= 0 && sim.step_index() >= hooks.stop_after_steps))
                                 ? 1.0
                                 : 0.0;
    // Rank 0's wall-clock timer, read every 16 steps as run_simulation does.
    control[kRestartPoint] = rank == 0 && out_cfg.checkpoint_interval > 0.0 && (sim.step_index() & 15) == 0 &&
                                     seconds_since(last_checkpoint) >= out_cfg.checkpoint_interval
                                 ? 1.0
                                 : 0.0;
    control[kCrossings] = crossed ? 1.0 : 0.0;
    control[kFront] = divergence.empty() && !front_nodes.empty() ? 1.0 : 0.0;
    control[kMaxSpeed] = divergence.empty() ? *std::max_element(sim.speed().begin(), sim.speed().end()) : 0.0;
    reduce_control();
    if (control[kDiverged] > 0.0) {
      // The diagnostic of the lowest process that diverged (the first node
      // in the file's order, as one process would name).
      int first = divergence.empty() ? processes : rank;
      MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
      result.status = "diverged: " + broadcast_string(divergence, first, comm);
      break;
    }
    if (control[kCrossings] > 0.0) pass_crossings();
    // Every process has the same time (the same steps of dt), so every one
    // takes part in the same station rows.
    if (stations && sim.time() >= next_station * (1 - 1e-12)) {
      stations->record(sim, output.get());
      next_station += out_cfg.station_interval;
    }
    if (control[kFront] > 0.0) pass_front();
    if (sim.time() >= next_timeseries * (1 - 1e-12)) {
      append_timeseries();
      next_timeseries += out_cfg.timeseries_interval;
    }
    if (out_cfg.snapshot_interval > 0.0 && sim.time() >= next_snapshot * (1 - 1e-12)) {
      write_snapshot();
      next_snapshot += out_cfg.snapshot_interval;
    } else if (out_cfg.snapshot_slip_increment > 0.0) {
      // The sum over processes may round differently on each: rank 0's
      // decides, as its mean is the one the file's time series holds.
      const double mean_slip = sim.mean_slip_x();
      int take = rank == 0 && mean_slip >= next_snapshot_slip ? 1 : 0;
      MPI_Bcast(&take, 1, MPI_INT, 0, comm);
      if (take) {
        write_snapshot();
        if (rank == 0)
          next_snapshot_slip = next_slip_trigger(next_snapshot_slip, mean_slip, out_cfg.snapshot_slip_increment);
      }
    }
    if (control[kRestartPoint] > 0.0 && control[kStop] == 0.0 && write_restart_point(false))
      last_checkpoint = last_flush = clock::now();
    if (rank == 0 && (sim.step_index() & 15) == 0) {
      if (seconds_since(last_flush) >= out_cfg.flush_interval) {
        output->flush();
        last_flush = clock::now();
      }
      if (hooks.progress && seconds_since(last_progress) >= hooks.progress_interval) {
        hooks.progress({sim.time(), config.time.duration, sim.step_index(), control[kMaxSpeed],
                        seconds_since(start)});
        last_progress = clock::now();
      }
    }
    if (control[kStop] > 0.0) {
      write_restart_point(/*force=*/true);
      result.status = "interrupted";
      break;
    }
  }
  if (result.status.empty()) result.status = "completed";
  result.simulated_time = sim.time();
  result.steps = sim.step_index();
  result.wall_seconds = seconds_since(start);
  if (rank == 0) {
    if (hooks.progress)
      hooks.progress({sim.time(), config.time.duration, sim.step_index(), control[kMaxSpeed],
                      result.wall_seconds});
    output->close(result.status);
    if (result.status != "interrupted") {
      // Completed: nothing left to resume.  Diverged: a resume would
      // diverge again.  Either way the restart point is dead weight.
      remove_checkpoint(output_path);
      result.restart_point.clear();
    }
  }
  result.restart_point = broadcast_string(result.restart_point, 0, comm);
  return result;
}

}  // namespace

RunResult run_distributed(const SimulationConfig& config, const std::string& output_path, const RunHooks& hooks,
                          bool overwrite, std::span<const std::string> inputs, MPI_Comm comm) {
  const int rank = mpi_rank(comm);
  check_distributed_run(config);
  // The run's lock and the output paths, on rank 0 (the one process that
  // writes), before any process starts the set-up: as `slipstrip run` and
  // run_simulation do, so an input (the config) is never an output, even
  // with overwrite.
  std::optional<io::FileLock> lock;
  std::string refusal;
  if (rank == 0) {
    try {
      const io::OutputPath outputs[] = {{"--out", output_path},
                                        {"the restart point of --out", checkpoint_path(output_path)}};
      io::check_output_paths(outputs, inputs, overwrite);
      lock.emplace(lock_run_file(output_path));
      if (overwrite) {
        remove_checkpoint(output_path);
      } else {
        io::check_output_paths(outputs, inputs, false);  // again under the lock
      }
    } catch (const std::exception& e) {
      refusal = e.what();
    }
  }
  throw_if_refused(refusal, comm);
  return drive(config, output_path, hooks, comm, false, nullptr);
}

std::optional<RunResult> resume_distributed(const std::string& run_path, const std::string& given_config_toml,
                                            const RunHooks& hooks, MPI_Comm comm) {
  const int rank = mpi_rank(comm), processes = mpi_size(comm);
  // On rank 0, under the run's lock held to the end: the checks of
  // resume_simulation, and that the restart point was written on as many
  // processes.
  std::optional<io::FileLock> lock;
  std::optional<RunCheckpoint> checkpoint;
  std::string refusal, config_toml;
  int completed = 0;
  if (rank == 0) {
    try {
      lock.emplace(lock_run_file(run_path));
      const RunFileHeader header = read_run_file_header(run_path);
      if (header.status == "completed") {
        completed = 1;
      } else {
        if (!given_config_toml.empty() && given_config_toml != header.config_toml)
          throw std::invalid_argument("--resume '" + run_path +
                                      "': the config given differs from the run's stored config; a resumed run "
                                      "always continues with the stored config, give --resume alone");
        if (header.status.rfind("diverged", 0) == 0)
          throw std::invalid_argument("run file '" + run_path + "' has status '" + header.status +
                                      "': a resumed run would diverge again; nothing to resume");
        checkpoint.emplace(read_checkpoint(run_path));
        if (checkpoint->config_toml != header.config_toml)
          throw std::invalid_argument("restart point '" + checkpoint_path(run_path) +
                                      "' was written for another config than the run file '" + run_path +
                                      "' holds (not its restart point)");
        // A restart point in the one-process layout (`slipstrip run`'s, or
        // slipstrip-mpi run's on any process count) is cut by Fourier mode
        // for this job's processes in drive().  One of an earlier version's
        // per-process layout holds each process's own modes' state: it is
        // resumed on as many processes, whose next restart points are in the
        // one-process layout.
        const int written_by = restart_point_processes(*checkpoint);
        if (written_by != 0 && written_by != processes)
          throw std::invalid_argument("restart point '" + checkpoint_path(run_path) + "' was written on " +
                                      std::to_string(written_by) + " processes, this job has " +
                                      std::to_string(processes) + ", in the per-process layout of earlier versions "
                                      "(history kind '" + kSplitHistoryKind + "'), which holds each process's "
                                      "history operator state: resume it on as many processes (mpirun -np " +
                                      std::to_string(written_by) + "); its next restart points are in the "
                                      "one-process layout, resumed on any process count");
        config_toml = header.config_toml;
      }
    } catch (const std::exception& e) {
      refusal = e.what();
    }
  }
  throw_if_refused(refusal, comm);
  MPI_Bcast(&completed, 1, MPI_INT, 0, comm);
  if (completed) return std::nullopt;
  config_toml = broadcast_string(config_toml, 0, comm);
  SimulationConfig config;
  try {
    config = load_config_string(config_toml);
  } catch (const std::invalid_argument& e) {
    throw CollectiveError(e.what(), 0);
  }
  check_distributed_run(config);
  return drive(config, run_path, hooks, comm, true, checkpoint ? &*checkpoint : nullptr);
}

void throw_if_any_failed(const std::string& error, const std::string& context, MPI_Comm comm) {
  const int processes = mpi_size(comm);
  int first = error.empty() ? processes : mpi_rank(comm);
  MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first < processes) throw CollectiveError(context + broadcast_string(error, first, comm), first);
}

}  // namespace slipstrip
