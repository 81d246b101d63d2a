// for_each_mode_in_parallel (kernels/mode_parallel.hpp): the set-up loop over
// Fourier modes of the half-space operators.  Every mode runs once, a
// cancellation stops the loop with SetupCancelled, a mode's error is returned
// as text, and only the calling thread polls the cancel check.
#include <doctest/doctest.h>
#include <omp.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "kernels/mode_parallel.hpp"

using namespace slipstrip;

TEST_CASE("every mode runs once and nothing is reported") {
  for (int threads : {1, 2, 4}) {
    omp_set_num_threads(threads);
    std::vector<std::atomic<int>> visits(50);
    const std::string failure =
        for_each_mode_in_parallel(1, 50, CancelCheck{}, "a test loop", [&](int q) { visits[q].fetch_add(1); });
    CHECK(failure.empty());
    CHECK(visits[0].load() == 0);  // the loop starts at `first`
    for (int q = 1; q < 50; ++q) CHECK(visits[q].load() == 1);
  }
}

TEST_CASE("a cancellation throws SetupCancelled naming the loop, and skips the rest") {
  // Each mode takes 1 ms, so that the calling thread takes modes of its own
  // (OpenMP does not promise it any) long before the others finish them all.
  omp_set_num_threads(2);
  std::atomic<int> ran{0};
  int polls = 0;
  try {
    for_each_mode_in_parallel(0, 1000, [&polls] { return ++polls > 2; }, "the test operator", [&](int) {
      ran.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    });
    FAIL("no SetupCancelled");
  } catch (const SetupCancelled& e) {
    CHECK(std::string(e.what()) == "set-up cancelled during the test operator");
  }
  CHECK(polls == 3);  // polled until it said so, then no more
  CHECK(ran.load() < 1000);
}

TEST_CASE("only the calling thread polls the cancel check") {
  omp_set_num_threads(4);
  const auto caller = std::this_thread::get_id();
  std::atomic<bool> other_thread_polled{false};
  const CancelCheck check = [&] {
    if (std::this_thread::get_id() != caller) other_thread_polled = true;
    return false;
  };
  for_each_mode_in_parallel(0, 200, check, "a test loop", [](int) {});
  CHECK_FALSE(other_thread_polled.load());
}

TEST_CASE("a mode's error is returned as text and the other modes still run") {
  omp_set_num_threads(2);
  std::vector<std::atomic<int>> visits(20);
  const std::string failure = for_each_mode_in_parallel(0, 20, CancelCheck{}, "a test loop", [&](int q) {
    visits[q].fetch_add(1);
    if (q == 7) throw std::invalid_argument("mode 7 has no passive correction");
  });
  CHECK(failure == "mode 7 has no passive correction");
  for (int q = 0; q < 20; ++q) CHECK(visits[q].load() == 1);
}
