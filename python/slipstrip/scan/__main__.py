"""python3 -m slipstrip.scan ... (what the Slurm scripts of `scan --emit-slurm` run)."""
import sys

from .cli import main

sys.exit(main(sys.argv[1:]))
