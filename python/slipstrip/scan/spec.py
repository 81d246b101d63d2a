"""The scan file (docs/scans.md): parsing, checking, expansion into runs, dry run.

A scan file names a base config, fixed overrides and varied parameters
(values, range or logspace; product with optional zipped groups, or zip).
`load_scan` checks it and raises ValueError naming the field, the value and
what is allowed; `expand_runs` turns it into one RunTask per run, each with
its `section.key=value` overrides (`slipstrip run --set` syntax) and its run
file name; `check_runs` checks each run's resolved config with the
solver's own config reader (the bindings).  Nothing here runs anything.
"""
from __future__ import annotations

import itertools
import json
import math
import os
import tomllib
from dataclasses import dataclass
from pathlib import Path


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


def dry_run_lines(spec: ScanSpec) -> list[str]:
    """`scan --dry-run`: one line per run, its file and its overrides."""
    return [f"{task.run_file}  " + " ".join(f"--set {o}" for o in task.overrides) for task in expand_runs(spec)]


def check_runs(spec: ScanSpec) -> tuple[list[str], list[str]]:
    """Every run's config (base config + overrides) read by the solver's own
    config reader (config/config.cpp, through the bindings), so a misspelt key
    gets its "did you mean" before anything runs.  Returns (errors, warnings):
    one line per refused run, "run <i> (<file>): <the reader's message>", and
    one per plausibility warning of an accepted run (docs/config.md, "Warnings")."""
    from ..config import Config  # the compiled bindings: only needed here
    errors, warnings = [], []
    for task in expand_runs(spec):
        where = f"run {task.index} ({task.run_file.name})"
        try:
            config = Config.from_file(spec.base_config, list(task.overrides))
        except ValueError as e:  # slipstrip.ConfigError
            errors.append(f"{where}: {e}")
            continue
        warnings += [f"{where}: {w}" for w in config.warnings()]
    return errors, warnings


def invalid_runs(spec: ScanSpec) -> list[str]:
    """The runs whose config the solver would refuse (check_runs' errors)."""
    return check_runs(spec)[0]
