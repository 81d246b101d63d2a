#!/usr/bin/env bash
# Set up (scripts/setup.sh), run the small default config and plot it:
#   quickstart.h5                  the run file (HDF5, see docs/output.md)
#   quickstart_spacetime.png       log10(v/v0) over x/L and t c_s/L
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# --overwrite: rerunning the demo replaces its own output file.
build/slipstrip run configs/quickstart.toml --out quickstart.h5 --overwrite
build/slipstrip events quickstart.h5
PYTHONPATH=python /usr/bin/python3 -m slipstrip plot quickstart.h5 --out quickstart_spacetime.png --overwrite
echo "wrote quickstart.h5 and quickstart_spacetime.png"
