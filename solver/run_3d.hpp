#pragma once
// Drive one Simulation3d (a 2D interface, geometry.nodes_z > 1) to the end of
// its duration, writing an HDF5 run file and an XDMF sidecar (docs/3d.md,
// "Output").  No restart points and no events yet.
#include <string>

#include "config/simulation_config.hpp"
#include "solver/run.hpp"

namespace slipstrip {

// Runs `config` (nodes_z > 1) and writes `output_path` and its .xdmf sidecar.
// hooks.stop_requested is polled during the set-up (throws SetupCancelled
// before any file is created) and every step (status "interrupted", file
// readable, no restart point).  A divergence ends the run with status
// "diverged: <diagnostic>" and a readable file.
RunResult run_simulation_3d(const SimulationConfig& config, const std::string& output_path,
                            const RunHooks& hooks = {});

}  // namespace slipstrip
