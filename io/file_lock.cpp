#include "io/file_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "io/messages.hpp"

namespace slipstrip::io {
namespace {

// The holder's process id as it wrote it into the lock file ("" if unknown).
std::string holder_of(int fd) {
  char buffer[32] = {};
  const ssize_t n = ::pread(fd, buffer, sizeof buffer - 1, 0);
  if (n <= 0) return "";
  std::string text(buffer, static_cast<std::size_t>(n));
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (char c : text)
    if (c < '0' || c > '9') return "";
  return text;
}

}  // namespace

FileLock::FileLock(const std::string& path, const std::string& what) : path_(path) {
  // The holder removes the lock file when it is done; a process that opened
  // the file just before that would lock a file no longer in the directory,
  // and a third process would then lock a new one.  So: lock, then check that
  // the path still names the file locked, else start again.
  for (int attempt = 0;; ++attempt) {
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0)
      throw std::runtime_error(one_line("cannot create the lock file " + quoted_input(path, 160) + " for " + what +
                                        ": " + std::strerror(errno)));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      const std::string holder = holder_of(fd);
      ::close(fd);
      if (err == EWOULDBLOCK)
        throw LockHeldError(one_line(what + " is in use by another process" +
                                     (holder.empty() ? std::string() : " (pid " + holder + ")") +
                                     ", which holds the lock " + quoted_input(path, 160) +
                                     ": one process per run; wait for it to end or stop it first"));
      throw std::runtime_error(one_line("cannot lock " + quoted_input(path, 160) + " for " + what + ": " +
                                        std::strerror(err)));
    }
    struct stat locked {}, named {};
    if (::fstat(fd, &locked) == 0 && ::stat(path.c_str(), &named) == 0 && locked.st_dev == named.st_dev &&
        locked.st_ino == named.st_ino) {
      fd_ = fd;
      break;
    }
    ::close(fd);
    if (attempt >= 100)
      throw std::runtime_error(one_line("cannot lock " + quoted_input(path, 160) + " for " + what +
                                        ": the lock file keeps being replaced"));
  }
  // For the message of a refused second process: who holds it.
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) == 0) {
    [[maybe_unused]] const ssize_t written = ::pwrite(fd_, pid.data(), pid.size(), 0);
  }
}

FileLock::FileLock(FileLock&& other) noexcept
    : path_(std::move(other.path_)), fd_(std::exchange(other.fd_, -1)) {}

FileLock& FileLock::operator=(FileLock&& other) noexcept {
  if (this != &other) {
    release();
    path_ = std::move(other.path_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

FileLock::~FileLock() { release(); }

void FileLock::release() noexcept {
  if (fd_ < 0) return;
  // Unlink while still holding the lock (see the constructor).
  ::unlink(path_.c_str());
  ::close(fd_);
  fd_ = -1;
}

}  // namespace slipstrip::io
