// slipstrip run CONFIG [--set ...] [--out RUN.h5]: one simulation, one HDF5
// file; and slipstrip run --resume RUN.h5: continue it from its restart point.
#include <sys/statvfs.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "apps/cli.hpp"
#include "config/config.hpp"
#include "config/resource_estimate.hpp"
#include "io/file_lock.hpp"
#include "io/messages.hpp"
#include "io/output_paths.hpp"
#include "slipstrip/version.hpp"
#include "solver/checkpoint.hpp"
#include "solver/run.hpp"

namespace slipstrip::cli {
namespace {

struct RunOptions {
  std::string config_path, out_path, resume_path;
  std::vector<std::string> overrides;
  bool quiet = false, overwrite = false;
  long long stop_after_steps = -1;
  ResourceLimits limits;
};

// Everything about the outputs that can be checked before the (possibly
// long) set-up, by the rule of every command (io/output_paths.hpp): the run
// file and its restart point are outputs, the config an input.  (The run
// checks again under its lock, solver/run.hpp.)
void check_run_outputs(const std::string& out_path, const std::string& config_path, bool overwrite) {
  const io::OutputPath outputs[] = {{"--out", out_path}, {"the restart point of --out", checkpoint_path(out_path)}};
  const std::string inputs[] = {config_path};
  io::check_output_paths(outputs, inputs, overwrite);
}

// The first line where two resolved configs differ, for the message of a
// refused --resume.
std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream sa(a), sb(b);
  std::string la, lb;
  while (true) {
    const bool more_a = static_cast<bool>(std::getline(sa, la)), more_b = static_cast<bool>(std::getline(sb, lb));
    if (!more_a && !more_b) return "";
    if (!more_a) la = "(end)";
    if (!more_b) lb = "(end)";
    if (la != lb) return "'" + la + "' given, the run has '" + lb + "'";
  }
}


int report_result(const RunResult& result, const std::string& out_path, bool quiet, bool tty) {
  if (!quiet && tty) std::fprintf(stderr, "\n");
  std::fprintf(stderr, "%s after %lld steps (dt = %.6g s), simulated %.6g s in %.2f s wall; output %s\n",
               result.status.c_str(), result.steps, result.time_step, result.simulated_time,
               result.wall_seconds, out_path.c_str());
  if (!result.restart_point.empty())
    std::fprintf(stderr, "restart point %s: continue with `slipstrip run --resume %s`\n",
                 result.restart_point.c_str(), out_path.c_str());
  if (result.status == "completed") return 0;
  if (result.status == "interrupted") return signal_exit_code();
  return 3;  // diverged
}

// `slipstrip run --resume RUN.h5 [CONFIG [--set ...]]`: the run continues
// with the resolved config stored in RUN.h5.  A config (and --set) given as
// well is only checked, never applied: it must resolve to exactly the stored
// config, else exit 2 (so a scan or job script can pass its usual command line).
int resume(const RunOptions& o) {
  catch_interrupts();
  const std::string& run_path = o.resume_path;
  // The lock before the first read: a run that another process writes is
  // refused as "in use", not as an HDF5 read error.
  const io::FileLock lock = lock_run_file(run_path);
  const auto header = read_run_file_header(run_path);
  if (header.status == "completed") {
    std::fprintf(stderr, "%s: the run is already completed; nothing to resume\n", run_path.c_str());
    return 0;
  }
  if (!o.config_path.empty()) {
    const auto given = to_toml(load_config_file(o.config_path, o.overrides));
    if (given != header.config_toml)
      throw std::invalid_argument("--resume '" + run_path + "': config '" + o.config_path +
                                  (o.overrides.empty() ? "" : "' with its --set overrides") +
                                  "' differs from the run's stored config (" +
                                  first_difference(given, header.config_toml) +
                                  "); a resumed run always continues with the stored config, give "
                                  "--resume alone");
  } else if (!o.overrides.empty()) {
    throw std::invalid_argument("--resume '" + run_path +
                                "' with --set but no config: a resumed run continues with its stored "
                                "config and cannot change it (give the original config and --set "
                                "only to have them checked)");
  }
  const bool tty = isatty(fileno(stderr));
  const RunHooks hooks = run_hooks(o.quiet, tty, o.stop_after_steps);
  std::fprintf(stderr, "slipstrip %s (%s): resuming %s\n", code_version, git_hash, io::one_line(run_path).c_str());
  RunResult result;
  try {
    result = resume_simulation(run_path, hooks, lock);
  } catch (const SetupCancelled& e) {
    std::fprintf(stderr, "interrupted by %s during the set-up (%s); %s and its restart point are unchanged\n",
                 interrupt_name(), e.what(), run_path.c_str());
    return signal_exit_code();
  }
  std::fprintf(stderr, "resumed from step %lld\n", result.resumed_from_step);
  return report_result(result, run_path, o.quiet, tty);
}

int run(const RunOptions& o) {
  // Signals first: from here on SIGINT/SIGTERM stop the run within about a
  // second, set-up included.
  catch_interrupts();
  const std::string& config_path = o.config_path;
  const auto config = load_config_file(config_path, o.overrides);
  std::string out_path = o.out_path;
  if (out_path.empty()) {
    auto base = config_path.substr(config_path.find_last_of('/') + 1);
    if (auto dot = base.rfind('.'); dot != std::string::npos) base = base.substr(0, dot);
    out_path = base + ".h5";
  }
  check_run_outputs(out_path, config_path, o.overwrite);
  // What the run will cost, and the config's plausibility warnings, before
  // the limits refuse it or the (possibly long) set-up starts.
  std::fputs(run_header(config).c_str(), stderr);
  check_resources(config, o.limits);
  warn_if_disk_too_small(config, out_path);
  const bool tty = isatty(fileno(stderr));
  const RunHooks hooks = run_hooks(o.quiet, tty, o.stop_after_steps);
  std::fprintf(stderr, "slipstrip %s (%s): %s -> %s\n", code_version, git_hash, io::one_line(config_path).c_str(),
               io::one_line(out_path).c_str());
  RunResult result;
  try {
    // With --overwrite, an old restart point of this name goes (under the
    // run's lock), so it is never taken for this run's.
    result = run_simulation(config, out_path, hooks, o.overwrite);
  } catch (const SetupCancelled& e) {
    std::fprintf(stderr, "interrupted by %s during the set-up (%s); no output written\n", interrupt_name(),
                 e.what());
    return signal_exit_code();
  }
  return report_result(result, out_path, o.quiet, tty);
}

}  // namespace

Command add_run_command(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  auto* run_app = app.add_subcommand("run", "Run a simulation from a TOML config and write one HDF5 file "
                                            "(see docs/config.md and docs/output.md). Ctrl-C stops cleanly "
                                            "and leaves a restart point for --resume.");
  run_app->add_option("config", o->config_path, "TOML config file (with --resume: optional, only checked)");
  run_app->add_option("--resume", o->resume_path,
                      "Continue the interrupted run RUN.h5 from its restart point RUN.h5.restart, appending "
                      "to RUN.h5 with the config stored in it (docs/reliability.md)");
  run_app->add_option("--stop-after-steps", o->stop_after_steps,
                      "Stop as SIGTERM does (restart point, status interrupted, exit 143) once this many "
                      "time steps from t = 0 are done (for tests of --resume)")
      ->check(finite_positive());
  run_app->add_option("--set", o->overrides, "Override a config key: section.key=value (repeatable)");
  run_app->add_option("--out", o->out_path, "Output HDF5 file (default: <config name>.h5)");
  run_app->add_flag("--quiet", o->quiet, "No progress bar");
  run_app->add_flag("--overwrite", o->overwrite, "Replace an existing --out file (never the config file itself)");
  run_app->add_option("--max-memory-gib", o->limits.max_operator_gib,
                      "Refuse runs whose estimated history-operator memory exceeds this [GiB]")
      ->capture_default_str()->check(finite_positive());
  run_app->add_option("--max-steps", o->limits.max_steps, "Refuse runs of more time steps than this")
      ->capture_default_str()->check(finite_positive());
  run_app->add_option("--max-output-gib", o->limits.max_output_gib,
                      "Refuse runs whose estimated output file exceeds this [GiB]")
      ->capture_default_str()->check(finite_positive());
  return {run_app, [o] {
            if (!o->resume_path.empty()) {
              if (!o->out_path.empty() || o->overwrite)
                throw std::invalid_argument("--resume '" + o->resume_path +
                                            "' continues writing that file: --out and --overwrite do not apply");
              return resume(*o);
            }
            if (o->config_path.empty())
              throw std::invalid_argument("run: config is required (a TOML config file; or --resume RUN.h5 to "
                                          "continue a run; see --help)");
            return run(*o);
          }};
}

}  // namespace slipstrip::cli
