"""Builds the extension slipstrip._slipstrip with CMake, for
`pip install --no-build-isolation --no-deps .` (docs/python.md).

The module links the whole C++ core (FFTW, HDF5, toml++, OpenMP), whose
sources and dependencies are listed once, in CMakeLists.txt; so build_ext
configures that project with SLIPSTRIP_PYTHON=ON for the interpreter running
pip, builds only the `_slipstrip` target and copies the module to where
setuptools expects it.  The build directory (build/pip by default,
SLIPSTRIP_PIP_BUILD_DIR to change it) is kept, so reinstalling recompiles only
what changed.  SLIPSTRIP_NATIVE=OFF in the environment builds for portable
x86-64 instead of the building machine's CPU (see CMakeLists.txt).

Metadata is in pyproject.toml; the version is CMakeLists.txt's
project(VERSION), the one the C++ code reports.
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE_DIR = Path(__file__).resolve().parent


def project_version() -> str:
    text = (SOURCE_DIR / "CMakeLists.txt").read_text()
    match = re.search(r"project\(\s*slipstrip\s+VERSION\s+([0-9][0-9.]*)", text)
    if not match:
        raise RuntimeError("CMakeLists.txt has no project(slipstrip VERSION x.y.z)")
    return match.group(1)


class CMakeExtension(Extension):
    """An extension CMake builds: no sources for setuptools to compile."""

    def __init__(self, name: str, target: str):
        super().__init__(name, sources=[])
        self.target = target


class CMakeBuild(build_ext):
    def build_extension(self, ext: CMakeExtension) -> None:
        build_dir = Path(os.environ.get("SLIPSTRIP_PIP_BUILD_DIR", SOURCE_DIR / "build" / "pip")).resolve()
        module_dir = build_dir / "module"
        native = os.environ.get("SLIPSTRIP_NATIVE", "ON").upper()
        if native not in ("ON", "OFF"):
            raise RuntimeError(f"SLIPSTRIP_NATIVE must be ON or OFF, not {native!r}")
        configure = ["cmake", "-S", str(SOURCE_DIR), "-B", str(build_dir),
                     "-DCMAKE_BUILD_TYPE=Release",
                     "-DSLIPSTRIP_PYTHON=ON",
                     f"-DPython3_EXECUTABLE={sys.executable}",
                     f"-DSLIPSTRIP_NATIVE={native}",
                     f"-DSLIPSTRIP_PYTHON_MODULE_DIR={module_dir}",
                     # Only the module is built; the verification tools need
                     # not even be configured.
                     "-DSLIPSTRIP_TOOLS=OFF"]
        subprocess.run(configure, check=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(self.parallel or os.cpu_count() or 1)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", ext.target, "-j", jobs], check=True)

        built = sorted(module_dir.glob(ext.target + ".*.so")) or sorted(module_dir.glob(ext.target + ".so"))
        if len(built) != 1:
            raise RuntimeError(f"expected one {ext.target} module in {module_dir}, found {built}")
        destination = Path(self.get_ext_fullpath(ext.name))
        destination.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], destination)


# egg_info writes the package metadata here (not into python/); it must exist.
Path("build", "pip").mkdir(parents=True, exist_ok=True)

setup(
    version=project_version(),
    ext_modules=[CMakeExtension("slipstrip._slipstrip", target="_slipstrip")],
    cmdclass={"build_ext": CMakeBuild},
    # setuptools' own build tree next to CMake's, not in build/lib.* beside
    # the developer's CMake build.
    options={"build": {"build_base": str(Path("build") / "pip" / "setuptools")},
             "egg_info": {"egg_base": str(Path("build") / "pip")}},
)
