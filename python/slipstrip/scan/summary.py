"""The scan's summary: one table per scan (summary.csv, summary.h5), the
table of what is on disk (`collect`, after a Slurm array), and the duration
plot (Fig. 3d style).  Columns: docs/scans.md.
"""
from __future__ import annotations

import csv
import math
import os
import sys
import tomllib
from pathlib import Path
from typing import Iterable, TextIO

from .. import runfile
from .spec import ScanSpec, expand_runs, format_override
from .task import ANALYSIS_KEYS, execute_task, is_completed, previous_row, read_record, task_payload

# Columns after the varied parameters (`index` comes first).
STATUS_COLUMNS = ("status", "error", "wall_time_s", "resumed")
TRAILING_COLUMNS = ("analysis_error", "run_file")

SUMMARY_CSV = "summary.csv"
SUMMARY_H5 = "summary.h5"


def stream_of(stream):
    """"stderr" means sys.stderr at call time (not at import: pytest and others replace it)."""
    return sys.stderr if stream == "stderr" else stream


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
    stream = stream_of(stream)
    rows = []
    for task in expand_runs(spec):
        previous = previous_row(task)
        if previous is not None and is_completed(task.run_file):
            rows.append(previous)
        elif is_completed(task.run_file):
            # Events and the analysis only (in-process): no solver is started.
            payload = task_payload(task, spec.base_config, binary or "", simulate=False)
            rows.append(execute_task(payload))
        else:
            status = runfile.read_status(task.run_file)
            row = {"index": task.index, **task.parameters,
                   "status": "interrupted" if status == "interrupted" else "failed" if status else "missing",
                   "error": f"run file status is {status!r}" if status else "no run file",
                   "wall_time_s": math.nan, "resumed": False, **{k: math.nan for k in ANALYSIS_KEYS},
                   "analysis_error": "", "run_file": task.run_file.name}
            record = read_record(task)  # a failed run's own error text is more useful
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


def height_round_trip_time(config_text: str) -> float:
    """2H/c_s [s]: a shear wave's round trip across the strip height (from the
    interface to the strip's far boundary and back), of a resolved config (the root attribute
    `config` of a run file); inf for a half-space.  Not the L/c_s of
    RunFile.length_transit_time."""
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
        run_path = summary_dir / row["run_file"]
        with runfile.open_h5(run_path) as f:
            if "events" not in f:
                continue
            durations = f["events/T"][()]
        config = runfile.read_config_text(run_path)
        centres, density = duration_pdf(durations, n_bins)
        label = ", ".join(f"{p.split('.')[-1]} = {row[p]:g}" if isinstance(row[p], float) else f"{p} = {row[p]}"
                          for p in params) or f"run {int(row['index'])}"
        label += f" ({len(durations)} events)"
        line, = ax.loglog(centres, density, "o-", ms=3, label=label)
        if len(centres) == 0:
            line.set_visible(False)
        arrows.append((height_round_trip_time(config), line.get_color()))
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
