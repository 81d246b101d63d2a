#include "apps/python_launcher.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>

extern char** environ;

namespace slipstrip::cli {
namespace {

namespace fs = std::filesystem;

fs::path this_executable() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : self;
}

// The source tree's python/ directory if this binary sits in the build tree
// of a checkout (CMakeCache.txt next to it names the source directory), else "".
fs::path build_tree_python_dir(const fs::path& executable) {
  if (executable.empty()) return {};
  std::ifstream cache(executable.parent_path() / "CMakeCache.txt");
  constexpr std::string_view key = "CMAKE_HOME_DIRECTORY:INTERNAL=";
  for (std::string line; std::getline(cache, line);) {
    if (line.compare(0, key.size(), key) != 0) continue;
    const fs::path python_dir = fs::path(line.substr(key.size())) / "python";
    std::error_code ec;
    return fs::exists(python_dir / "slipstrip" / "__init__.py", ec) ? python_dir : fs::path();
  }
  return {};
}

std::vector<std::string> module_command(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {python_interpreter(), "-m", "slipstrip"};
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}

std::vector<char*> c_argv(std::vector<std::string>& argv) {
  std::vector<char*> out;
  for (auto& a : argv) out.push_back(a.data());
  out.push_back(nullptr);
  return out;
}

}  // namespace

std::string python_interpreter() {
  if (const char* chosen = std::getenv("SLIPSTRIP_PYTHON"); chosen && *chosen) return chosen;
  const std::string configured = SLIPSTRIP_CONFIGURED_PYTHON;
  if (!configured.empty() && ::access(configured.c_str(), X_OK) == 0) return configured;
  return "python3";
}

void prepare_python_environment() {
  const fs::path self = this_executable();
  if (const fs::path dir = build_tree_python_dir(self); !dir.empty()) {
    std::string python_path = dir.string();
    if (const char* existing = std::getenv("PYTHONPATH")) python_path += std::string(":") + existing;
    ::setenv("PYTHONPATH", python_path.c_str(), 1);
  }
  if (!std::getenv("SLIPSTRIP_BIN") && !self.empty()) ::setenv("SLIPSTRIP_BIN", self.c_str(), 1);
}

int exec_python_module(const std::vector<std::string>& args) {
  prepare_python_environment();
  auto argv = module_command(args);
  auto ptrs = c_argv(argv);
  ::execvp(ptrs[0], ptrs.data());
  std::fprintf(stderr, "slipstrip: cannot start %s: %s (set SLIPSTRIP_PYTHON to a Python 3 that has the "
                       "slipstrip package)\n", argv[0].c_str(), std::strerror(errno));
  return 1;
}

int run_python_module(const std::vector<std::string>& args) {
  prepare_python_environment();
  auto argv = module_command(args);
  auto ptrs = c_argv(argv);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, STDERR_FILENO, STDOUT_FILENO);
  pid_t pid = 0;
  const int err = ::posix_spawnp(&pid, ptrs[0], &actions, nullptr, ptrs.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0) {
    std::fprintf(stderr, "slipstrip: cannot start %s: %s\n", argv[0].c_str(), std::strerror(err));
    return 1;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return 1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

}  // namespace slipstrip::cli
