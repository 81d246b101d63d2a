"""`python3 -m slipstrip scan` (and the C++ `slipstrip scan`, which starts it):
the command line of parameter scans (docs/scans.md)."""
from __future__ import annotations

import argparse
import json
import signal
import sys
from pathlib import Path

from ..paths import check_outputs, one_line
from .executors import emit_slurm, run_scan
from .spec import check_runs, dry_run_lines, expand_runs, load_scan
from .stopping import ScanInterrupted, StopSignals, exit_code
from .summary import SUMMARY_CSV, SUMMARY_H5, collect, plot_duration_pdfs
from .task import execute_task, find_binary


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="slipstrip scan",
        description="Run a parameter scan of slipstrip runs (docs/scans.md).")
    p.add_argument("scan", nargs="?", help="scan file (TOML)")
    p.add_argument("--jobs", "-j", type=int, default=1, help="concurrent runs on this machine (default 1)")
    p.add_argument("--dask", metavar="ADDRESS", help="run on a dask.distributed scheduler, e.g. tcp://host:8786")
    p.add_argument("--emit-slurm", metavar="DIR", help="write a Slurm job array into DIR instead of running")
    p.add_argument("--slurm-time", metavar="HH:MM:SS", help="--time of each Slurm task")
    p.add_argument("--out", metavar="DIR", help="output directory (overrides the scan file's output_dir)")
    p.add_argument("--binary", metavar="PATH", help="slipstrip binary (default: $SLIPSTRIP_BIN, PATH, build/)")
    p.add_argument("--dry-run", action="store_true", help="list the runs and their overrides and check every run's config, run nothing "
                        "(exit 2 if a config is invalid)")
    p.add_argument("--collect", action="store_true",
                   help="only write the summary of the runs on disk (after a Slurm array)")
    p.add_argument("--plot-durations", metavar="PNG", help="afterwards, plot p(T) of every run (Fig. 3d style)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing --plot-durations file")
    p.add_argument("--run-task", metavar="TASK_JSON", help="run one task file written by --emit-slurm")
    return p


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.run_task:
            payload = json.loads(Path(args.run_task).read_text())
            payload["binary"] = args.binary or payload.get("binary") or find_binary()
            # A Slurm time limit or scancel sends SIGTERM: forwarded to the solver (restart point, 143).
            with StopSignals(sys.stderr) as stop:
                row = execute_task(payload, stop)
            if row is not None:
                print(f"[scan] run {row['index']}: {row['status']} {row['error']}".rstrip(), file=sys.stderr)
            if stop():
                return exit_code(stop())
            return 0 if row["status"] == "completed" else 1
        if not args.scan:
            print("error: a scan file is required (slipstrip scan SCAN.toml ...)", file=sys.stderr)
            return 2
        spec = load_scan(args.scan, args.out)
        # The run files and summaries in the output directory are the scan's own
        # state (resumed or redone on a relaunch, docs/scans.md); the rule
        # covers what the user names.
        check_outputs({"--plot-durations": args.plot_durations},
                      directories={"output directory": spec.output_dir, "--emit-slurm": args.emit_slurm},
                      inputs=[spec.path, spec.base_config],
                      overwrite=args.overwrite)
        if args.dry_run:
            print("\n".join(dry_run_lines(spec)))
            errors, warnings = check_runs(spec)
            for line in warnings:
                print(f"warning: {line}", file=sys.stderr)
            for line in errors:
                print(f"error: {line}", file=sys.stderr)
            if errors:
                print(f"error: {len(errors)} of {len(expand_runs(spec))} runs have an invalid config "
                      "(fix the scan file's [fixed] or [[parameter]] entries)", file=sys.stderr)
                return 2
            print(f"all {len(expand_runs(spec))} run configs are valid", file=sys.stderr)
            return 0
        if args.emit_slurm:
            script = emit_slurm(spec, args.emit_slurm, binary=args.binary, time_limit=args.slurm_time)
            n = len(expand_runs(spec))
            print(f"wrote {script} ({n} array tasks); submit with: sbatch {script} "
                  f"(or {script.parent / 'submit.sh'} to also write the summary afterwards)")
            return 0
        if args.collect:
            rows = collect(spec, binary=args.binary)
        else:
            rows = run_scan(spec, jobs=args.jobs, dask_address=args.dask, binary=args.binary)
        print(f"summary: {spec.output_dir / SUMMARY_CSV}, {spec.output_dir / SUMMARY_H5}", file=sys.stderr)
        if args.plot_durations:
            print(f"plot: {plot_duration_pdfs(spec.output_dir, args.plot_durations)}", file=sys.stderr)
        n_failed = sum(r["status"] != "completed" for r in rows)
        return 0 if n_failed == 0 else 1
    except ScanInterrupted as e:
        print(f"summary: {spec.output_dir / SUMMARY_CSV}, {spec.output_dir / SUMMARY_H5}", file=sys.stderr)
        print(f"[scan] {e}", file=sys.stderr)
        return exit_code(e.signal)
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {one_line(e)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # before the runs start (reading the scan file)
        print("interrupted before any run started", file=sys.stderr)
        return exit_code(signal.SIGINT)
