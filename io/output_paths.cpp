#include "io/output_paths.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include "io/messages.hpp"

namespace slipstrip::io {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void refuse(const OutputPath& output, const std::string& reason) {
  throw OutputPathError(one_line(output.option + " " + quoted_input(output.path, 160) + " " + reason));
}

// The same file as an existing path: device and inode of what it names
// (symbolic links followed).
bool same_file(const struct stat& a, const std::string& other) {
  struct stat b {};
  return ::stat(other.c_str(), &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

// Where an output will land, for comparing outputs with each other (they may
// not exist yet): the absolute path with every existing symbolic link and
// `..` resolved.
fs::path landing_place(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::absolute(path, ec).lexically_normal() : p;
}

// What is at an output's path: the directory entry itself (a symbolic link
// is not followed) and what it names (followed).
struct Found {
  bool entry = false, target = false;
  struct stat link {}, file {};
};

// Looks at the path; refuses it if it names one of the inputs (for files and
// directories alike) or is a symbolic link to nothing.
Found look_at(const OutputPath& output, std::span<const std::string> inputs, const std::string& advice) {
  Found f;
  f.entry = ::lstat(output.path.c_str(), &f.link) == 0;
  f.target = ::stat(output.path.c_str(), &f.file) == 0;
  if (f.target)
    for (const auto& input : inputs)
      if (same_file(f.file, input)) refuse(output, "is the input " + quoted_input(input, 160) + ": " + advice);
  if (f.entry && !f.target) {
    std::error_code ec;
    const auto to = fs::read_symlink(output.path, ec);
    refuse(output, "is a symbolic link to " + quoted_input(ec ? std::string("?") : to.string(), 160) +
                       ", which does not exist: remove the link or choose another path");
  }
  return f;
}

// `in_new_directory`: the file goes into a directory output that does not
// exist yet (the command creates it), so there is nothing to probe.
void check_file(const OutputPath& output, std::span<const std::string> inputs, bool overwrite,
                std::string_view overwrite_flag, bool in_new_directory) {
  const Found found = look_at(output, inputs,
                              "refusing to write over an input (even with " + std::string(overwrite_flag) +
                                  "); choose another path");
  const bool exists = found.target;
  if (exists && S_ISDIR(found.file.st_mode)) refuse(output, "is a directory: expected a file name");
  if (exists && !overwrite)
    refuse(output, "already exists: refusing to overwrite it (give " + std::string(overwrite_flag) +
                       " to replace it, or choose another path)");
  if (in_new_directory) return;
  const fs::path p(output.path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  struct stat dir_stat {};
  if (::stat(dir.c_str(), &dir_stat) != 0)
    refuse(output, "cannot be written: its directory " + quoted_input(dir.string(), 160) + " is not usable (" +
                       std::strerror(errno) + ")");
  if (!S_ISDIR(dir_stat.st_mode))
    refuse(output, "cannot be written: " + quoted_input(dir.string(), 160) + " is not a directory");
  // The real test (permissions, read-only file system): open it for writing
  // as the command will, truncating nothing.  Never waiting: a FIFO that no
  // process reads would block the open for ever (O_NONBLOCK makes it ENXIO).
  const int fd = exists ? ::open(output.path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC)
                        : ::open(output.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0 && errno == ENXIO && S_ISFIFO(found.file.st_mode))
    refuse(output, "is a FIFO that no process reads: expected a file name");
  if (fd < 0) refuse(output, std::string("cannot be written: ") + std::strerror(errno));
  ::close(fd);
  if (!exists) ::unlink(output.path.c_str());
}

void check_directory(const OutputPath& output, std::span<const std::string> inputs) {
  const Found found = look_at(output, inputs, "choose another directory");
  if (found.target && !S_ISDIR(found.file.st_mode))
    refuse(output, "exists and is not a directory: refusing to replace it; choose another directory");
}

}  // namespace

void check_output_paths(std::span<const OutputPath> outputs, std::span<const std::string> inputs,
                        bool overwrite, std::string_view overwrite_flag) {
  // Directory outputs that do not exist yet: their files are not probed.
  std::vector<fs::path> new_directories;
  for (const auto& output : outputs) {
    std::error_code ec;
    if (output.kind == OutputPath::Kind::directory && !output.path.empty() &&
        !fs::exists(fs::symlink_status(output.path, ec)))
      new_directories.push_back(landing_place(output.path));
  }
  // Directories first: a directory that cannot be one (it is an input, a
  // file) is the reason its files cannot be written, and is named as such.
  std::vector<const OutputPath*> ordered;
  for (const auto kind : {OutputPath::Kind::directory, OutputPath::Kind::file})
    for (const auto& output : outputs)
      if (output.kind == kind) ordered.push_back(&output);
  std::vector<std::pair<fs::path, const OutputPath*>> seen;
  for (const OutputPath* next : ordered) {
    const OutputPath& output = *next;
    if (output.path.empty()) continue;
    const fs::path place = landing_place(output.path);
    for (const auto& [other_place, other] : seen)
      if (other_place == place)
        refuse(output, "is also given as " + other->option + ": each output needs its own path");
    seen.emplace_back(place, &output);
    if (output.kind == OutputPath::Kind::directory)
      check_directory(output, inputs);
    else
      check_file(output, inputs, overwrite, overwrite_flag,
                 std::find(new_directories.begin(), new_directories.end(), place.parent_path()) !=
                     new_directories.end());
  }
}

std::string not_a_regular_file(const std::string& path) {
  struct stat link {}, target {};
  if (::lstat(path.c_str(), &link) != 0) return "does not exist";
  if (::stat(path.c_str(), &target) != 0) {
    std::error_code ec;
    return "is a symbolic link to " + quoted_input(fs::read_symlink(path, ec).string(), 120) +
           ", which does not exist";
  }
  if (S_ISREG(target.st_mode)) return "";
  if (S_ISDIR(target.st_mode)) return "is not a regular file (a directory)";
  if (S_ISCHR(target.st_mode)) return "is not a regular file (a character device)";
  if (S_ISBLK(target.st_mode)) return "is not a regular file (a block device)";
  if (S_ISFIFO(target.st_mode)) return "is not a regular file (a FIFO)";
  if (S_ISSOCK(target.st_mode)) return "is not a regular file (a socket)";
  return "is not a regular file";
}

void check_output_path(const std::string& option, const std::string& path, std::span<const std::string> inputs,
                       bool overwrite, std::string_view overwrite_flag) {
  const OutputPath output{option, path, OutputPath::Kind::file};
  check_output_paths(std::span(&output, 1), inputs, overwrite, overwrite_flag);
}

}  // namespace slipstrip::io
