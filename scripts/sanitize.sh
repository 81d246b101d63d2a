#!/usr/bin/env bash
# C++ tests under AddressSanitizer + UndefinedBehaviorSanitizer (a fast subset:
# the kernels, history operators, friction, config, output and event code the
# time loop and the CLI use).  Separate build directory build-asan/.  Any
# report aborts the test (halt_on_error), so ctest's summary is the verdict.
set -euo pipefail
cd "$(dirname "$0")/.."
tests=(test_kernels_nufft test_kernels_block_history test_kernels_time_domain test_kernels_cache
       test_solver_history_algorithms test_config_parsing test_solver_run_output test_solver_reliability
       test_solver_free_interface test_friction_batch_solve test_friction_local_solve test_friction_laws
       test_events_detection test_events_io)
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSLIPSTRIP_SANITIZE=ON -DSLIPSTRIP_NATIVE=OFF \
      -DSLIPSTRIP_PYTHON=OFF -DSLIPSTRIP_TOOLS=OFF > build-asan-configure.log
cmake --build build-asan -j "$(nproc)" --target "${tests[@]}"
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:abort_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"
regex="^($(IFS='|'; echo "${tests[*]}"))\$"
# -j: the tests are independent (the fast tier runs them side by side too).
(cd build-asan && ctest --output-on-failure -j "$(nproc)" -R "$regex")
