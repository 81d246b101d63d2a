#!/usr/bin/env bash
# Install slipstrip's dependencies from Debian's archive (idempotent), then
# configure and build everything (C++ library, CLI, tests, Python module) in
# ./build.  Works on a fresh Debian 12 machine; run as root or with sudo.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config git
          libfftw3-dev libeigen3-dev libhdf5-dev doctest-dev pybind11-dev
          libtomlplusplus-dev libcli11-dev libxsimd-dev
          python3 python3-dev python3-numpy python3-scipy python3-h5py
          python3-matplotlib python3-pytest python3-pytest-xdist python3-dask python3-distributed
          python3-pip python3-setuptools python3-venv)
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "installing: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
fi

# Debian's interpreter: the pybind11 module must match it (a pyenv python3
# first on PATH cannot see Debian's numpy/h5py).
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSLIPSTRIP_PYTHON=ON \
      -DPython3_EXECUTABLE=/usr/bin/python3 > build-configure.log
cmake --build build -j "$(nproc)"

# "Install" in place (like pip's editable install, without pip): Debian's
# python3 finds the package through a .pth file, and the CLI is linked onto
# PATH.  Both point into this checkout, so a rebuild is picked up at once.
site_dir=$(/usr/bin/python3 -c "import site; print(site.getsitepackages()[0])")
$SUDO mkdir -p "$site_dir" /usr/local/bin
echo "$PWD/python" | $SUDO tee "$site_dir/slipstrip.pth" > /dev/null
$SUDO ln -sf "$PWD/build/slipstrip" /usr/local/bin/slipstrip
echo "built build/slipstrip (linked as /usr/local/bin/slipstrip) and the Python package"
echo "python/slipstrip (importable by /usr/bin/python3 via $site_dir/slipstrip.pth)"
