// Stations on a 2D interface (solver/stations.hpp): a station's value from
// row terms taken on separate slabs of rows (as the processes of a run split
// by rows take them, parallel/distributed_run.cpp) and combined equals
// sample() over the whole field bit for bit, for stations on nodes, between
// rows of two slabs and between the last row and row 0; the rows each term
// reads.  The run-level comparison (slipstrip-mpi against slipstrip) is
// tests/mpi/test_parallel_run.py.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "solver/stations.hpp"

using namespace slipstrip;

TEST_CASE("StationSampler2d: row terms from two slabs combine to sample() bit for bit") {
  constexpr std::size_t nx = 8, nz = 6;
  const double dx = 0.5, dz = 0.25;
  // On node (0, 0); between rows 2 and 3 (the two slabs below); between row
  // 5 and row 0 (the wrap); on row 2 (weight 0 along z: row 3 still read);
  // between the last column and column 0 inside the second slab.
  const std::vector<double> x = {0.0, 1.3, 2.75, 3.0, 7.5 * dx};
  const std::vector<double> z = {0.0, 2.4 * dz, 5.5 * dz, 2.0 * dz, 4.125 * dz};
  StationSampler2d sampler(x, z, dx, dz, nx, nz);
  REQUIRE(sampler.terms() == 2 * x.size());
  CHECK(sampler.term_row(0) == 0);
  CHECK(sampler.term_row(1) == 1);
  CHECK(sampler.term_row(2) == 2);
  CHECK(sampler.term_row(3) == 3);
  CHECK(sampler.term_row(4) == 5);
  CHECK(sampler.term_row(5) == 0);
  CHECK(sampler.term_row(6) == 2);
  CHECK(sampler.term_row(7) == 3);

  // A field with no structure to hide a wrong node behind.
  std::vector<double> field(nx * nz);
  for (std::size_t i = 0; i < field.size(); ++i) field[i] = std::sin(1.7 * static_cast<double>(i) + 0.3) * 1e-3;
  const auto whole = sampler.sample(field);
  const std::vector<double> expected(whole.begin(), whole.end());

  // Slabs: rows 0-2 and rows 3-5.
  const std::size_t split = 3;
  const std::span<const double> low(field.data(), split * nx), high(field.data() + split * nx, (nz - split) * nx);
  std::vector<double> terms(sampler.terms());
  for (std::size_t t = 0; t < sampler.terms(); ++t)
    terms[t] = sampler.term_row(t) < split ? sampler.row_term(low, 0, t) : sampler.row_term(high, split, t);
  for (std::size_t s = 0; s < x.size(); ++s) {
    CAPTURE(s);
    const double value = sampler.combine(s, terms[2 * s], terms[2 * s + 1]);
    CHECK(std::bit_cast<std::uint64_t>(value) == std::bit_cast<std::uint64_t>(expected[s]));
  }
  // On a node: the node's value.
  CHECK(expected[0] == field[0]);
  CHECK(expected[3] == field[2 * nx + 6]);
}
