// slipstrip command-line program.  One file per subcommand
// (apps/command_<name>.cpp): run, stability, events, bench, config-docs, and
// the Python-backed analyze / scan / plot / export / report / transition
// (python/slipstrip).  Here: the command line, and the exit codes.
#include <hdf5.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/cli.hpp"
#include "io/messages.hpp"
#include "slipstrip/version.hpp"
#include "solver/run_output.hpp"

int main(int argc, char** argv) {
  namespace cli = slipstrip::cli;
  CLI::App app{"slipstrip: spectral boundary-integral solver for frictional sliding between two "
               "elastic strips of height H (rate-and-state friction). SI units throughout."};
  app.set_version_flag("--version", std::string(slipstrip::code_version) + " (" + slipstrip::git_hash + ")");
  app.require_subcommand(1);
  // Usage errors in one line (CLI11's default adds "Run with --help ..." on a second line).
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    std::string message = e.what();
    std::replace(message.begin(), message.end(), '\n', ' ');
    return "error: " + slipstrip::io::one_line(message) + " (see --help)\n";
  });

  std::vector<cli::Command> commands = {cli::add_run_command(app), cli::add_stability_command(app),
                                        cli::add_events_command(app), cli::add_bench_command(app),
                                        cli::add_config_docs_command(app)};
  for (auto& command : cli::add_python_commands(app)) commands.push_back(std::move(command));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every usage error exits 2 (not CLI11's 104-114).
    return app.exit(e) == 0 ? 0 : 2;
  }
  // Our own messages name the cause; HDF5's stack dumps would bury them.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  try {
    for (const auto& command : commands)
      if (*command.app) return command.run();
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", slipstrip::io::one_line(e.what()).c_str());
    return 2;
  } catch (const slipstrip::OutputError& e) {
    std::fprintf(stderr, "error: %s\n", slipstrip::io::one_line(e.what()).c_str());
    std::fflush(stderr);
    // A file whose H5Fclose failed stays open inside HDF5, whose exit handler
    // would retry the close and crash (exit 139 on a full disk): leave
    // without running it.  Nothing of ours is buffered.
    std::fflush(stdout);
    std::_Exit(4);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", slipstrip::io::one_line(e.what()).c_str());
    return 1;
  }
  return 0;
}
