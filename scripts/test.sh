#!/usr/bin/env bash
# The whole test suite: C++ (doctest executables through ctest) and Python
# (pytest).  Builds first if needed.  Slow verification cases are labelled
# "slow" and excluded here; run them with scripts/test.sh --slow.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/slipstrip ] || bash scripts/setup.sh
cmake --build build -j "$(nproc)"
export SLIPSTRIP_BUILD_DIR="$PWD/build" SLIPSTRIP_BIN="$PWD/build/slipstrip" PYTHONPATH="$PWD/python"
# Test problems are small, and ctest/pytest may run solver processes side by
# side: one OpenMP thread each avoids oversubscribed (spin-waiting) threads,
# which were measured ~10x slower on this 2-core machine.
export OMP_NUM_THREADS="${OMP_NUM_THREADS:-1}"
if [ "${1:-}" = "--slow" ]; then
  for t in build/test_*; do [ -x "$t" ] && "$t" -ts=slow; done
fi
(cd build && ctest --output-on-failure)
/usr/bin/python3 -m pytest -q tests/python
