#!/usr/bin/env bash
# The test suite, in two tiers (docs/developing.md, "Test tiers"):
#   scripts/test.sh         the fast tier: every physics verification (kernels,
#                           growth rates, Lc, convergence at its default size),
#                           config, output, CLI and Python API tests.
#   scripts/test.sh --all   the whole suite: the fast tier plus the cases
#                           labelled "slow" (doctest suite "slow", pytest marker
#                           "slow": the fuzz corpus, pip and CMake install builds,
#                           long convergence studies).  .ci/run uses this.
# Builds first if needed.
set -euo pipefail
cd "$(dirname "$0")/.."
tier=fast
case "${1:-}" in
  "") ;;
  --all) tier=all ;;
  *) echo "usage: scripts/test.sh [--all]  (got '$1')" >&2; exit 2 ;;
esac
[ -x build/slipstrip ] || bash scripts/setup.sh
cmake --build build -j "$(nproc)"
export SLIPSTRIP_BUILD_DIR="$PWD/build" SLIPSTRIP_BIN="$PWD/build/slipstrip" PYTHONPATH="$PWD/python"
# Test problems are small, and ctest/pytest may run solver processes side by
# side: one OpenMP thread each avoids oversubscribed (spin-waiting) threads,
# which were measured ~10x slower on a 2-core machine.
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"
# A test that starts two threads lets the idle one sleep rather than spin:
# spinning on shared cores was most of such a test's CPU time (measured
# 44.8 s against 4.2 s for the one- and two-thread bitwise test).  The wait
# policy does not enter the arithmetic.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
jobs=$(nproc)
if [ "$tier" = all ]; then
  for t in build/test_*; do [ -x "$t" ] && "$t" -ts=slow; done
  pytest_args=()
else
  pytest_args=(-m "not slow")
fi
# pytest-xdist (Debian: python3-pytest-xdist, installed by scripts/setup.sh)
# spreads the Python tests over the cores; without it they run one at a time.
if /usr/bin/python3 -c "import xdist" 2> /dev/null; then
  pytest_args+=(-n "$jobs")
else
  echo "scripts/test.sh: pytest-xdist is not installed (apt-get install python3-pytest-xdist);" \
       "the Python tests run one at a time" >&2
fi
# ctest and pytest side by side, so that neither one's longest test leaves a
# core idle; ctest's report is printed when both have finished.
ctest_log=$(mktemp)
trap 'rm -f "$ctest_log"' EXIT
(cd build && ctest --output-on-failure -j "$jobs") > "$ctest_log" 2>&1 &
ctest_pid=$!
pytest_status=0
/usr/bin/python3 -m pytest -q "${pytest_args[@]}" tests/python || pytest_status=$?
ctest_status=0
wait "$ctest_pid" || ctest_status=$?
cat "$ctest_log"
echo "scripts/test.sh: ctest exit $ctest_status, pytest exit $pytest_status"
[ "$ctest_status" -eq 0 ] && [ "$pytest_status" -eq 0 ]
