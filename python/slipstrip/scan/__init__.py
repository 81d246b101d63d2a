"""Parameter scans: many `slipstrip run`s of one base config, on this machine
(a concurrent.futures pool), on a Dask cluster, or as a Slurm job array, with
one summary table per scan.  File format, commands and output layout:
docs/scans.md.

    python3 -m slipstrip scan configs/scans/fig3c_heights.toml --jobs 2

Modules:
  spec.py       the scan file: parsing, checks, expansion into runs, dry run
  task.py       one run: the solver (resumed from its restart point when it
                can be, else run again), events and analysis in-process, the row;
                its docstring says why each run is a solver process
  executors.py  local pool, Dask, Slurm job array
  stopping.py   SIGINT/SIGTERM of a scan (forwarded to its solvers), one lock per run file
  summary.py    summary.csv / summary.h5, `collect`, the duration plot
  cli.py        the command line
"""
from .cli import main
from .executors import Progress, emit_slurm, plan, run_dask, run_local, run_scan
from .spec import (Parameter, RunTask, ScanSpec, check_runs, dry_run_lines, expand_runs, format_override, invalid_runs, load_scan,
                   run_file_name)
from .summary import (STATUS_COLUMNS, SUMMARY_CSV, SUMMARY_H5, TRAILING_COLUMNS, collect, duration_pdf,
                      height_round_trip_time, plot_duration_pdfs, read_summary, table_columns, write_summary)
from .stopping import RunBusy, RunLock, ScanInterrupted, StopSignals, lock_path
from .task import (ANALYSIS_KEYS, execute_task, find_binary, has_restart_point, is_completed,
                   kernel_cache_override, restart_point, summarize_run_file, task_payload)

__all__ = [
    "ANALYSIS_KEYS", "check_runs", "Parameter", "Progress", "RunTask", "STATUS_COLUMNS", "SUMMARY_CSV", "SUMMARY_H5",
    "ScanSpec", "TRAILING_COLUMNS", "collect", "dry_run_lines", "duration_pdf", "emit_slurm", "execute_task",
    "expand_runs", "find_binary", "format_override", "has_restart_point", "height_round_trip_time", "invalid_runs",
    "is_completed", "kernel_cache_override", "load_scan", "lock_path", "RunBusy", "RunLock", "ScanInterrupted",
    "StopSignals", "main", "plan", "plot_duration_pdfs", "read_summary",
    "restart_point", "run_dask", "run_file_name", "run_local", "run_scan", "summarize_run_file",
    "table_columns", "task_payload", "write_summary",
]
