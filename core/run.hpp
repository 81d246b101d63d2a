#pragma once
// Drive one Simulation to the end of its duration, writing the HDF5 run file.
#include <functional>
#include <string>

#include "core/simulation_config.hpp"

namespace slipstrip {

struct RunProgress {
  double time;            // simulated time [s]
  double duration;        // target [s]
  long long step;
  double max_slip_rate;   // [m/s]
  double wall_seconds;    // since the start of the time loop
};

struct RunHooks {
  // Called about every progress_interval seconds of wall time.
  std::function<void(const RunProgress&)> progress;
  double progress_interval = 0.5;
  // Polled every step; true stops the run cleanly ("interrupted").
  std::function<bool()> stop_requested;
};

struct RunResult {
  std::string status;  // "completed", "interrupted" or "diverged: ..."
  double simulated_time = 0.0;
  long long steps = 0;
  double wall_seconds = 0.0;
  double time_step = 0.0;
};

// Runs `config` and writes `output_path`.  A divergence (non-finite field,
// failed local solve) ends the run with status "diverged: <diagnostic>" and a
// readable file; it is reported in the result, not thrown.
RunResult run_simulation(const SimulationConfig& config, const std::string& output_path,
                         const RunHooks& hooks = {});

}  // namespace slipstrip
