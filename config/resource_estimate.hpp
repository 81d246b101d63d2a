#pragma once
// What a run will cost, from its config alone, before anything is built:
// the number of time steps, the memory of the history operator and the size
// of the output file.  check_resources() refuses (ConfigError, exit code 2 in
// the CLI) what exceeds the limits, naming the keys that drive the estimate;
// docs/reliability.md lists the formulas and the default limits.
#include <cstdint>
#include <string>

#include "config/simulation_config.hpp"

namespace slipstrip {

struct ResourceEstimate {
  double time_step = 0.0;            // dt [s] as the solver will use it
  double steps = 0.0;                // duration / dt (a double: it may be astronomically large)
  double echo_steps = 0.0;           // M = 2H/(c_s dt) (0 for a half-space)
  double modes_per_fourier_mode = 0.0;  // P ~ (M/2)(1 + c_s/c_d) strip normal modes
  bool block_history = false;        // which strip algorithm the run will take
  double operator_bytes = 0.0;       // history operator (state + coefficients + kernels)
  double output_bytes = 0.0;         // uncompressed upper estimate of the HDF5 file
};

// Default limits: generous for one workstation; the CLI options
// --max-memory-gib, --max-steps and --max-output-gib raise them.
struct ResourceLimits {
  double max_operator_gib = 8.0;
  double max_steps = 1e10;
  double max_output_gib = 64.0;
};

ResourceEstimate estimate_resources(const SimulationConfig& config);

// Throws ConfigError naming the keys, the estimate and the limit (and the CLI
// option that raises it) when an estimate exceeds its limit.
void check_resources(const SimulationConfig& config, const ResourceLimits& limits = {});

}  // namespace slipstrip
