// io/file_lock: one holder at a time, a clear refusal naming the holder, the
// lock file removed by its holder, and a lock file left by a killed process
// (SIGKILL: no destructor ran) taken over by the next process.
#include <doctest/doctest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <optional>
#include <string>

#include "io/file_lock.hpp"
#include "io_test_support.hpp"

using namespace slipstrip;
using io_test::contains;
using io_test::error_of;
using io_test::temp_path;

TEST_CASE("a second holder is refused with the holder's pid; the lock file goes with its holder") {
  const std::string path = temp_path("lock") + ".lock";
  {
    io::FileLock first(path, "run file 'a.h5'");
    CHECK(std::filesystem::exists(path));
    const std::string e = error_of([&] { io::FileLock second(path, "run file 'a.h5'"); });
    CHECK(contains(e, "run file 'a.h5' is in use by another process (pid " + std::to_string(getpid()) + ")"));
    CHECK(e.find('\n') == std::string::npos);
    CHECK_THROWS_AS(io::FileLock(path, "x"), io::LockHeldError);
  }
  CHECK_FALSE(std::filesystem::exists(path));
  io::FileLock again(path, "run file 'a.h5'");  // free again
  io::FileLock moved = std::move(again);
  CHECK(moved.path() == path);
}

TEST_CASE("a process killed by SIGKILL leaves its lock file but not its lock") {
  const std::string path = temp_path("killed") + ".lock";
  int ready[2];
  REQUIRE(pipe(ready) == 0);
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    io::FileLock held(path, "run file 'b.h5'");
    const char byte = 1;
    [[maybe_unused]] auto n = write(ready[1], &byte, 1);
    pause();  // until killed
    _exit(0);
  }
  char byte = 0;
  REQUIRE(read(ready[0], &byte, 1) == 1);
  CHECK(contains(error_of([&] { io::FileLock(path, "run file 'b.h5'"); }),
                 "(pid " + std::to_string(child) + ")"));
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  CHECK(WIFSIGNALED(status));
  CHECK(std::filesystem::exists(path));  // the killed holder could not remove it
  {
    io::FileLock taken_over(path, "run file 'b.h5'");
    CHECK(std::filesystem::exists(path));
  }
  CHECK_FALSE(std::filesystem::exists(path));
  close(ready[0]);
  close(ready[1]);
}
