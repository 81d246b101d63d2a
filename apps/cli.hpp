#pragma once
// What the slipstrip subcommands share: how a subcommand is registered and
// run, signal handling for the runs, and the progress and JSON helpers.
// Each subcommand lives in its own file, apps/command_<name>.cpp.
#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

#include "solver/run.hpp"

namespace slipstrip::cli {

// A registered subcommand: `run` is called when it was given on the command
// line and returns the exit code.  The options it parses live in the closure.
struct Command {
  CLI::App* app;
  std::function<int()> run;
};

Command add_run_command(CLI::App& app);
Command add_stability_command(CLI::App& app);
Command add_events_command(CLI::App& app);
Command add_bench_command(CLI::App& app);
Command add_config_docs_command(CLI::App& app);
// The subcommands implemented by the Python package (analyze, scan, ...).
std::vector<Command> add_python_commands(CLI::App& app);

// CLI::PositiveNumber prints its range as 0 ... 1.8e308 in %f, 300 digits.
const CLI::Validator& finite_positive();

// SIGINT/SIGTERM stop a run cleanly: the handler only records the signal
// (the one piece of process-wide mutable state, kept in the CLI so that a
// process embedding several simulations is unaffected).
void catch_interrupts();
bool interrupted();
// Exit code of a run stopped by a signal: the shell's 128 + signal number
// (SIGINT 130, SIGTERM 143; docs/reliability.md).  --stop-after-steps stops
// the run as SIGTERM would, so it exits as SIGTERM.
int signal_exit_code();
const char* interrupt_name();  // "SIGTERM", "SIGINT" or "a signal"

// The hooks of a run started from the CLI: progress bar on stderr (unless
// quiet), stop on SIGINT/SIGTERM or after stop_after_steps.
RunHooks run_hooks(bool quiet, bool tty, long long stop_after_steps);

// Warns on stderr when the run's estimated output (estimate_resources, an
// upper bound: snapshots are compressed) exceeds the free space where
// out_path will be written.  Advisory only: a full disk stops the run with
// exit code 4 and keeps what was written readable.
void warn_if_disk_too_small(const SimulationConfig& config, const std::string& out_path);

// Numbers for JSON output: %.17g, non-finite values as null.
std::string json_number(double v);
std::string json_array(const std::vector<double>& v);

}  // namespace slipstrip::cli
