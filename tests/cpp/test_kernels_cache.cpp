// The HDF5 kernel cache returns exactly the kernels it was given, is keyed by
// every input (a change of any input is a miss), and the history operator
// built from cached kernels behaves bit for bit like the computed one.
#include <doctest/doctest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <complex>
#include <filesystem>
#include <fstream>

#include "kernels/kernel_cache.hpp"

using namespace slipstrip;

namespace {
std::string temp_path(const char* name) {
  return (std::filesystem::temp_directory_path() /
          (std::string("slipstrip_") + std::to_string(getpid()) + "_" + name))
      .string();
}
}  // namespace

TEST_CASE("kernel cache: round trip, keyed by every input, identical operator") {
  const std::string path = temp_path("kernel_cache");
  std::filesystem::remove_all(path);
  ElasticMaterial m;
  const double H = 0.05, L = 0.8, dx = L / 64;
  const double dt = strip_time_step(m, H, dx, 0.25);

  KernelSource source;
  const auto first = load_or_compute_strip_kernels(path, m, H, L, 64, dt, &source);
  CHECK(source == KernelSource::computed);
  const auto second = load_or_compute_strip_kernels(path, m, H, L, 64, dt, &source);
  CHECK(source == KernelSource::cache);
  const auto direct = compute_strip_kernels(m, H, L, 64, dt);
  CHECK(second.echo_steps == direct.echo_steps);
  CHECK(second.first_oscillator == direct.first_oscillator);
  CHECK(second.phase == direct.phase);    // exact: doubles stored as doubles
  CHECK(second.weight == direct.weight);
  CHECK(first.weight == direct.weight);

  // Any changed input is a miss (and then a new entry).
  auto other = m;
  other.poisson_ratio = 0.25;
  load_or_compute_strip_kernels(path, other, H, L, 64, dt, &source);
  CHECK(source == KernelSource::computed);
  other = m;
  other.plane = PlaneCondition::stress;
  load_or_compute_strip_kernels(path, other, H, L, 64, dt, &source);
  CHECK(source == KernelSource::computed);
  const double dt128 = strip_time_step(m, H, L / 128, 0.25);
  load_or_compute_strip_kernels(path, m, H, L, 128, dt128, &source);
  CHECK(source == KernelSource::computed);
  load_or_compute_strip_kernels(path, m, H, L, 64, strip_time_step(m, H, dx, 0.2), &source);
  CHECK(source == KernelSource::computed);
  load_or_compute_strip_kernels(path, m, H, L * 1.5, 64, dt, &source);
  CHECK(source == KernelSource::computed);
  // ... and the first entry is still served.
  load_or_compute_strip_kernels(path, m, H, L, 64, dt, &source);
  CHECK(source == KernelSource::cache);

  // Operators from cached and computed kernels give identical histories.
  StripHistory a(m, second), b(m, H, L, 64, dt);
  std::vector<std::complex<double>> v(33);
  for (int n = 0; n < 200; ++n) {
    for (int q = 0; q < 33; ++q) v[q] = {std::sin(0.1 * n + q), std::cos(0.03 * n * q)};
    a.push(v);
    b.push(v);
    for (int q = 0; q < 33; ++q) REQUIRE(a.history()[q] == b.history()[q]);
  }
  // One file per entry, no partial files left behind.
  int entries = 0;
  for (const auto& f : std::filesystem::directory_iterator(path)) {
    CHECK(f.path().extension() == ".h5");
    ++entries;
  }
  CHECK(entries == 6);  // base, nu, plane, N, dt, L
  std::filesystem::remove_all(path);
}

TEST_CASE("kernel cache: an entry that is not HDF5 is a clear error; so is an unusable directory") {
  const std::string dir = temp_path("bad_cache");
  std::filesystem::remove_all(dir);
  ElasticMaterial m;
  const double dt = strip_time_step(m, 0.05, 0.8 / 64, 0.25);
  load_or_compute_strip_kernels(dir, m, 0.05, 0.8, 64, dt);  // creates the entry
  for (const auto& f : std::filesystem::directory_iterator(dir)) std::ofstream(f.path()) << "hello";
  CHECK_THROWS_WITH_AS(load_or_compute_strip_kernels(dir, m, 0.05, 0.8, 64, dt),
                       doctest::Contains("is not an HDF5 file"), std::invalid_argument);
  std::filesystem::remove_all(dir);
  const std::string file_not_dir = temp_path("plain_file");
  std::ofstream(file_not_dir) << "x";
  CHECK_THROWS_WITH_AS(load_or_compute_strip_kernels(file_not_dir + "/sub", m, 0.05, 0.8, 64, dt),
                       doctest::Contains("output.kernel_cache"), std::invalid_argument);
  std::filesystem::remove(file_not_dir);
}

TEST_CASE("kernel cache: concurrent writers of the same entry never fail and leave one good entry") {
  const std::string dir = temp_path("race_cache");
  std::filesystem::remove_all(dir);
  ElasticMaterial m;
  const double dt = strip_time_step(m, 0.05, 0.8 / 64, 0.25);
  std::vector<pid_t> children;
  for (int c = 0; c < 6; ++c) {
    const pid_t pid = fork();
    if (pid == 0) {
      int status = 0;
      try {
        for (int i = 0; i < 20; ++i) load_or_compute_strip_kernels(dir, m, 0.05, 0.8, 64, dt);
      } catch (...) {
        status = 1;
      }
      _exit(status);
    }
    children.push_back(pid);
  }
  for (pid_t pid : children) {
    int status = -1;
    waitpid(pid, &status, 0);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
  }
  KernelSource source;
  const auto k = load_or_compute_strip_kernels(dir, m, 0.05, 0.8, 64, dt, &source);
  CHECK(source == KernelSource::cache);
  CHECK(k.weight == compute_strip_kernels(m, 0.05, 0.8, 64, dt).weight);
  std::filesystem::remove_all(dir);
}
