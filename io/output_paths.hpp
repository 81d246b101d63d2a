#pragma once
// The one rule for the output paths of every command (C++ CLI and Python,
// docs/reliability.md "Output paths"): an output never replaces an input, and
// never an existing file unless the user said so.  Python calls the same
// function through the bindings (python/slipstrip/paths.py).
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace slipstrip::io {

// A refused output path (a bad command line: exit code 2).
struct OutputPathError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// One output a command is about to write.
struct OutputPath {
  enum class Kind { file, directory };
  std::string option;  // how the user named it, for the message: "--out", "--csv", "restart point of --out"
  std::string path;
  Kind kind = Kind::file;
};

// Checks every output before anything is computed or written; throws
// OutputPathError (one line naming the option, the path and the reason):
//  * an output that is one of `inputs` (the same file by device and inode,
//    so `./a.h5`, `a.h5` and a symlink to it are one file) is refused, even
//    with overwrite;
//  * two outputs naming the same file are refused;
//  * a file output that exists is refused unless `overwrite` (the message
//    names `overwrite_flag`, e.g. "--overwrite" or "overwrite=True"); a
//    directory, or a symbolic link to nothing, in its place is refused;
//  * a file output's directory must exist and accept the file: it is opened
//    for writing as the command will (without truncating; a new file is
//    created and removed again), so a missing or read-only directory is
//    found now, with the operating system's reason;
//  * a directory output (the command writes files into it) may exist, but
//    only as a directory; the files it writes there are file outputs of
//    their own, checked by the command with this rule.
// Directory outputs are checked before file outputs (a directory that is an
// input is named as such, not as the reason its files cannot be written).
// Empty paths are skipped (an option that was not given).
void check_output_paths(std::span<const OutputPath> outputs, std::span<const std::string> inputs,
                        bool overwrite, std::string_view overwrite_flag = "--overwrite");

// What is at `path` when it is not a regular file an input must be, for a
// message: "does not exist", "is a symbolic link to 'X', which does not
// exist", "is not a regular file (a directory)", "... (a character device)",
// "... (a block device)", "... (a FIFO)", "... (a socket)"; "" for a regular
// file (symbolic links followed).
std::string not_a_regular_file(const std::string& path);

// One file output (the common case).
void check_output_path(const std::string& option, const std::string& path, std::span<const std::string> inputs,
                       bool overwrite, std::string_view overwrite_flag = "--overwrite");

}  // namespace slipstrip::io
