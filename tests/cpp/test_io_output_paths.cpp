// io/output_paths: the one rule for output paths of every command.  An
// input is never an output (whatever the spelling, even with overwrite), an
// existing file only with overwrite, two outputs never share a file, and
// unusable places are found before anything runs, each with one line.
#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/output_paths.hpp"
#include "io_test_support.hpp"

using namespace slipstrip;
using io_test::contains;
using io_test::error_of;
namespace fs = std::filesystem;

namespace {

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("slipstrip_io_paths_" + std::to_string(getpid()));
  Scratch() {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  std::string file(const std::string& name, const std::string& content = "data") const {
    std::ofstream(dir / name) << content;
    return (dir / name).string();
  }
  std::string path(const std::string& name) const { return (dir / name).string(); }
};

std::string check(const std::string& option, const std::string& path, std::vector<std::string> inputs,
                  bool overwrite) {
  return error_of([&] { io::check_output_path(option, path, inputs, overwrite); });
}

}  // namespace

TEST_CASE("a new file in a writable directory is accepted and nothing is left behind") {
  Scratch s;
  CHECK(check("--csv", s.path("new.csv"), {}, false) == "<no error>");
  CHECK_FALSE(fs::exists(s.path("new.csv")));
}

TEST_CASE("an input is never an output, by any spelling, even with overwrite") {
  Scratch s;
  const std::string run = s.file("run.h5");
  fs::create_symlink(run, s.path("link.h5"));
  fs::create_hard_link(run, s.path("hard.h5"));
  for (const std::string& spelling :
       {run, (s.dir / "." / "run.h5").string(), s.path("link.h5"), s.path("hard.h5")}) {
    const std::string e = check("--csv", spelling, {run}, true);
    CHECK(contains(e, "--csv '"));
    CHECK(contains(e, "is the input"));
    CHECK(contains(e, "even with --overwrite"));
  }
  std::ifstream in(run);
  std::string content;
  in >> content;
  CHECK(content == "data");
}

TEST_CASE("an existing file needs overwrite; a directory or a dangling link never") {
  Scratch s;
  const std::string old = s.file("old.csv");
  const std::string e = check("--csv", old, {}, false);
  CHECK(contains(e, "already exists: refusing to overwrite it (give --overwrite to replace it"));
  CHECK(check("--csv", old, {}, true) == "<no error>");
  CHECK(contains(error_of([&] { io::check_output_path("out_path", old, {}, false, "overwrite=True"); }),
                 "give overwrite=True"));
  CHECK(contains(check("--out", s.dir.string(), {}, true), "is a directory"));
  fs::create_symlink(s.path("missing/target.h5"), s.path("dangling.h5"));
  const std::string d = check("--out", s.path("dangling.h5"), {}, true);
  CHECK(contains(d, "is a symbolic link to '"));
  CHECK(contains(d, "which does not exist"));
}

TEST_CASE("a missing or read-only directory is found with the system's reason") {
  Scratch s;
  CHECK(contains(check("--out", s.path("nowhere/x.h5"), {}, false), "No such file or directory"));
  const std::string file = s.file("plain");
  CHECK(contains(check("--out", file + "/x.h5", {}, false), "is not a directory"));
  if (getuid() != 0) {  // root writes into read-only directories
    fs::create_directories(s.path("ro"));
    fs::permissions(s.path("ro"), fs::perms::owner_read | fs::perms::owner_exec);
    CHECK(contains(check("--out", s.path("ro/x.h5"), {}, false), "Permission denied"));
    fs::permissions(s.path("ro"), fs::perms::owner_all);
  }
}

TEST_CASE("two outputs naming one file are refused; directory outputs may exist as directories only") {
  Scratch s;
  const std::vector<io::OutputPath> same = {{"--csv", s.path("t.csv")}, {"--plot", s.path("./t.csv")}};
  CHECK(contains(error_of([&] { io::check_output_paths(same, {}, true); }), "is also given as --csv"));
  const std::string file = s.file("seas");
  const std::vector<io::OutputPath> dirs = {{"--seas", file, io::OutputPath::Kind::directory}};
  CHECK(contains(error_of([&] { io::check_output_paths(dirs, {}, true); }), "exists and is not a directory"));
  const std::vector<io::OutputPath> ok = {{"--seas", s.dir.string(), io::OutputPath::Kind::directory},
                                          {"--figures", s.path("new_dir"), io::OutputPath::Kind::directory}};
  CHECK(error_of([&] { io::check_output_paths(ok, {}, false); }) == "<no error>");
}

TEST_CASE("the message is one line however the path is spelled") {
  Scratch s;
  const std::string weird = s.file(std::string("a\nb\x01") + std::string(240, 'c'));
  const std::string e = check("--csv", weird, {}, false);
  CHECK(e.find('\n') == std::string::npos);
  CHECK(e.size() <= 400);
  CHECK(contains(e, "a\\nb\\x01ccc"));  // escaped, and the path shortened
  CHECK(contains(e, " bytes omitted] ... "));
  CHECK(contains(e, "already exists"));
}

TEST_CASE("files of a directory output that does not exist yet are accepted (the command creates it)") {
  Scratch s;
  const std::vector<io::OutputPath> outputs = {{"--out-dir", s.path("analysis"), io::OutputPath::Kind::directory},
                                               {"--out-dir summary.json", s.path("analysis/summary.json")}};
  CHECK(error_of([&] { io::check_output_paths(outputs, {}, false); }) == "<no error>");
  CHECK_FALSE(std::filesystem::exists(s.path("analysis")));
}

TEST_CASE("a FIFO that no process reads is refused at once, never waited on") {
  // An open for writing of a FIFO without a reader blocks until one comes: the
  // check would hang for ever instead of refusing.
  Scratch s;
  const std::string fifo = s.path("fifo");
  REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
  CHECK(contains(check("--out", fifo, {}, false), "already exists"));
  const std::string e = check("--out", fifo, {}, true);
  CHECK(contains(e, "--out '"));
  CHECK(contains(e, "is a FIFO that no process reads"));
}

TEST_CASE("what is at a path that is not a regular file is said, not 'does not exist'") {
  // A restart point or run file that was a directory or a link to /dev/zero
  // was reported as missing.
  Scratch s;
  CHECK(io::not_a_regular_file(s.file("a.h5")) == "");
  CHECK(io::not_a_regular_file(s.path("missing")) == "does not exist");
  CHECK(io::not_a_regular_file(s.dir.string()) == "is not a regular file (a directory)");
  fs::create_symlink("/dev/zero", s.path("zero"));
  CHECK(io::not_a_regular_file(s.path("zero")) == "is not a regular file (a character device)");
  REQUIRE(::mkfifo(s.path("fifo").c_str(), 0644) == 0);
  CHECK(io::not_a_regular_file(s.path("fifo")) == "is not a regular file (a FIFO)");
  fs::create_symlink(s.path("nowhere/x"), s.path("dangling"));
  const std::string d = io::not_a_regular_file(s.path("dangling"));
  CHECK(contains(d, "is a symbolic link to '"));
  CHECK(contains(d, "nowhere/x', which does not exist"));
}
