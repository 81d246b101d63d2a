"""Where a scan's runs execute: this machine (a concurrent.futures pool),
a Dask cluster, or a Slurm job array (written as scripts, submitted by the
user).  Every executor calls the same task.execute_task on plain-data
payloads; see task.py for why each run is a solver process.

    run_scan(spec, jobs=2)                      # local pool, then the summary
    run_scan(spec, dask_address="tcp://h:8786")  # Dask, then the summary
    emit_slurm(spec, "slurm/")                  # scan.sbatch, collect.sbatch, submit.sh
"""
from __future__ import annotations

import itertools
import math
import os
import shlex
import sys
import time
import uuid
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path
from typing import Callable, TextIO

from .spec import ScanSpec, expand_runs
from .stopping import ScanInterrupted, StopSignals, never_stop
from .summary import stream_of, write_summary
from .task import (execute_task, execute_task_on_worker, find_binary, is_completed, kernel_cache_override,
                   previous_row, read_record, task_payload, write_json)

# The package directory holding slipstrip/ (put on PYTHONPATH of Slurm tasks).
PACKAGE_PARENT = Path(__file__).resolve().parents[2]


class Progress:
    """Whole-scan progress on a stream: runs done / total, elapsed, ETA."""

    def __init__(self, total: int, stream: TextIO | None):
        self.total, self.stream = total, stream
        self.done = self.skipped = self.failed = self.interrupted = 0
        self.start = time.monotonic()

    def update(self, row: dict, skipped: bool = False) -> None:
        self.done += 1
        self.skipped += skipped
        status = row.get("status")
        self.interrupted += status == "interrupted"
        self.failed += status not in ("completed", "interrupted")
        if self.stream is None:
            return
        elapsed = time.monotonic() - self.start
        worked = self.done - self.skipped  # skipped runs took no time: leave them out of the rate
        remaining = self.total - self.done
        eta = elapsed / worked * remaining if worked else math.nan
        eta_text = "--" if math.isnan(eta) else f"{eta:.0f} s"
        note = f"run {row['index']} {status}"
        if skipped:
            note += " (skipped: already completed)"
        elif row.get("resumed"):
            note += " (resumed from its restart point)"
        interrupted = f", {self.interrupted} interrupted" if self.interrupted else ""
        print(f"[scan] {self.done}/{self.total} runs done, {self.failed} failed{interrupted}, {self.skipped} skipped; "
              f"elapsed {elapsed:.1f} s, ETA {eta_text}; {note}", file=self.stream, flush=True)


def plan(spec: ScanSpec, binary: str, threads: int | None = None, stream: TextIO | None = None):
    """Splits the scan into rows that are already done and payloads to execute.

    A run is finished when its file's status is "completed" (docs/output.md).
    A finished run with a matching stored row is not touched at all; one
    without a row (e.g. made by a Slurm task that died before the analysis) is
    only analysed; a finished file made with other overrides (the scan file
    was edited) is run again."""
    done, todo = [], []
    for task in expand_runs(spec):
        if is_completed(task.run_file):
            previous = previous_row(task)
            if previous is not None:
                done.append(previous)
                continue
            record = read_record(task)
            stale = record is not None and record.get("overrides") != list(task.overrides)
            if stale and stream is not None:
                print(f"[scan] run {task.index}: {task.run_file.name} was made with other overrides; running it again",
                      file=stream)
            todo.append(task_payload(task, spec.base_config, binary, simulate=stale, threads=threads))
        else:
            todo.append(task_payload(task, spec.base_config, binary, simulate=True, threads=threads))
    return done, todo


def run_scan(spec: ScanSpec, jobs: int = 1, dask_address: str | None = None, binary: str | None = None,
             stream: TextIO | None | str = "stderr") -> list[dict]:
    """Runs every unfinished run of the scan and writes the summary table
    (summary.csv, summary.h5 in the output directory).  Returns the rows in run order.

    While it runs, SIGINT and SIGTERM are the scan's (stopping.StopSignals,
    whatever the process inherited): no new run starts, the running solvers
    get the signal and write their restart points, the summary lists them
    as "interrupted", and ScanInterrupted is raised (`slipstrip scan` exits
    128 + signal)."""
    binary = binary or find_binary()
    stream = stream_of(stream)
    if jobs < 1:
        raise ValueError(f"jobs = {jobs} is not allowed: expected an integer >= 1")
    spec.output_dir.mkdir(parents=True, exist_ok=True)
    # Share the cores between concurrent runs unless the user chose the OpenMP threads.
    threads = None if "OMP_NUM_THREADS" in os.environ or dask_address else max(1, (os.cpu_count() or 1) // jobs)
    with StopSignals(stream) as stop:
        done, todo = plan(spec, binary, threads, stream)
        progress = Progress(len(done) + len(todo), stream)
        rows = list(done)
        for row in done:
            progress.update(row, skipped=True)
        try:
            if todo and dask_address:
                run_dask(todo, dask_address, progress, rows, stop)
            elif todo:
                run_local(todo, jobs, progress, rows, stop)
        finally:
            # Also when stopped: the table then lists what has finished or was interrupted.
            rows.sort(key=lambda r: r["index"])
            write_summary(spec, rows)
    if stop():
        raise ScanInterrupted(stop(), rows, not_started=len(done) + len(todo) - len(rows))
    return rows


def run_local(payloads: list[dict], jobs: int, progress: Progress, rows: list[dict],
              stop: Callable[[], int] = never_stop) -> None:
    """execute_task on this machine, `jobs` at a time; appends each row to `rows` as it finishes.

    A pool of threads (concurrent.futures), each waiting on one solver process
    while the GIL is free.  Threads, not worker processes, because a stop
    must reach every running solver and start no new run: each task polls
    `stop` (stopping.StopSignals), forwards the signal to its solver and
    returns an "interrupted" row; tasks not yet started return None."""
    def collect(row: dict | None) -> None:
        if row is not None:  # None: not started because of a stop
            rows.append(row)
            progress.update(row)

    if jobs == 1:
        for payload in payloads:
            collect(execute_task(payload, stop))
        return
    with ThreadPoolExecutor(max_workers=min(jobs, len(payloads)), thread_name_prefix="slipstrip-run") as pool:
        for future in as_completed([pool.submit(execute_task, p, stop) for p in payloads]):
            collect(future.result())


# How often the Dask client looks at its futures and its stop request [s].
DASK_POLL_SECONDS = 0.25


def run_dask(payloads: list[dict], address: str, progress: Progress, rows: list[dict],
             stop: Callable[[], int] = never_stop) -> None:
    """The same execute_task on a dask.distributed cluster.  Workers need this
    package importable (with its bindings: events and analysis run in the
    worker), the solver binary at the same path or as SLIPSTRIP_BIN, and the
    output directory.

    A stop reaches the workers through a distributed.Variable that every task
    polls (task.execute_task_on_worker): the scan sets it to the signal it
    got, each running task sends that signal to its own solver and returns
    an "interrupted" row, and tasks that had not started return None."""
    from distributed import Client, Variable, as_completed as dask_as_completed
    with Client(address) as client:
        stop_variable = Variable(f"slipstrip-scan-stop-{uuid.uuid4().hex}", client=client)
        stop_variable.set(0)
        futures = client.map(execute_task_on_worker, payloads, stop_variable=stop_variable.name, pure=False)
        pending = dask_as_completed(futures)
        told = False
        while not pending.is_empty():
            if stop() and not told:
                stop_variable.set(stop())
                told = True
            if not pending.has_ready():
                time.sleep(DASK_POLL_SECONDS)
                continue
            for future in pending.next_batch(block=False):
                row = future.result()
                if row is not None:
                    rows.append(row)
                    progress.update(row)
        stop_variable.delete()


# --------------------------------------------------------------------------- Slurm


def emit_slurm(spec: ScanSpec, directory: str | os.PathLike, binary: str | None = None,
               python: str | None = None, time_limit: str | None = None,
               cpus_per_task: int = 1) -> Path:
    """Writes a Slurm job array for the scan into `directory`:

    tasks/task_<index>.json  one per run: overrides, output path, base config
    scan.sbatch              `sbatch scan.sbatch`: --array=0-(n-1), task i runs tasks/task_<i>.json
    collect.sbatch           the summary table once the array is done
    submit.sh                submits both, collect after the array (afterany)

    Paths are absolute: the cluster must see this checkout, the binary and the
    output directory at the same paths (a shared file system)."""
    directory = Path(directory).resolve()
    tasks = expand_runs(spec)
    if not tasks:
        raise ValueError(f"{spec.path}: the scan has no runs")
    binary = binary or os.environ.get("SLIPSTRIP_BIN") or find_binary()
    binary = str(Path(binary).resolve()) if Path(binary).exists() else binary
    python = python or sys.executable
    (directory / "tasks").mkdir(parents=True, exist_ok=True)
    (directory / "logs").mkdir(exist_ok=True)
    spec.output_dir.mkdir(parents=True, exist_ok=True)
    task_files = []
    for task in tasks:
        payload = task_payload(task, spec.base_config, binary="", simulate=True)
        payload["command"] = ["slipstrip", "run", str(spec.base_config),
                              *itertools.chain.from_iterable(("--set", o) for o in task.overrides),
                              *kernel_cache_override(task.overrides, spec.output_dir),
                              "--out", str(task.run_file), "--quiet"]
        path = directory / "tasks" / f"task_{task.index:0{max(4, len(str(len(tasks) - 1)))}d}.json"
        write_json(path, payload)
        task_files.append(path)
    header = [
        "#!/bin/bash",
        f"#SBATCH --job-name=slipstrip-{spec.name}",
        f"#SBATCH --array=0-{len(tasks) - 1}",
        "#SBATCH --ntasks=1",
        f"#SBATCH --cpus-per-task={cpus_per_task}",
        f"#SBATCH --output={directory}/logs/task_%a.out",
        f"#SBATCH --error={directory}/logs/task_%a.err",
    ]
    if time_limit:
        header.append(f"#SBATCH --time={time_limit}")
    common = [
        "set -euo pipefail",
        f"# Scan {spec.path}: {len(tasks)} runs of {spec.base_config}, output in {spec.output_dir}",
        f"export SLIPSTRIP_BIN=\"${{SLIPSTRIP_BIN:-{binary}}}\"",
        "export OMP_NUM_THREADS=\"${SLURM_CPUS_PER_TASK:-1}\"",
        f"export PYTHONPATH=\"{PACKAGE_PARENT}${{PYTHONPATH:+:$PYTHONPATH}}\"",
        f"PYTHON=\"${{SLIPSTRIP_PYTHON:-{python}}}\"",
    ]
    array = ["TASKS=("] + [f"  {shlex.quote(str(p))}" for p in task_files] + [")"]
    body = [
        "TASK=\"${TASKS[$SLURM_ARRAY_TASK_ID]}\"",
        "exec \"$PYTHON\" -m slipstrip.scan --run-task \"$TASK\"",
    ]
    sbatch = directory / "scan.sbatch"
    sbatch.write_text("\n".join(header + common + array + body) + "\n")
    collect_script = directory / "collect.sbatch"
    collect_script.write_text("\n".join([
        "#!/bin/bash",
        f"#SBATCH --job-name=slipstrip-{spec.name}-collect",
        "#SBATCH --ntasks=1",
        f"#SBATCH --output={directory}/logs/collect.out",
        f"#SBATCH --error={directory}/logs/collect.err",
        *common,
        f"exec \"$PYTHON\" -m slipstrip.scan {shlex.quote(str(spec.path))} "
        f"--out {shlex.quote(str(spec.output_dir))} --collect",
    ]) + "\n")
    submit = directory / "submit.sh"
    submit.write_text("\n".join([
        "#!/bin/bash",
        "set -euo pipefail",
        f"array=$(sbatch --parsable {shlex.quote(str(sbatch))})",
        f"sbatch --dependency=afterany:${{array%%;*}} {shlex.quote(str(collect_script))}",
    ]) + "\n")
    for p in (sbatch, collect_script, submit):
        p.chmod(0o755)
    return sbatch
