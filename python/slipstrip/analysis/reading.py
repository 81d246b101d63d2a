"""Reading a run file for the analysis: its scales (RunInfo), its event
catalog (/events, made by the C++ detector through the bindings when
missing), its space-time field (/snapshots) and its slip sampling."""
from __future__ import annotations

import dataclasses
import math
import os
import tempfile
import tomllib
from pathlib import Path

import numpy as np

from ..paths import lock_run
from ..runfile import decode_attr, open_h5, read_times


DEFAULT_ALPHA = 15.0
CATALOG_FIELDS = ("t_start", "T", "x_start", "L_s", "u_mean", "M0", "max_slip_rate", "n_clusters")
# Only in the catalog of a 2D interface (docs/3d.md): hypocentre z, extent
# along z, area.
CATALOG_FIELDS_2D = ("z_start", "L_z", "A")


@dataclasses.dataclass(frozen=True)
class RunInfo:
    """Scales of one run [SI]."""
    D: float            # characteristic slip [m]
    L: float            # interface length [m]
    H: float            # strip height [m] (inf for a half-space)
    v0: float           # driving velocity [m/s]
    mu: float           # shear modulus [Pa]
    c_s: float          # shear wave speed [m/s]
    sigma0: float       # normal stress [Pa]
    delta_th: float     # slip-sampling threshold [m]
    n_nodes: int        # nodes of the interface (N, or N N_z on a 2D interface)
    duration: float     # simulated time covered by the file [s]
    nodes_z: int = 1    # > 1: a 2D interface (docs/3d.md), N_z rows across z
    W: float = math.nan  # L_z [m], the width of a 2D interface (nan on a line)

    @property
    def interface_2d(self) -> bool:
        return self.nodes_z > 1


def read_run_info(path: str | os.PathLike) -> RunInfo:
    with open_h5(path) as f:
        config = tomllib.loads(decode_attr(f.attrs["config"])) if "config" in f.attrs else {}
        ss = f["slip_sampling"].attrs if "slip_sampling" in f else {}
        geometry = config.get("geometry", {})
        material = config.get("material", {})
        friction = config.get("friction", {})
        L = float(ss.get("L", geometry.get("length", math.nan)))
        D = float(ss.get("D", friction.get("characteristic_slip", math.nan)))
        v0 = float(ss.get("v0", config.get("loading", {}).get("driving_velocity", math.nan)))
        mu = float(ss.get("mu", material.get("shear_modulus", math.nan)))
        rho = float(material.get("density", math.nan))
        H = geometry.get("height", math.nan)
        H = math.inf if isinstance(H, str) and H.strip().lower() == "inf" else float(H)
        if "snapshots" in f and "x" in f["snapshots"]:
            n = int(f["snapshots/x"].shape[0])
        elif "slip_sampling" in f:
            n = int(f["slip_sampling/crossing_time"].shape[1])
        else:
            n = int(geometry.get("nodes", 0))
        duration = math.nan
        if "timeseries" in f and f["timeseries/time"].shape[0] > 0:
            duration = float(read_times(f, "timeseries/time")[-1])
        elif "snapshots" in f and f["snapshots/time"].shape[0] > 0:
            duration = float(read_times(f, "snapshots/time")[-1])
        nodes_z = int(ss.get("nodes_z", geometry.get("nodes_z", 1)))
        W = float(ss.get("W", geometry.get("width", math.nan))) if nodes_z > 1 else math.nan
        return RunInfo(D=D, L=L, H=H, v0=v0, mu=mu, c_s=math.sqrt(mu / rho) if rho > 0 else math.nan,
                       sigma0=float(config.get("loading", {}).get("normal_stress", math.nan)),
                       delta_th=float(ss.get("delta_th", math.nan)), n_nodes=n, duration=duration,
                       nodes_z=nodes_z, W=W)


def read_catalog(path: str | os.PathLike) -> dict:
    """/events of `path` as {field: ndarray} plus 'attrs' (dict)."""
    with open_h5(path) as f:
        if "events" not in f:
            raise KeyError(f"{path}: no group /events (run `slipstrip events {path}` first)")
        g = f["events"]
        catalog = {k: np.asarray(g[k][:]) for k in CATALOG_FIELDS + CATALOG_FIELDS_2D if k in g}
        catalog["attrs"] = {k: decode_attr(v) for k, v in g.attrs.items()}
    return catalog


def run_event_detection(run_path: str | os.PathLike, alpha: float = DEFAULT_ALPHA,
                        out: str | os.PathLike | None = None, min_slip_rate_v0: float = 0.0) -> str:
    """Detects slip events in /slip_sampling of `run_path` and writes the
    catalog as /events of `out` (default: the run file itself, replacing its
    /events); returns the file holding /events.  The same C++ calls as
    `slipstrip events RUN --alpha A --min-slip-rate K [--out OUT]` (bindings,
    in-process), so the file is the CLI's byte for byte.  RuntimeError if the
    run file cannot be read or the target cannot be written."""
    import time

    from .. import _slipstrip
    target = os.fspath(out if out is not None else run_path)
    # Another process may hold HDF5's lock on the file for a moment (a reader of the
    # run file, or its solver during a write-out): HDF5 then refuses to open it with
    # "Resource temporarily unavailable".  Retried for up to 5 s, as open_h5 does for
    # readers; any other error, or a lock held longer, is raised.
    for attempt in range(100):
        try:
            _slipstrip.detect_events_into_file(os.fspath(run_path), target, alpha=float(alpha),
                                               min_slip_rate_v0=float(min_slip_rate_v0))
            return target
        except RuntimeError as err:
            if "Resource temporarily unavailable" not in str(err) or attempt == 99:
                raise
            time.sleep(0.05)
    return target


def catalog_file_name(alpha: float, min_slip_rate_v0: float = 0.0) -> str:
    """The catalog file analyze writes for (alpha, min_slip_rate_v0); the
    filter's value is in the name only when it is on."""
    return f"events_alpha{alpha:g}" + (f"_rate{min_slip_rate_v0:g}" if min_slip_rate_v0 > 0 else "") + ".h5"


def catalog_for(run_path: str | os.PathLike, alpha: float = DEFAULT_ALPHA,
                workdir: str | os.PathLike | None = None, write_into_run: bool = False,
                min_slip_rate_v0: float = 0.0) -> dict:
    """The catalog of `run_path` for `alpha` and `min_slip_rate_v0`: /events
    of the run file if it was made with both (a catalog without the
    min_slip_rate_v0 attribute is unfiltered, 0); else detection is run into a
    catalog file in `workdir` (or a temporary one).  Only with
    write_into_run=True, and when the run file has no /events yet, is the
    catalog added to the run file."""
    stored = None
    with open_h5(run_path) as f:
        if "events" in f:
            a = f["events"].attrs
            stored = (float(a["alpha"]), float(a.get("min_slip_rate_v0", 0.0)))
    if stored == (float(alpha), float(min_slip_rate_v0)):
        return read_catalog(run_path)
    if stored is None and write_into_run:
        # Not while a run or resume writes the file (LockHeldError, a ValueError,
        # is raised); a read-only directory or file falls back to a separate
        # catalog file.
        try:
            with lock_run(run_path):
                run_event_detection(run_path, alpha, min_slip_rate_v0=min_slip_rate_v0)
                return read_catalog(run_path)
        except (RuntimeError, OSError):
            pass
    if workdir is not None:
        out = Path(workdir) / catalog_file_name(alpha, min_slip_rate_v0)
        run_event_detection(run_path, alpha, out, min_slip_rate_v0)
        return read_catalog(out)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / catalog_file_name(alpha, min_slip_rate_v0)
        run_event_detection(run_path, alpha, out, min_slip_rate_v0)
        return read_catalog(out)


def read_spacetime(path, max_rows: int | None = None):
    """(time, x, slip_rate) of /snapshots; None without enough snapshots.
    max_rows > 0 strides the rows evenly."""
    with open_h5(path) as f:
        if "snapshots" not in f or f["snapshots/time"].shape[0] < 2:
            return None
        t = read_times(f, "snapshots/time")
        step = 1 if not max_rows else _stride(t.size, max_rows)
        return t[::step], f["snapshots/x"][:], f["snapshots/slip_rate"][::step]


def _stride(n: int, target: int) -> int:
    return max(1, int(math.ceil(n / target)))


def _read_crossing_time(path):
    with open_h5(path) as f:
        g = f["slip_sampling"]
        ct = g["crossing_time"][:]
        x = g["x"][:] if "x" in g else np.arange(ct.shape[1]) * float(g.attrs["dx"])
    return ct, x
