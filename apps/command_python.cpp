// The subcommands implemented by the Python package: every argument is
// forwarded to `python -m slipstrip <command>` (apps/python_launcher.hpp).
#include <string>
#include <vector>

#include "apps/cli.hpp"
#include "apps/python_launcher.hpp"

namespace slipstrip::cli {

std::vector<Command> add_python_commands(CLI::App& app) {
  std::vector<Command> commands;
  for (const char* name : {"analyze", "scan", "plot", "export", "report", "transition", "pulse-episodes",
                           "trajectory-divergence"}) {
    auto* py = app.add_subcommand(name, std::string("Python: python3 -m slipstrip ") + name +
                                            " (see docs/analysis.md, docs/scans.md); arguments are forwarded");
    py->allow_extras();
    py->prefix_command();
    // No help flag of our own: `slipstrip export --help` goes to the Python
    // command, whose help lists its real options (ours would list only -h).
    py->set_help_flag();
    commands.push_back({py, [py, name = std::string(name)] {
                          std::vector<std::string> args = {name};
                          const auto rest = py->remaining();
                          args.insert(args.end(), rest.begin(), rest.end());
                          return exec_python_module(args);
                        }});
  }
  return commands;
}

}  // namespace slipstrip::cli
