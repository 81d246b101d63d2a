"""`cmake --install` gives a working CMake package: a tiny C++ program
(tests/install/) finds it with find_package(slipstrip), links slipstrip::solver
and runs ten steps; the installed CLI runs too."""
import os
import subprocess
from pathlib import Path

import pytest

# Minutes long: run by scripts/test.sh --all and .ci/run, not the fast tier.
pytestmark = pytest.mark.slow

REPO = Path(__file__).resolve().parents[2]


def build_dir() -> Path:
    return Path(os.environ.get("SLIPSTRIP_BUILD_DIR", REPO / "build"))


@pytest.mark.skipif(not (build_dir() / "CMakeCache.txt").exists(), reason="no configured build directory")
def test_installed_package_is_found_and_linked(tmp_path):
    prefix = tmp_path / "prefix"
    subprocess.run(["cmake", "--install", str(build_dir()), "--prefix", str(prefix)], check=True,
                   capture_output=True, text=True)
    assert (prefix / "bin" / "slipstrip").exists()
    assert (prefix / "include" / "slipstrip" / "solver" / "simulation.hpp").exists()
    assert list(prefix.glob("lib*/cmake/slipstrip/slipstripConfig.cmake"))
    version = subprocess.run([str(prefix / "bin" / "slipstrip"), "--version"], capture_output=True, text=True)
    assert version.returncode == 0 and version.stdout.startswith("0.")

    consumer = tmp_path / "consumer-build"
    configure = subprocess.run(["cmake", "-S", str(REPO / "tests" / "install"), "-B", str(consumer),
                                f"-DCMAKE_PREFIX_PATH={prefix}", "-DCMAKE_BUILD_TYPE=Release"],
                               capture_output=True, text=True)
    assert configure.returncode == 0, configure.stdout + configure.stderr
    build = subprocess.run(["cmake", "--build", str(consumer), "-j2"], capture_output=True, text=True)
    assert build.returncode == 0, build.stdout + build.stderr
    run = subprocess.run([str(consumer / "consumer")], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    fields = run.stdout.split()
    assert fields[0] == "dt" and float(fields[1]) > 0
    assert fields[2] == "max_slip_rate" and float(fields[3]) > 0
