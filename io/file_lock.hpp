#pragma once
// An advisory lock that lives exactly as long as its holder: flock(2) on a
// lock file, released by the kernel when the holding process ends however it
// ends (SIGKILL included), so a killed process never leaves a stale lock.
// Used for "one process per run" (core/run.hpp); any process that honours
// the same lock file is kept out, other programs are not (advisory).
#include <stdexcept>
#include <string>

namespace slipstrip::io {

// Another process (or another FileLock in this one) holds the lock: a usage
// error, exit code 2 in the CLI.
struct LockHeldError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

class FileLock {
 public:
  // Takes the lock on `path` (created if missing, mode 0644), without
  // waiting.  `what` names the protected thing in the message of a refusal,
  // e.g. "run file 'a.h5' and its restart point".  Throws LockHeldError
  // naming `what`, the lock file and the holder's process id, or
  // std::runtime_error if the lock file cannot be created.
  FileLock(const std::string& path, const std::string& what);
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;
  FileLock(FileLock&& other) noexcept;
  FileLock& operator=(FileLock&& other) noexcept;
  // Removes the lock file, then releases the lock.
  ~FileLock();

  const std::string& path() const { return path_; }

 private:
  void release() noexcept;
  std::string path_;
  int fd_ = -1;
};

}  // namespace slipstrip::io
