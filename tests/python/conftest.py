"""Shared fixtures of the Python tests.

The package is imported in-tree from python/slipstrip/ (the _slipstrip module
is built there by `cmake --build <dir> --target _slipstrip`).  The CLI binary,
used as an independent entry point to the same C++ code, is looked up in
  $SLIPSTRIP_BUILD_DIR, else <repo>/build, else the newest <repo>/build*/
holding a `slipstrip` executable.

Run: /usr/bin/python3 -m pytest tests/python
"""
import os
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
PYTHON_DIR = REPO / "python"
if str(PYTHON_DIR) not in sys.path:
    sys.path.insert(0, str(PYTHON_DIR))


def _find_build_dir():
    explicit = os.environ.get("SLIPSTRIP_BUILD_DIR")
    if explicit:
        return Path(explicit)
    default = REPO / "build"
    if (default / "slipstrip").is_file():
        return default
    candidates = [p.parent for p in REPO.glob("build*/slipstrip") if p.is_file()]
    if not candidates:
        return None
    return max(candidates, key=lambda d: (d / "slipstrip").stat().st_mtime)


@pytest.fixture(scope="session")
def repo():
    return REPO


@pytest.fixture(scope="session")
def build_dir():
    d = _find_build_dir()
    if d is None:
        pytest.skip("no build directory with the slipstrip CLI (set SLIPSTRIP_BUILD_DIR)")
    return d


@pytest.fixture(scope="session")
def cli(build_dir):
    exe = build_dir / "slipstrip"
    if not exe.is_file():
        pytest.skip(f"{exe} not built (cmake --build {build_dir} --target slipstrip)")
    return exe


@pytest.fixture(scope="session")
def slipstrip_module():
    """The in-tree package; skips (with the build command) if _slipstrip is not built."""
    try:
        import slipstrip
    except ImportError as e:
        pytest.skip(f"slipstrip Python module not importable ({e}); build it with "
                    "cmake -S . -B build-python -DSLIPSTRIP_PYTHON=ON && "
                    "cmake --build build-python --target _slipstrip -j1")
    return slipstrip


@pytest.fixture(autouse=True, scope="session")
def _sigint_raises_keyboard_interrupt():
    """Tests that send SIGINT to this process expect KeyboardInterrupt.  A
    shell starts background jobs (CI runners, `cmd &`) with SIGINT ignored, and
    Python then installs no handler: the signal would be dropped and such a test
    would wait forever.  Install Python's default handler for the session."""
    import signal
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)
