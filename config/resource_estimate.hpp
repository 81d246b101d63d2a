#pragma once
// What a run will cost, from its config alone, before anything is built:
// the number of time steps, the memory of the history operator, the size
// of the output file and a rough wall time.  check_resources() refuses (ConfigError, exit code 2 in
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
  // A bottom body of its own (bottom.body = "elastic"; docs/bodies.md): its
  // echo and normal modes, counted like the top body's (0 for a half-space, a
  // rigid or a mirror bottom).  operator_bytes and step_seconds include it.
  double bottom_echo_steps = 0.0;
  double bottom_modes_per_fourier_mode = 0.0;
  bool block_history = false;        // which strip algorithm the run will take
  double operator_bytes = 0.0;       // history operator (state + coefficients + kernels)
  double output_bytes = 0.0;         // uncompressed upper estimate of the HDF5 file
  double step_seconds = 0.0;         // wall time of one step on one core (rough model, below)
  double wall_seconds = 0.0;         // steps * step_seconds, without the set-up
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

// The run header `slipstrip run` prints before the set-up, so that a unit
// mistake shows at once: steps and dt, the wall-time estimate, H/L, the
// history operator's memory, the output size, the slip of one step at v0
// against delta_th, then one "warning: ..." line per plausibility warning of
// the config (config/config_schema.hpp).  Lines end with '\n'.
std::string run_header(const SimulationConfig& config);

}  // namespace slipstrip
