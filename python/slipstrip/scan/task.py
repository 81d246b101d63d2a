"""One run of a scan: the solver, the restart-or-rerun decision, events, analysis, the row.

`execute_task(payload)` is what every executor calls (local pool, Dask
worker, Slurm array task); a payload is plain data (task_payload), so it
pickles to a Dask worker and is stored as JSON for Slurm.

Why each run is a solver process (`slipstrip run`), not a bindings call in
this process (slipstrip.run / slipstrip.resume):

  * SIGTERM: Slurm ends a task at its time limit (and on scancel) with
    SIGTERM.  The CLI's own handler stops the run at a whole step, writes a
    restart point and the status "interrupted", and exits 143; a relaunched
    scan then resumes the run (`has_restart_point` below).  A Python process
    ends on SIGTERM without any of that: the bindings stop a run cleanly only
    when an interpreter signal handler raises (SIGINT -> KeyboardInterrupt),
    and a SIGTERM handler of our own would have to redo the CLI's handling
    (set-up cancelled, exit 143) in Python.
  * crashes: a solver that dies (abort in a library, the kernel's OOM
    killer, a segfault) takes only its own run down; the row says so and
    the other runs go on.  In-process, it would end the whole scan.
  * OpenMP threads: each run gets OMP_NUM_THREADS (the cores shared between
    concurrent runs).  The OpenMP runtime reads it once per process, so
    concurrent in-process runs could not each have their own count.
  * the CLI's checks before a run: resource limits (--max-memory-gib,
    --max-steps, --max-output-gib), the free-disk warning, and for --resume
    that the scan's config and overrides still resolve to the run's stored
    config (refused with exit 2: the run is done again).  The bindings' run()
    has none of these.
  * the exit code is the outcome (0 completed, 2 bad input, 3 diverged,
    4 disk full, 143 interrupted) and the solver's stderr the message, both
    kept in the row.

A ProcessPoolExecutor worker calling the bindings would give the isolation
and the thread count, but not the SIGTERM handling, the checks or the exit
codes, and would cost an interpreter per run; and on Ctrl-C its idle workers
die with the pool (BrokenProcessPool).  So the process is the solver itself,
and the executors (executors.py) run this function
in threads of concurrent.futures (each waits on its solver, the GIL is free
meanwhile), in Dask workers, or once per Slurm array task.  Everything after
the run is in-process through the bindings and the package: event detection
(analysis.run_event_detection, the C++ detector of `slipstrip events`) and
the analysis (analysis.summarize_run).
"""
from __future__ import annotations

import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from .. import runfile
from .spec import RunTask
from .stopping import RunBusy, RunLock, exit_code, never_stop, signal_name

REPO = Path(__file__).resolve().parents[3]

# Keys of analysis.summarize_run() (docs/analysis.md), in table order.
ANALYSIS_KEYS = (
    "n_events",
    "small_exponent_u",
    "small_exponent_u_err",
    "lognormal_mu",
    "lognormal_sigma",
    "lognormal_ks_pvalue",
    "slip_fraction_spanning",
    "slip_fraction_small",
    "periodic_pulse",
    "n_events_large",
    "n_events_small",
)
MAX_ERROR_CHARS = 2000  # enough for the solver's one-line errors plus context; keeps the table readable


def find_binary() -> str:
    """$SLIPSTRIP_BIN, else `slipstrip` on PATH, else the newest build*/slipstrip of this repository."""
    explicit = os.environ.get("SLIPSTRIP_BIN")
    if explicit:
        return explicit
    on_path = shutil.which("slipstrip")
    if on_path:
        return on_path
    default = REPO / "build" / "slipstrip"
    if default.is_file():
        return str(default)
    candidates = sorted(REPO.glob("build*/slipstrip"), key=lambda p: p.stat().st_mtime)
    if candidates:
        return str(candidates[-1])
    raise FileNotFoundError("slipstrip binary not found: set SLIPSTRIP_BIN, put slipstrip on PATH, "
                            f"or build it in {REPO / 'build'}")


def is_completed(run_file: str | os.PathLike) -> bool:
    return runfile.read_status(run_file) == "completed"


def restart_point(run_file: Path) -> Path:
    """The solver's restart point of a run file (docs/output.md): RUN.h5.restart."""
    return run_file.with_name(run_file.name + ".restart")


def has_restart_point(run_file: Path) -> bool:
    """An interrupted run that `slipstrip run --resume` can continue."""
    return restart_point(run_file).is_file() and runfile.read_status(run_file) not in (None, "completed")


def kernel_cache_override(overrides, directory) -> list[str]:
    """Runs of a scan share one strip-kernel cache (kernels/kernel_cache.hpp),
    so kernels that several runs need (same material, H, L, N, dt) are
    computed once.  A scan file that sets output.kernel_cache itself wins."""
    if any(o.split("=", 1)[0].strip() == "output.kernel_cache" for o in overrides):
        return []
    return ["--set", f'output.kernel_cache="{Path(directory).resolve() / "kernel_cache"}"']


def tail(text: str) -> str:
    """A message as one table cell: one line, at most MAX_ERROR_CHARS (the end, where the cause is)."""
    text = " | ".join(line.strip() for line in text.strip().splitlines() if line.strip())
    return text if len(text) <= MAX_ERROR_CHARS else "..." + text[-MAX_ERROR_CHARS:]


# --------------------------------------------------------------------------- records


def record_path(run_file: Path) -> Path:
    """The run's row as JSON next to its file (run_<index>.json)."""
    return run_file.with_suffix(".json")


def _json_default(value):
    if hasattr(value, "tolist"):  # numpy scalars and arrays
        return value.tolist()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    return str(value)


def write_json(path: Path, data) -> None:
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(json.dumps(data, indent=1, default=_json_default))
    os.replace(tmp, path)  # a record is either absent or complete, even if the scan is killed


def read_record(task: RunTask) -> dict | None:
    try:
        return json.loads(record_path(task.run_file).read_text())
    except (OSError, json.JSONDecodeError):  # absent or unreadable: as if never analysed
        return None


def previous_row(task: RunTask) -> dict | None:
    """The stored row of a finished run whose overrides are this task's, else None."""
    record = read_record(task)
    if record is None or record.get("overrides") != list(task.overrides) or record.get("status") != "completed":
        return None
    record.pop("overrides")
    record.pop("analysis_details", None)
    return record


# --------------------------------------------------------------------------- analysis of one run


def summarize_run_file(run_file: str | os.PathLike, summarizer: Callable | None = None) -> dict:
    """The analysis columns of one completed run (with /events): every key of
    ANALYSIS_KEYS, NaN where the analysis is missing or failed, plus
    `analysis_error` ("" on success).  n_events falls back to the catalog's own
    count when the analysis does not give it."""
    row = {k: math.nan for k in ANALYSIS_KEYS}
    row["analysis_error"] = ""
    try:
        if summarizer is None:
            from ..analysis import summarize_run as summarizer
        result = dict(summarizer(str(run_file)))
        for key, value in result.items():
            if hasattr(value, "item") and getattr(value, "ndim", 1) == 0:
                value = value.item()  # numpy scalar -> Python, so JSON and the table keep its type
            # The table holds scalars; nested diagnostics stay in the run's JSON record.
            if value is None or isinstance(value, (bool, int, float, str)):
                row[key] = value
            elif key in ANALYSIS_KEYS:
                row[key] = str(value)
            else:
                row.setdefault("analysis_details", {})[key] = value
    except Exception as e:  # any analysis failure is data for the table, not a reason to stop the scan
        row["analysis_error"] = tail(f"{type(e).__name__}: {e}")
    if not isinstance(row.get("n_events"), (int, float)) or \
            (isinstance(row["n_events"], float) and math.isnan(row["n_events"])):
        row["n_events"] = runfile.read_event_count(run_file)
    return row


# --------------------------------------------------------------------------- one run


def task_payload(task: RunTask, base_config: Path, binary: str, simulate: bool = True,
                 threads: int | None = None) -> dict:
    """What a worker needs, as plain data (pickles anywhere: Dask workers, JSON for Slurm)."""
    return {
        "index": task.index,
        "parameters": dict(task.parameters),
        "overrides": list(task.overrides),
        "run_file": str(task.run_file),
        "base_config": str(base_config),
        "binary": binary,
        "simulate": simulate,
        "threads": threads,
    }


# How often a running task looks for a stop request, and how long a solver
# that was told to stop may take to write its restart point before it is
# killed (the solver stops within about a second, solver/run.hpp; the rest is
# margin for a large restart point on a slow file system).
STOP_POLL_SECONDS = 0.25
STOP_GRACE_SECONDS = 60.0


def _run_solver(cmd: list[str], env: dict, stop_signal: Callable[[], int] = never_stop,
                lock: RunLock | None = None) -> tuple[int, str, str]:
    """Runs the solver to its end.  When stop_signal() turns non-zero (the scan
    got SIGINT or SIGTERM), that signal is sent to the solver, which writes its
    restart point, closes its file as "interrupted" and exits 128 + signal; we
    wait for that (at most STOP_GRACE_SECONDS) instead of killing it.  The
    solver inherits the run's lock, so the lock lasts as long as it runs."""
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                          pass_fds=(lock.fd,) if lock is not None else ()) as proc:
        if lock is not None:
            lock.note_holder(proc.pid)
        told_at = None
        while True:
            try:
                out, err = proc.communicate(timeout=STOP_POLL_SECONDS)
                return proc.returncode, out, err
            except subprocess.TimeoutExpired:
                pass  # still running: the output read so far is kept by communicate
            except KeyboardInterrupt:
                # No StopSignals around this call (a Python caller's own
                # loop): stop the solver cleanly, then let the caller stop.
                proc.send_signal(signal.SIGINT)
                try:
                    proc.wait(timeout=STOP_GRACE_SECONDS)
                except subprocess.TimeoutExpired:
                    proc.kill()
                raise
            signum = stop_signal()
            if signum and told_at is None:
                proc.send_signal(signum)
                told_at = time.monotonic()
            elif told_at is not None and time.monotonic() - told_at > STOP_GRACE_SECONDS:
                proc.kill()


@dataclass
class SolverOutcome:
    error: str  # "" if the solver exited 0, else the exit code and its message
    resumed: bool  # continued from a restart point (not run from t = 0)
    returncode: int | None  # the solver's exit code (None: no solver ran)


def _simulate(payload: dict, run_file: Path, binary: str, env: dict, stop_signal: Callable[[], int],
              lock: RunLock) -> SolverOutcome:
    """Runs (or resumes) the solver for this task."""
    cmd = [binary, "run", payload["base_config"]]
    for o in payload["overrides"]:
        cmd += ["--set", o]
    cmd += kernel_cache_override(payload["overrides"], run_file.parent)
    returncode = None
    resumed = False
    if has_restart_point(run_file):
        # An interrupted run of this scan (Ctrl-C, a Slurm time limit):
        # continue it from its restart point instead of redoing it.  The
        # config and overrides are passed only to be checked: the solver
        # refuses (exit 2) if they do not resolve to the run's stored config
        # (the scan file was edited) or the restart point is unusable, and
        # the run is then done again from t = 0.
        record_path(run_file).unlink(missing_ok=True)
        try:
            returncode, out, err = _run_solver(cmd + ["--resume", str(run_file), "--quiet"], env, stop_signal, lock)
        except OSError as e:
            returncode, out, err = -1, "", f"cannot start {binary}: {e}"
        resumed = returncode != 2
        if returncode == 2:
            print(f"[scan] run {payload['index']}: {run_file.name} cannot be resumed "
                  f"({tail(err or out)}); running it again", file=sys.stderr)
            returncode = None
    if returncode is None and not stop_signal():
        # A file of an earlier attempt must not outlive this one: if this run
        # fails before writing, an old "completed" file would pass for its result.
        run_file.unlink(missing_ok=True)
        restart_point(run_file).unlink(missing_ok=True)
        record_path(run_file).unlink(missing_ok=True)
        try:
            returncode, out, err = _run_solver(cmd + ["--out", str(run_file), "--quiet"], env, stop_signal, lock)
        except OSError as e:
            returncode, out, err = -1, "", f"cannot start {binary}: {e}"
    if returncode is None:  # stopped between a refused resume and the new start
        return SolverOutcome(f"not run again: stopped by {signal_name(stop_signal())}", False, None)
    if returncode != 0:
        return SolverOutcome(f"slipstrip run exited with code {returncode}: " + (tail(err or out) or "(no message)"),
                             resumed, returncode)
    return SolverOutcome("", resumed, returncode)


def _earlier_wall_time(payload: dict, run_file: Path) -> float:
    """Wall time [s] of the earlier parts of an interrupted run, from the row
    the scan stored when it was interrupted (0 if there is none: e.g. the part
    ran outside a scan, or the scan was killed before it could write the row)."""
    try:
        record = json.loads(record_path(run_file).read_text())
    except (OSError, json.JSONDecodeError):
        return 0.0
    if record.get("status") != "interrupted" or record.get("overrides") != list(payload["overrides"]):
        return 0.0
    value = record.get("wall_time_s")
    return float(value) if isinstance(value, (int, float)) and math.isfinite(value) else 0.0


def execute_task(payload: dict, stop_signal: Callable[[], int] = never_stop) -> dict | None:
    """Runs one scan task: `slipstrip run` (unless payload["simulate"] is False),
    event detection and the analysis (in-process); writes the row next to the
    run file as run_<index>.json and returns it.  Never raises for a failing
    run: the row says status "failed" and the error text.

    stop_signal() is polled while the solver runs (stopping.StopSignals, or
    the Dask scan's stop variable): once non-zero, the solver gets that
    signal and the row says "interrupted"; a task asked to stop before it
    starts returns None and touches nothing.  A run whose lock another
    process holds (stopping.RunLock) is left alone: status "busy", no row
    written to disk."""
    if stop_signal():
        return None
    run_file = Path(payload["run_file"])
    run_file.parent.mkdir(parents=True, exist_ok=True)
    row = {"index": payload["index"], **payload["parameters"],
           "status": "failed", "error": "", "wall_time_s": math.nan, "resumed": False}
    row.update({k: math.nan for k in ANALYSIS_KEYS})
    row["analysis_error"] = ""
    row["run_file"] = run_file.name
    try:
        with RunLock(run_file) as lock:
            _execute_locked(payload, run_file, row, stop_signal, lock)
    except RunBusy as e:
        row["status"] = "busy"
        row["error"] = (f"{run_file.name} is being written by another process ({e}; e.g. the solver of an "
                        "earlier scan that was killed and runs on): left alone; wait for that process to end "
                        "or stop it with `kill -TERM <pid>` (it writes a restart point), then relaunch")
    return row


def _execute_locked(payload: dict, run_file: Path, row: dict, stop_signal: Callable[[], int],
                    lock: RunLock) -> None:
    from ..analysis import run_event_detection

    stopped = False  # the solver ended on the scan's stop (maybe still in its set-up: then no file)
    if payload.get("simulate", True):
        env = dict(os.environ)
        if payload.get("threads"):
            env["OMP_NUM_THREADS"] = str(payload["threads"])
        earlier = _earlier_wall_time(payload, run_file)
        start = time.monotonic()
        outcome = _simulate(payload, run_file, payload.get("binary") or find_binary(), env, stop_signal, lock)
        # A resumed run's wall time counts every part the scan measured.
        row["wall_time_s"] = time.monotonic() - start + (earlier if outcome.resumed else 0.0)
        row["error"], row["resumed"] = outcome.error, outcome.resumed
        stopped = bool(stop_signal()) and outcome.returncode in (None, exit_code(stop_signal()))
    else:
        row["wall_time_s"] = runfile.wall_seconds(run_file)

    status = runfile.read_status(run_file)
    if status == "interrupted" or stopped:
        # Stopped by a signal (the scan's, forwarded, or one sent to the
        # solver itself): the restart point is kept and a relaunch resumes it.
        row["status"] = "interrupted"
        row["error"] = row["error"] or "run file status is 'interrupted'"
    elif not row["error"] and status != "completed":
        row["error"] = f"run file status is {status!r}" if status is not None else "no run file written"
    if not row["error"]:
        row["status"] = "completed"
        try:
            if payload.get("simulate", True) or not runfile.has_group(run_file, "events"):
                run_event_detection(run_file)  # the default alpha, as `slipstrip events`
            row.update(summarize_run_file(run_file))
        except Exception as e:
            row["analysis_error"] = tail(f"{type(e).__name__}: {e}")
    details = row.pop("analysis_details", None)
    record = dict(row, overrides=list(payload["overrides"]))
    if details:
        record["analysis_details"] = details
    write_json(record_path(run_file), record)


def execute_task_on_worker(payload: dict, stop_variable: str) -> dict | None:
    """execute_task in a Dask worker: the stop request is the scan's
    distributed.Variable `stop_variable` (0, or the signal the scan got)."""
    from distributed import Variable
    variable = Variable(stop_variable)
    return execute_task(payload, lambda: int(variable.get()))
