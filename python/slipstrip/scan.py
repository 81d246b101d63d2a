"""Parameter scans: many `slipstrip run`s of one base config, on this machine
(a pool of solver subprocesses), on a Dask cluster, or as a Slurm job array, with one summary
table per scan.  File format, commands and output layout: docs/scans.md.

Each run is the C++ solver as a subprocess, so a scan needs nothing of the
solver but its binary, and a crashing run cannot take the scan down with it.

    python3 -m slipstrip scan configs/scans/fig3c_heights.toml --jobs 2
"""
from __future__ import annotations

import argparse
import csv
import importlib.util
import itertools
import json
import math
import os
import shlex
import shutil
import subprocess
import sys
import time
import tomllib
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable, TextIO

REPO = Path(__file__).resolve().parents[2]

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
# Columns after the varied parameters (`index` comes first).
STATUS_COLUMNS = ("status", "error", "wall_time_s")
TRAILING_COLUMNS = ("analysis_error", "run_file")

SUMMARY_CSV = "summary.csv"
SUMMARY_H5 = "summary.h5"
MAX_ERROR_CHARS = 2000  # enough for the solver's one-line errors plus context; keeps the table readable


# --------------------------------------------------------------------------- scan file


@dataclass(frozen=True)
class Parameter:
    key: str  # "section.key", as for `slipstrip run --set`
    values: tuple
    # Parameters sharing a group move together (zipped) inside a product scan:
    # a one-parameter family through several keys, e.g. (f0, a, b) of the
    # transition map.  None = a group of its own.
    group: str | None = None


@dataclass(frozen=True)
class ScanSpec:
    path: Path  # the scan file
    name: str
    base_config: Path  # absolute
    mode: str  # "product" | "zip"
    parameters: tuple[Parameter, ...]
    fixed: dict  # "section.key" -> value, applied before the varied parameters
    output_dir: Path  # absolute


@dataclass(frozen=True)
class RunTask:
    index: int
    parameters: dict  # varied "section.key" -> value
    overrides: tuple[str, ...]  # every --set of this run, fixed first
    run_file: Path


def _fail(scan_path, what: str):
    raise ValueError(f"{scan_path}: {what}")


def _flatten(table: dict, prefix: str = "") -> dict:
    """{"geometry": {"nodes": 64}, "time.beta": 0.2} -> {"geometry.nodes": 64, "time.beta": 0.2}."""
    flat = {}
    for key, value in table.items():
        full = f"{prefix}{key}"
        if isinstance(value, dict):
            flat.update(_flatten(value, full + "."))
        else:
            flat[full] = value
    return flat


def _check_key(scan_path, key) -> str:
    if not isinstance(key, str) or key.count(".") != 1 or not all(key.split(".")):
        _fail(scan_path, f"parameter key {key!r} is not allowed: expected 'section.key' as in "
                         "`slipstrip run --set section.key=value` (docs/config.md)")
    return key


def _range_values(scan_path, key: str, spec, log: bool) -> tuple:
    what = "logspace" if log else "range"
    if not isinstance(spec, dict) or set(spec) - {"start", "stop", "num", "scale"} or \
            not {"start", "stop", "num"} <= set(spec):
        _fail(scan_path, f"{key}: {what} = {spec!r} is not allowed: expected "
                         "{start = <number>, stop = <number>, num = <integer>}")
    start, stop, num = spec["start"], spec["stop"], spec["num"]
    scale = spec.get("scale", "log" if log else "linear")
    if scale not in ("linear", "log"):
        _fail(scan_path, f"{key}: {what}.scale = {scale!r} is not allowed: expected \"linear\" or \"log\"")
    if isinstance(num, bool) or not isinstance(num, int) or num < 1:
        _fail(scan_path, f"{key}: {what}.num = {num!r} is not allowed: expected an integer >= 1")
    for name, v in (("start", start), ("stop", stop)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            _fail(scan_path, f"{key}: {what}.{name} = {v!r} is not allowed: expected a finite number")
        if scale == "log" and v <= 0:
            _fail(scan_path, f"{key}: {what}.{name} = {v!r} is not allowed: a log range needs values > 0")
    if num == 1:
        values = [float(start)]
    elif scale == "log":
        # start/stop are the end VALUES (like numpy.geomspace), not exponents.
        ratio = math.log(stop / start)
        values = [start * math.exp(ratio * i / (num - 1)) for i in range(num)]
        values[-1] = float(stop)  # exact end point, no exp/log round-off
    else:
        values = [start + (stop - start) * i / (num - 1) for i in range(num)]
        values[-1] = float(stop)
    # Integer ends give integers when every value is whole (e.g. geometry.nodes,
    # which the config reader wants as a TOML integer).
    if isinstance(start, int) and isinstance(stop, int) and all(float(v).is_integer() for v in values):
        return tuple(int(v) for v in values)
    return tuple(float(v) for v in values)


def _parameter(scan_path, entry) -> Parameter:
    if not isinstance(entry, dict):
        _fail(scan_path, f"[[parameter]] entry {entry!r} is not a table")
    key = _check_key(scan_path, entry.get("key"))
    given = [k for k in ("values", "range", "logspace") if k in entry]
    unknown = set(entry) - {"key", "values", "range", "logspace", "group"}
    if unknown:
        _fail(scan_path, f"{key}: unknown field(s) {sorted(unknown)}; allowed: key, values, range, logspace, group")
    group = entry.get("group")
    if group is not None and (not isinstance(group, str) or not group):
        _fail(scan_path, f"{key}: group = {group!r} is not allowed: expected a non-empty string")
    if len(given) != 1:
        _fail(scan_path, f"{key}: give exactly one of values, range, logspace (got {given or 'none'})")
    if given[0] == "values":
        values = entry["values"]
        if not isinstance(values, list) or not values:
            _fail(scan_path, f"{key}: values = {values!r} is not allowed: expected a non-empty list")
        for v in values:
            if isinstance(v, (dict, list)):
                _fail(scan_path, f"{key}: value {v!r} is not allowed: expected a number, string or boolean")
        return Parameter(key, tuple(values), group)
    return Parameter(key, _range_values(scan_path, key, entry[given[0]], log=given[0] == "logspace"), group)


def load_scan(path: str | os.PathLike, output_dir: str | os.PathLike | None = None) -> ScanSpec:
    """Reads and checks a scan file; raises ValueError naming the field, the value and what is allowed.

    The base config is relative to the scan file; the output directory (scan
    file `output_dir`, or `output_dir` here, which wins) is relative to the
    current directory, default `scan_<scan file stem>`.
    """
    path = Path(path).resolve()
    with open(path, "rb") as f:
        try:
            doc = tomllib.load(f)
        except tomllib.TOMLDecodeError as e:
            _fail(path, f"invalid TOML: {e}")
    allowed = {"name", "base", "mode", "output_dir", "fixed", "parameter"}
    unknown = set(doc) - allowed
    if unknown:
        _fail(path, f"unknown top-level key(s) {sorted(unknown)}; allowed: {sorted(allowed)}")
    if "base" not in doc or not isinstance(doc["base"], str):
        _fail(path, "base = <path of the base config, relative to this file> is required")
    base = (path.parent / doc["base"]).resolve()
    if not base.is_file():
        _fail(path, f"base = {doc['base']!r}: {base} does not exist")
    mode = doc.get("mode", "product")
    if mode not in ("product", "zip"):
        _fail(path, f"mode = {mode!r} is not allowed: expected \"product\" or \"zip\"")
    fixed = _flatten(doc.get("fixed", {}))
    for key in fixed:
        _check_key(path, key)
    entries = doc.get("parameter", [])
    if not isinstance(entries, list):
        _fail(path, "parameter must be an array of tables: [[parameter]]")
    parameters = tuple(_parameter(path, e) for e in entries)
    keys = [p.key for p in parameters]
    duplicates = sorted({k for k in keys if keys.count(k) > 1} | (set(keys) & set(fixed)))
    if duplicates:
        _fail(path, f"key(s) {duplicates} given more than once (as parameters or in [fixed])")
    if mode == "zip" and len({len(p.values) for p in parameters}) > 1:
        lengths = {p.key: len(p.values) for p in parameters}
        _fail(path, f"mode = \"zip\" needs lists of equal length; got {lengths}")
    if mode == "zip" and any(p.group is not None for p in parameters):
        _fail(path, "group is only allowed with mode = \"product\" (in a zip every parameter is one group)")
    for group in {p.group for p in parameters if p.group is not None}:
        lengths = {p.key: len(p.values) for p in parameters if p.group == group}
        if len(set(lengths.values())) > 1:
            _fail(path, f"group {group!r} needs lists of equal length (its parameters are zipped); got {lengths}")
    name = doc.get("name", path.stem)
    out = Path(output_dir if output_dir is not None else doc.get("output_dir", f"scan_{path.stem}"))
    return ScanSpec(path=path, name=str(name), base_config=base, mode=mode, parameters=parameters,
                    fixed=fixed, output_dir=out.resolve())


def format_override(key: str, value) -> str:
    """`section.key=value` with value a TOML literal (docs/config.md, Overrides)."""
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, int):
        text = str(value)
    elif isinstance(value, float):
        text = repr(value)  # shortest exact form; 'inf'/'nan' are TOML too
    elif isinstance(value, str):
        text = json.dumps(value)  # a TOML basic string for anything printable
    else:
        raise ValueError(f"{key} = {value!r}: expected a number, string or boolean")
    return f"{key}={text}"


def run_file_name(index: int, n_runs: int) -> str:
    width = max(4, len(str(n_runs - 1)))
    return f"run_{index:0{width}d}.h5"


def expand_runs(spec: ScanSpec) -> list[RunTask]:
    """The scan's runs in order: Cartesian product (last parameter fastest) or zip.

    In a product, parameters of the same `group` are zipped into one factor,
    placed where the group's first parameter stands.
    """
    if spec.mode == "zip":
        value_lists = [p.values for p in spec.parameters]
        combos = [dict(zip((p.key for p in spec.parameters), c))
                  for c in (zip(*value_lists) if value_lists else [()])]
    else:
        factors = []  # each factor: list of {key: value} of its zipped parameters
        positions = {}
        for p in spec.parameters:
            if p.group is None or p.group not in positions:
                if p.group is not None:
                    positions[p.group] = len(factors)
                factors.append([{p.key: v} for v in p.values])
            else:
                factor = factors[positions[p.group]]
                for entry, v in zip(factor, p.values):
                    entry[p.key] = v
        combos = []
        for choice in itertools.product(*factors):
            merged = {}
            for part in choice:
                merged.update(part)
            combos.append(merged)
    # Overrides in the order the parameters are declared, whatever the grouping.
    order = [p.key for p in spec.parameters]
    fixed = tuple(format_override(k, v) for k, v in spec.fixed.items())
    tasks = []
    for index, combo in enumerate(combos):
        params = {k: combo[k] for k in order}
        overrides = fixed + tuple(format_override(k, v) for k, v in params.items())
        tasks.append(RunTask(index=index, parameters=params, overrides=overrides,
                             run_file=spec.output_dir / run_file_name(index, len(combos))))
    return tasks


# --------------------------------------------------------------------------- one run


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


def run_status(run_file: str | os.PathLike) -> str | None:
    """Root attribute `status` of a run file (docs/output.md), None if there is no readable file."""
    try:
        import h5py
        with h5py.File(run_file, "r") as f:
            status = f.attrs.get("status")
    except (OSError, KeyError):
        return None
    if isinstance(status, bytes):
        status = status.decode()
    return None if status is None else str(status)


def is_completed(run_file: str | os.PathLike) -> bool:
    return run_status(run_file) == "completed"


def _has_events(run_file) -> bool:
    import h5py
    with h5py.File(run_file, "r") as f:
        return "events" in f


def _events_count(run_file) -> float:
    """n_events attribute of the /events catalog (kept events), NaN if absent."""
    import h5py
    try:
        with h5py.File(run_file, "r") as f:
            return int(f["events"].attrs["n_events"])
    except (OSError, KeyError):
        return math.nan


def _tail(text: str) -> str:
    # One line per table cell: CSV readers and terminals cope better.
    text = " | ".join(line.strip() for line in text.strip().splitlines() if line.strip())
    return text if len(text) <= MAX_ERROR_CHARS else "..." + text[-MAX_ERROR_CHARS:]


def _load_summarize_run() -> Callable:
    """analysis.summarize_run, imported only when needed: from the package, else
    from analysis.py next to this file (when scan.py is run as a script)."""
    try:
        from slipstrip.analysis import summarize_run  # type: ignore
        return summarize_run
    except Exception as package_error:  # the package's __init__ may fail for reasons of its own
        local = Path(__file__).with_name("analysis.py")
        if not local.is_file():
            raise ImportError(f"slipstrip.analysis not available ({package_error})") from package_error
        name = "slipstrip_analysis_local"
        module = sys.modules.get(name)
        if module is None:
            spec = importlib.util.spec_from_file_location(name, local)
            module = importlib.util.module_from_spec(spec)
            sys.modules[name] = module  # dataclasses (and pickle) look the module up by name
            try:
                spec.loader.exec_module(module)
            except BaseException:
                del sys.modules[name]
                raise
        return module.summarize_run


def summarize_run_file(run_file: str | os.PathLike, summarizer: Callable | None = None) -> dict:
    """The analysis columns of one completed run (with /events): every key of
    ANALYSIS_KEYS, NaN where the analysis is missing or failed, plus
    `analysis_error` ("" on success).  n_events falls back to the catalog's own
    count when the analysis does not give it."""
    row = {k: math.nan for k in ANALYSIS_KEYS}
    row["analysis_error"] = ""
    try:
        summarize = summarizer if summarizer is not None else _load_summarize_run()
        result = dict(summarize(str(run_file)))
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
        row["analysis_error"] = _tail(f"{type(e).__name__}: {e}")
    if not isinstance(row.get("n_events"), (int, float)) or \
            (isinstance(row["n_events"], float) and math.isnan(row["n_events"])):
        row["n_events"] = _events_count(run_file)
    return row


def _record_path(run_file: Path) -> Path:
    return run_file.with_suffix(".json")


def _json_default(value):
    if hasattr(value, "tolist"):  # numpy scalars and arrays
        return value.tolist()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    return str(value)


def _write_json(path: Path, data) -> None:
    tmp = path.with_suffix(path.suffix + ".tmp")
    tmp.write_text(json.dumps(data, indent=1, default=_json_default))
    os.replace(tmp, path)  # a record is either absent or complete, even if the scan is killed


def _kernel_cache_override(overrides, directory) -> list[str]:
    """Runs of a scan share one strip-kernel cache (kernels/kernel_cache.hpp),
    so kernels that several runs need (same material, H, L, N, dt) are
    computed once.  A scan file that sets output.kernel_cache itself wins."""
    if any(o.split("=", 1)[0].strip() == "output.kernel_cache" for o in overrides):
        return []
    return ["--set", f'output.kernel_cache="{Path(directory).resolve() / "kernel_cache"}"']


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


def execute_task(payload: dict) -> dict:
    """Runs one scan task: `slipstrip run` (unless payload["simulate"] is False),
    `slipstrip events`, the analysis; writes the row next to the run file as
    run_<index>.json and returns it.  Never raises for a failing run: the row
    says status "failed" and the error text."""
    run_file = Path(payload["run_file"])
    run_file.parent.mkdir(parents=True, exist_ok=True)
    binary = payload.get("binary") or find_binary()
    env = dict(os.environ)
    if payload.get("threads"):
        env["OMP_NUM_THREADS"] = str(payload["threads"])
    row = {"index": payload["index"], **payload["parameters"],
           "status": "failed", "error": "", "wall_time_s": math.nan}
    row.update({k: math.nan for k in ANALYSIS_KEYS})
    row["analysis_error"] = ""
    row["run_file"] = run_file.name

    if payload.get("simulate", True):
        cmd = [binary, "run", payload["base_config"]]
        for o in payload["overrides"]:
            cmd += ["--set", o]
        cmd += _kernel_cache_override(payload["overrides"], run_file.parent)
        start = time.monotonic()
        returncode = None
        if _has_restart_point(run_file):
            # An interrupted run of this scan (Ctrl-C, a Slurm time limit):
            # continue it from its restart point instead of redoing it.  The
            # config and overrides are passed only to be checked: the solver
            # refuses (exit 2) if they do not resolve to the run's stored config
            # (the scan file was edited) or the restart point is unusable, and
            # the run is then done again from t = 0.
            _record_path(run_file).unlink(missing_ok=True)
            try:
                returncode, out, err = _run_solver(cmd + ["--resume", str(run_file), "--quiet"], env)
            except OSError as e:
                returncode, out, err = -1, "", f"cannot start {binary}: {e}"
            if returncode == 2:
                print(f"[scan] run {payload['index']}: {run_file.name} cannot be resumed "
                      f"({_tail(err or out)}); running it again", file=sys.stderr)
                returncode = None
        if returncode is None:
            # A file of an earlier attempt must not outlive this one: if this run
            # fails before writing, an old "completed" file would pass for its result.
            run_file.unlink(missing_ok=True)
            _restart_point(run_file).unlink(missing_ok=True)
            _record_path(run_file).unlink(missing_ok=True)
            try:
                returncode, out, err = _run_solver(cmd + ["--out", str(run_file), "--quiet"], env)
            except OSError as e:
                returncode, out, err = -1, "", f"cannot start {binary}: {e}"
        row["wall_time_s"] = time.monotonic() - start
        if returncode != 0:
            row["error"] = f"slipstrip run exited with code {returncode}: " + (_tail(err or out) or "(no message)")
    else:
        row["wall_time_s"] = _file_wall_time(run_file)

    status = run_status(run_file)
    if not row["error"] and status != "completed":
        row["error"] = f"run file status is {status!r}" if status is not None else "no run file written"
    if not row["error"]:
        row["status"] = "completed"
        try:
            if payload.get("simulate", True) or not _has_events(run_file):
                ev = subprocess.run([binary, "events", str(run_file)], capture_output=True, text=True, env=env)
                if ev.returncode != 0:
                    raise RuntimeError(f"slipstrip events exited with code {ev.returncode}: "
                                       + (ev.stderr or ev.stdout).strip())
            row.update(summarize_run_file(run_file))
        except Exception as e:
            row["analysis_error"] = _tail(f"{type(e).__name__}: {e}")
    details = row.pop("analysis_details", None)
    record = dict(row, overrides=list(payload["overrides"]))
    if details:
        record["analysis_details"] = details
    _write_json(_record_path(run_file), record)
    return row


def _restart_point(run_file: Path) -> Path:
    """The solver's restart point of a run file (docs/output.md): RUN.h5.restart."""
    return run_file.with_name(run_file.name + ".restart")


def _has_restart_point(run_file: Path) -> bool:
    """An interrupted run that `slipstrip run --resume` can continue."""
    return _restart_point(run_file).is_file() and run_status(run_file) not in (None, "completed")


def _run_solver(cmd: list[str], env: dict) -> tuple[int, str, str]:
    """Runs the solver to its end.  On Ctrl-C the solver (same process group)
    gets SIGINT itself and closes its file with status "interrupted"; we wait
    for that instead of killing it as subprocess.run would after 0.25 s."""
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env) as proc:
        try:
            out, err = proc.communicate()
        except KeyboardInterrupt:
            try:
                proc.wait(timeout=60)  # the solver's clean stop: one last flush of the file
            except subprocess.TimeoutExpired:
                proc.kill()
            raise
        return proc.returncode, out, err


def _file_wall_time(run_file: Path) -> float:
    """end_time - start_time of a run file (1 s resolution), for runs made outside this scan process."""
    from datetime import datetime
    import h5py
    try:
        with h5py.File(run_file, "r") as f:
            start, end = (str(f.attrs[k].decode() if isinstance(f.attrs[k], bytes) else f.attrs[k])
                          for k in ("start_time", "end_time"))
        fmt = "%Y-%m-%dT%H:%M:%SZ"
        return (datetime.strptime(end, fmt) - datetime.strptime(start, fmt)).total_seconds()
    except (OSError, KeyError, ValueError):
        return math.nan


# --------------------------------------------------------------------------- whole scan


def _stream(stream):
    """"stderr" means sys.stderr at call time (not at import: pytest and others replace it)."""
    return sys.stderr if stream == "stderr" else stream


class Progress:
    """Whole-scan progress on a stream: runs done / total, elapsed, ETA."""

    def __init__(self, total: int, stream: TextIO | None):
        self.total, self.stream = total, stream
        self.done = self.skipped = self.failed = 0
        self.start = time.monotonic()

    def update(self, row: dict, skipped: bool = False) -> None:
        self.done += 1
        self.skipped += skipped
        self.failed += row.get("status") != "completed"
        if self.stream is None:
            return
        elapsed = time.monotonic() - self.start
        worked = self.done - self.skipped  # skipped runs took no time: leave them out of the rate
        remaining = self.total - self.done
        eta = elapsed / worked * remaining if worked else math.nan
        eta_text = "--" if math.isnan(eta) else f"{eta:.0f} s"
        note = f"run {row['index']} {row.get('status')}" + (" (skipped: already completed)" if skipped else "")
        print(f"[scan] {self.done}/{self.total} runs done, {self.failed} failed, {self.skipped} skipped; "
              f"elapsed {elapsed:.1f} s, ETA {eta_text}; {note}", file=self.stream, flush=True)


def _read_record(task: RunTask) -> dict | None:
    try:
        return json.loads(_record_path(task.run_file).read_text())
    except (OSError, json.JSONDecodeError):  # absent or unreadable: as if never analysed
        return None


def _previous_row(task: RunTask) -> dict | None:
    """The stored row of a finished run whose overrides are this task's, else None."""
    record = _read_record(task)
    if record is None or record.get("overrides") != list(task.overrides) or record.get("status") != "completed":
        return None
    record.pop("overrides")
    record.pop("analysis_details", None)
    return record


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
            previous = _previous_row(task)
            if previous is not None:
                done.append(previous)
                continue
            record = _read_record(task)
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
    (summary.csv, summary.h5 in the output directory).  Returns the rows in run order."""
    binary = binary or find_binary()
    stream = _stream(stream)
    spec.output_dir.mkdir(parents=True, exist_ok=True)
    if jobs < 1:
        raise ValueError(f"jobs = {jobs} is not allowed: expected an integer >= 1")
    # Share the cores between concurrent runs unless the user chose the OpenMP threads.
    threads = None if "OMP_NUM_THREADS" in os.environ or dask_address else max(1, (os.cpu_count() or 1) // jobs)
    done, todo = plan(spec, binary, threads, stream)
    progress = Progress(len(done) + len(todo), stream)
    rows = list(done)
    for row in done:
        progress.update(row, skipped=True)
    try:
        if todo and dask_address:
            rows += _run_dask(todo, dask_address, progress)
        elif todo and jobs == 1:
            for payload in todo:
                row = execute_task(payload)
                rows.append(row)
                progress.update(row)
        elif todo:
            # A subprocess pool: each thread waits on one solver process (the
            # work is in the solver; the GIL is free while it runs).  Threads,
            # not worker processes, because on Ctrl-C a process pool would still
            # start the calls it had already queued, while here no new run starts
            # and the running solvers, which get the terminal's SIGINT too, close
            # their files as "interrupted" and their rows are kept.
            with ThreadPoolExecutor(max_workers=min(jobs, len(todo)), thread_name_prefix="slipstrip-run") as pool:
                futures = [pool.submit(execute_task, p) for p in todo]
                collected = set()
                try:
                    for future in as_completed(futures):
                        rows.append(future.result())
                        collected.add(future)
                        progress.update(rows[-1])
                except KeyboardInterrupt:
                    pool.shutdown(wait=True, cancel_futures=True)
                    for f in futures:
                        if f not in collected and f.done() and not f.cancelled() and f.exception() is None:
                            rows.append(f.result())
                            progress.update(rows[-1])
                    raise
    finally:
        # Also on Ctrl-C: the table then lists what has finished so far.
        rows.sort(key=lambda r: r["index"])
        write_summary(spec, rows)
    return rows


def _run_dask(payloads: list[dict], address: str, progress: Progress) -> list[dict]:
    """The same execute_task on a dask.distributed cluster (workers need the
    binary at the same path, or SLIPSTRIP_BIN, and the output directory)."""
    from distributed import Client, as_completed as dask_as_completed
    try:
        # Workers then need neither this package on their path nor the same checkout.
        import cloudpickle
        cloudpickle.register_pickle_by_value(sys.modules[execute_task.__module__])
    except (ImportError, AttributeError, ValueError, KeyError):
        pass
    rows = []
    with Client(address) as client:
        futures = client.map(execute_task, payloads, pure=False)
        for future in dask_as_completed(futures):
            row = future.result()
            rows.append(row)
            progress.update(row)
    return rows


def table_columns(spec: ScanSpec, rows: Iterable[dict]) -> list[str]:
    columns = ["index", *(p.key for p in spec.parameters), *STATUS_COLUMNS, *ANALYSIS_KEYS]
    extra = []
    for row in rows:  # keys the analysis gives beyond the documented ones
        extra += [k for k in row if k not in columns and k not in TRAILING_COLUMNS and k not in extra]
    return columns + extra + list(TRAILING_COLUMNS)


def _csv_text(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)
    return str(value)


def write_summary(spec: ScanSpec, rows: list[dict]) -> tuple[Path, Path]:
    """summary.csv and summary.h5 (group /summary, one dataset per column) in the output directory."""
    import h5py
    import numpy as np
    columns = table_columns(spec, rows)
    csv_path = spec.output_dir / SUMMARY_CSV
    with open(csv_path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(columns)
        for row in rows:
            writer.writerow([_csv_text(row.get(c)) for c in columns])
    h5_path = spec.output_dir / SUMMARY_H5
    with h5py.File(h5_path, "w") as f:
        g = f.create_group("summary")
        g.attrs["columns"] = columns
        g.attrs["scan_file"] = str(spec.path)
        g.attrs["base_config"] = str(spec.base_config)
        g.attrs["mode"] = spec.mode
        g.attrs["fixed_overrides"] = [format_override(k, v) for k, v in spec.fixed.items()] or [""]
        g.attrs["n_runs"] = len(rows)
        g.attrs["units"] = "wall_time_s: s; lognormal_mu: ln(s); everything else: 1 or the parameter's SI unit"
        for c in columns:
            values = [row.get(c) for row in rows]
            numeric = all(v is None or (isinstance(v, (int, float)) and not isinstance(v, str)) for v in values)
            if numeric:
                data = np.array([math.nan if v is None else float(v) for v in values], dtype=np.float64)
            else:
                data = np.array(["" if v is None else str(v) for v in values], dtype=h5py.string_dtype())
            g.create_dataset(c, data=data)
    return csv_path, h5_path


def read_summary(directory: str | os.PathLike) -> list[dict]:
    """Rows of summary.h5 in `directory` (numbers as float, text as str)."""
    import h5py
    with h5py.File(Path(directory) / SUMMARY_H5, "r") as f:
        g = f["summary"]
        columns = [c.decode() if isinstance(c, bytes) else str(c) for c in g.attrs["columns"]]
        data = {c: g[c][()] for c in columns}
    n = len(next(iter(data.values()))) if data else 0
    rows = []
    for i in range(n):
        row = {}
        for c in columns:
            v = data[c][i]
            row[c] = v.decode() if isinstance(v, bytes) else (float(v) if hasattr(v, "dtype") else v)
        rows.append(row)
    return rows


def collect(spec: ScanSpec, binary: str | None = None, stream: TextIO | None | str = "stderr") -> list[dict]:
    """Summary of what is on disk (e.g. after a Slurm array), running nothing but
    the analysis of completed runs that lack a stored row; unfinished runs are
    rows with status "missing" or the file's status."""
    stream = _stream(stream)
    rows = []
    for task in expand_runs(spec):
        previous = _previous_row(task)
        if previous is not None and is_completed(task.run_file):
            rows.append(previous)
        elif is_completed(task.run_file):
            payload = task_payload(task, spec.base_config, binary or find_binary(), simulate=False)
            rows.append(execute_task(payload))
        else:
            status = run_status(task.run_file)
            row = {"index": task.index, **task.parameters, "status": "failed" if status else "missing",
                   "error": f"run file status is {status!r}" if status else "no run file",
                   "wall_time_s": math.nan, **{k: math.nan for k in ANALYSIS_KEYS},
                   "analysis_error": "", "run_file": task.run_file.name}
            record = _read_record(task)  # a failed run's own error text is more useful
            if record is not None and record.get("overrides") == list(task.overrides):
                record.pop("overrides")
                record.pop("analysis_details", None)
                row = record
            rows.append(row)
    write_summary(spec, rows)
    if stream is not None:
        n_ok = sum(r["status"] == "completed" for r in rows)
        print(f"[scan] collected {len(rows)} runs, {n_ok} completed", file=stream)
    return rows


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
                              *_kernel_cache_override(task.overrides, spec.output_dir),
                              "--out", str(task.run_file), "--quiet"]
        path = directory / "tasks" / f"task_{task.index:0{max(4, len(str(len(tasks) - 1)))}d}.json"
        _write_json(path, payload)
        task_files.append(path)
    scan_py = Path(__file__).resolve()
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
        f"export PYTHONPATH=\"{scan_py.parents[1]}${{PYTHONPATH:+:$PYTHONPATH}}\"",
        f"PYTHON=\"${{SLIPSTRIP_PYTHON:-{python}}}\"",
    ]
    array = ["TASKS=("] + [f"  {shlex.quote(str(p))}" for p in task_files] + [")"]
    body = [
        "TASK=\"${TASKS[$SLURM_ARRAY_TASK_ID]}\"",
        f"exec \"$PYTHON\" {shlex.quote(str(scan_py))} --run-task \"$TASK\"",
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
        f"exec \"$PYTHON\" {shlex.quote(str(scan_py))} {shlex.quote(str(spec.path))} "
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


# --------------------------------------------------------------------------- plots


def duration_pdf(durations, n_bins: int = 20):
    """Log-binned probability density of event durations: (bin centres [s],
    p(T) [1/s]), normalised so sum p dT = 1 over the positive durations."""
    import numpy as np
    t = np.asarray(durations, dtype=float)
    t = t[np.isfinite(t) & (t > 0)]  # T = 0 (single nodal slip) has no place on a log axis
    if t.size == 0:
        return np.empty(0), np.empty(0)
    lo, hi = t.min(), t.max()
    if hi == lo:
        lo, hi = lo / 1.1, hi * 1.1
    edges = np.geomspace(lo, hi * (1 + 1e-12), n_bins + 1)
    counts, _ = np.histogram(t, bins=edges)
    density = counts / (t.size * np.diff(edges))
    centres = np.sqrt(edges[:-1] * edges[1:])
    keep = counts > 0
    return centres[keep], density[keep]


def transit_time(config_text: str) -> float:
    """2H/c_s of a resolved config (the /attrs `config` text of a run file); inf for a half-space."""
    cfg = tomllib.loads(config_text)
    height = cfg["geometry"]["height"]
    height = math.inf if isinstance(height, str) else float(height)
    material = cfg["material"]
    mu = material.get("shear_modulus")
    if mu is None:
        mu = material["youngs_modulus"] / (2 * (1 + material["poisson_ratio"]))
    return 2 * height / math.sqrt(mu / material["density"])


def plot_duration_pdfs(summary_dir: str | os.PathLike, out_png: str | os.PathLike, n_bins: int = 20) -> Path:
    """Fig. 3d style: p(T) of every completed run of a scan (the /events catalogs),
    with an arrow at 2H/c_s of each run in the curve's colour."""
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    summary_dir = Path(summary_dir)
    rows = read_summary(summary_dir)
    columns = list(rows[0]) if rows else []
    params = [c for c in columns[1:columns.index("status")]] if "status" in columns else []
    fig, ax = plt.subplots(figsize=(6, 4.5))
    arrows = []
    for row in rows:
        if row["status"] != "completed":
            continue
        with h5py.File(summary_dir / row["run_file"], "r") as f:
            if "events" not in f:
                continue
            durations = f["events/T"][()]
            config = f.attrs["config"]
        config = config.decode() if isinstance(config, bytes) else str(config)
        centres, density = duration_pdf(durations, n_bins)
        label = ", ".join(f"{p.split('.')[-1]} = {row[p]:g}" if isinstance(row[p], float) else f"{p} = {row[p]}"
                          for p in params) or f"run {int(row['index'])}"
        label += f" ({len(durations)} events)"
        line, = ax.loglog(centres, density, "o-", ms=3, label=label)
        if len(centres) == 0:
            line.set_visible(False)
        arrows.append((transit_time(config), line.get_color()))
    ax.set_xlabel("event duration T [s]")
    ax.set_ylabel("p(T) [1/s]")
    ax.set_title("Event durations; arrows: 2H/c_s")
    for t, color in arrows:  # after the curves, so the axis limits are known
        if math.isfinite(t):
            ax.annotate("", xy=(t, 0.0), xycoords=("data", "axes fraction"),
                        xytext=(t, 0.12), textcoords=("data", "axes fraction"),
                        arrowprops=dict(arrowstyle="->", color=color, lw=2))
    if rows:
        ax.legend(fontsize=8)
    fig.tight_layout()
    out_png = Path(out_png)
    fig.savefig(out_png, dpi=120)
    plt.close(fig)
    return out_png


# --------------------------------------------------------------------------- command line


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
    p.add_argument("--dry-run", action="store_true", help="list the runs and their overrides, run nothing")
    p.add_argument("--collect", action="store_true",
                   help="only write the summary of the runs on disk (after a Slurm array)")
    p.add_argument("--plot-durations", metavar="PNG", help="afterwards, plot p(T) of every run (Fig. 3d style)")
    p.add_argument("--run-task", metavar="TASK_JSON", help="run one task file written by --emit-slurm")
    return p


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.run_task:
            payload = json.loads(Path(args.run_task).read_text())
            payload["binary"] = args.binary or payload.get("binary") or find_binary()
            row = execute_task(payload)
            print(f"[scan] run {row['index']}: {row['status']} {row['error']}".rstrip(), file=sys.stderr)
            return 0 if row["status"] == "completed" else 1
        if not args.scan:
            print("error: a scan file is required (slipstrip scan SCAN.toml ...)", file=sys.stderr)
            return 2
        spec = load_scan(args.scan, args.out)
        if args.dry_run:
            for task in expand_runs(spec):
                print(f"{task.run_file}  " + " ".join(f"--set {o}" for o in task.overrides))
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
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted: the summary lists the runs finished so far", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
