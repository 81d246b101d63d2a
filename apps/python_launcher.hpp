#pragma once
// The subcommands written in Python (analyze, scan, plot, ...) run
// `<python> -m slipstrip <command> ...`, found the way an installed package is:
//   * the interpreter: $SLIPSTRIP_PYTHON if set, else the one CMake was
//     configured with (Python3_EXECUTABLE, recorded at build time) if it
//     still exists, else `python3` from PATH;
//   * the package: from the interpreter's import path (pip install, a .pth
//     file, PYTHONPATH).  A binary that runs from its build tree also puts
//     that tree's source python/ first on PYTHONPATH (read from the build
//     tree's CMakeCache.txt next to the binary), so a checkout's CLI uses
//     the checkout's package.
// SLIPSTRIP_BIN is set to this binary (unless already set), so the Python
// side starts the same solver.
#include <string>
#include <vector>

namespace slipstrip::cli {

// The interpreter as chosen above (a path, or "python3" to be found on PATH).
std::string python_interpreter();

// Sets PYTHONPATH and SLIPSTRIP_BIN for the Python side as described above.
void prepare_python_environment();

// Replaces this process by `<python> -m slipstrip args...`; returns 1 with a
// message on stderr only if the interpreter cannot be started.
int exec_python_module(const std::vector<std::string>& args);

// Runs `<python> -m slipstrip args...` with its stdout sent to our stderr
// (our stdout stays the command's own output) and returns its exit status
// (nonzero if it could not run).
int run_python_module(const std::vector<std::string>& args);

}  // namespace slipstrip::cli
