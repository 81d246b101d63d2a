// The HDF5 kernel cache returns exactly the kernels it was given, is keyed by
// every input (a change of any input is a miss), and the history operator
// built from cached kernels behaves bit for bit like the computed one.
#include <doctest/doctest.h>
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
  const std::string path = temp_path("kernels.h5");
  std::filesystem::remove(path);
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
  std::filesystem::remove(path);
}

TEST_CASE("kernel cache: a file that is not HDF5 is a clear error") {
  const std::string path = temp_path("not_hdf5.h5");
  std::ofstream(path) << "hello";
  ElasticMaterial m;
  const double dt = strip_time_step(m, 0.05, 0.8 / 64, 0.25);
  CHECK_THROWS_WITH_AS(load_or_compute_strip_kernels(path, m, 0.05, 0.8, 64, dt),
                       doctest::Contains("is not an HDF5 file"), std::invalid_argument);
  std::filesystem::remove(path);
}
