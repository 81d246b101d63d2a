"""Read a run file (docs/output.md) without holding it open.

This module is the package's one reader of run files: everything else
(analysis, report, transition, export, scan) opens them with `open_h5` and
decodes attributes with `decode_attr` or the small readers below
(`read_attrs`, `read_config`, `read_status`, ...), so that the lock retry
and the attribute decoding (HDF5 strings arrive as bytes or str, numbers as
NumPy scalars) exist once.

The writer defers its flushes while a reader holds the file (HDF5 file
locks), so RunFile opens the file only for the duration of each read and
closes it again.  Everything is read on demand; nothing is cached except the
small root attributes, which `refresh()` re-reads.
"""
from __future__ import annotations

import datetime
import math
import os
import time
import tomllib
from typing import Any

import h5py
import numpy as np

__all__ = ["RunFile", "RunFileError", "LazyDataset", "open_run", "open_h5", "unreadable_reason", "decode_attr", "read_attrs",
           "read_config_text", "read_config", "read_status", "wall_seconds", "has_group", "read_event_count", "read_times"]

# Root attributes start_time / end_time (docs/output.md): UTC, 1 s resolution.
DATE_FORMAT = "%Y-%m-%dT%H:%M:%SZ"


class RunFileError(OSError):
    """A path that is not a readable run file, with a one-line message that
    names the path, what it is instead and what to give (never HDF5's own
    error text).  An OSError, so handlers of unreadable files catch it."""


def unreadable_reason(path: str | os.PathLike) -> str:
    """Why `path` cannot be opened as a run file, as one line for the user."""
    p = os.fspath(path)
    expected = "expected a run file (HDF5) written by `slipstrip run`"
    if not os.path.lexists(p):
        return f"'{p}' does not exist: {expected}"
    if os.path.isdir(p):
        inside = sorted(name for name in os.listdir(p) if name.endswith(".h5"))
        hint = f"; it holds {', '.join(inside[:3])}{' ...' if len(inside) > 3 else ''}" if inside else ""
        return f"'{p}' is a directory: {expected}{hint}"
    if not os.path.isfile(p):
        return f"'{p}' is not a regular file: {expected}"
    if not os.access(p, os.R_OK):
        return f"'{p}' is not readable (permissions): {expected}"
    if not h5py.is_hdf5(p):
        return f"'{p}' is not an HDF5 file: {expected}"
    return f"'{p}' is an HDF5 file that cannot be opened (truncated or damaged, or still being created)"


def open_h5(path: str | os.PathLike, attempts: int = 100, wait: float = 0.05) -> h5py.File:
    """h5py.File(path, "r"), retried for up to attempts * wait seconds while a
    running solver holds its write lock: during a write-out (a few ms) the
    writer holds an exclusive lock and opening fails with "unable to lock file".
    Any other failure raises RunFileError saying what the path is instead
    (a directory, missing, not HDF5, damaged)."""
    for i in range(attempts):
        try:
            return h5py.File(path, "r")
        except OSError as e:
            if "lock" in str(e) and i < attempts - 1:
                time.sleep(wait)
                continue
            if "lock" in str(e):
                raise
            raise RunFileError(unreadable_reason(path)) from None
    raise AssertionError("unreachable")


def read_times(f: h5py.File, name: str) -> np.ndarray:
    """A time axis of an open run file (``timeseries/time``, ``snapshots/time``,
    ``stations/time``): every value finite, >= 0 and none below the one before,
    as the solver writes them; else ValueError naming the dataset and the first
    bad row, so a damaged file is reported as such instead of failing later
    inside a reduction over no rows."""
    t = np.asarray(f[name][()], dtype=float)
    if t.ndim != 1:
        raise ValueError(f"{name} has shape {t.shape}: expected one time per row")
    bad = np.flatnonzero(~np.isfinite(t) | (t < 0))
    if bad.size:
        raise ValueError(f"{name}[{bad[0]}] = {t[bad[0]]!r}: expected a finite time >= 0 in every row "
                         "(the run file is damaged)")
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size:
        k = back[0] + 1
        raise ValueError(f"{name}[{k}] = {t[k]!r} is before {name}[{k - 1}] = {t[k - 1]!r}: "
                         "times must not decrease (the run file is damaged)")
    return t


def decode_attr(value: Any) -> Any:
    """An HDF5 attribute as plain Python: bytes -> str, NumPy scalar -> int/float/bool."""
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, np.generic):
        return value.item()
    return value


def read_attrs(path: str | os.PathLike, group: str = "/") -> dict[str, Any]:
    """The attributes of `group` (default: the root), decoded."""
    with open_h5(path) as f:
        return {k: decode_attr(v) for k, v in f[group].attrs.items()}


def is_interface_2d(path: str | os.PathLike) -> bool:
    """True for the run file of a 2D interface (root attribute `format`, docs/3d.md)."""
    return read_attrs(path).get("format", "") == "slipstrip interface_2d"


def require_line(path: str | os.PathLike, command: str, why: str) -> None:
    """ValueError (one line) if `path` is a 2D interface's run file: `command`
    reads one-dimensional interfaces only, for the reason `why`."""
    if is_interface_2d(path):
        raise ValueError(f"{os.fspath(path)} is a 2D interface (geometry.nodes_z > 1): {command} {why}")


def read_config_text(path: str | os.PathLike) -> str:
    """The resolved config (root attribute `config`, TOML text); KeyError if absent."""
    with open_h5(path) as f:
        if "config" not in f.attrs:
            raise KeyError(f"{os.fspath(path)}: no root attribute 'config' (not a slipstrip run file)")
        return str(decode_attr(f.attrs["config"]))


def read_config(path: str | os.PathLike) -> dict:
    """The resolved config as a dict; KeyError if absent."""
    return tomllib.loads(read_config_text(path))


def read_status(path: str | os.PathLike) -> str | None:
    """Root attribute `status` ("running", "completed", "interrupted", "diverged: ...");
    None if there is no readable run file or it has no status."""
    try:
        with open_h5(path) as f:
            status = f.attrs.get("status")
    except (OSError, KeyError):
        return None
    return None if status is None else str(decode_attr(status))


def wall_seconds(path: str | os.PathLike) -> float:
    """end_time - start_time [s] of a run file (1 s resolution); NaN if unknown."""
    try:
        attrs = read_attrs(path)
        start, end = (datetime.datetime.strptime(str(attrs[k]), DATE_FORMAT) for k in ("start_time", "end_time"))
    except (OSError, KeyError, ValueError, TypeError):
        return math.nan
    return (end - start).total_seconds()


def has_group(path: str | os.PathLike, name: str) -> bool:
    with open_h5(path) as f:
        return name in f


def read_event_count(path: str | os.PathLike) -> float:
    """n_events attribute of the /events catalog (kept events), NaN if absent."""
    try:
        with open_h5(path) as f:
            return int(f["events"].attrs["n_events"])
    except (OSError, KeyError):
        return math.nan


class LazyDataset:
    """A dataset of the run file read on indexing (file opened per read).

    ds[...] or np.asarray(ds) reads; ds.shape, ds.units need one short open."""

    def __init__(self, path: str, name: str):
        self.path = path
        self.name = name

    def _meta(self):
        with open_h5(self.path) as f:
            d = f[self.name]
            return d.shape, d.dtype, decode_attr(d.attrs.get("units", ""))

    @property
    def shape(self) -> tuple[int, ...]:
        return self._meta()[0]

    @property
    def dtype(self) -> np.dtype:
        return self._meta()[1]

    @property
    def units(self) -> str:
        return self._meta()[2]

    def __len__(self) -> int:
        return self.shape[0]

    def __getitem__(self, key) -> np.ndarray:
        with open_h5(self.path) as f:
            return f[self.name][key]

    def __array__(self, dtype=None, copy=None):
        a = self[()]
        return a if dtype is None else a.astype(dtype)

    def __repr__(self) -> str:
        shape, dtype, units = self._meta()
        return f"<LazyDataset {self.name} shape={shape} dtype={dtype} units={units!r}>"


class _Group:
    """Lazy view of a group: g["slip"] is a LazyDataset, g.attrs a dict."""

    def __init__(self, path: str, name: str):
        self.path = path
        self.name = name

    def keys(self) -> list[str]:
        with open_h5(self.path) as f:
            return list(f[self.name].keys())

    def __contains__(self, key: str) -> bool:
        return key in self.keys()

    def __getitem__(self, key: str) -> LazyDataset:
        if key not in self.keys():
            raise KeyError(f"{self.name}/{key} is not in {self.path} (has: {', '.join(self.keys())})")
        return LazyDataset(self.path, f"{self.name}/{key}")

    @property
    def attrs(self) -> dict[str, Any]:
        with open_h5(self.path) as f:
            return {k: decode_attr(v) for k, v in f[self.name].attrs.items()}

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name}: {', '.join(self.keys())}>"


class Snapshots(_Group):
    """/snapshots: time [n], x [N] and the fields [n, N], read lazily:
    run.snapshots["slip_rate"][-1] reads only the last snapshot.  A 2D
    interface (docs/3d.md): the fields (slip_x, slip_rate_x, ...) are
    [n, N_z, N] arrays (time, z, x), x and z the node positions of /grid."""

    @property
    def time(self) -> np.ndarray:
        return self["time"][()]

    @property
    def x(self) -> np.ndarray:
        with open_h5(self.path) as f:
            return f["snapshots/x" if "x" in f["snapshots"] else "grid/x"][()]

    @property
    def z(self) -> np.ndarray:
        """Node positions across [m] (a 2D interface; KeyError on a line)."""
        with open_h5(self.path) as f:
            if "grid" not in f:
                raise KeyError(f"{self.path} is a one-dimensional interface: its snapshots have no z")
            return f["grid/z"][()]

    @property
    def trigger(self) -> str:
        return self.attrs.get("trigger", "")

    def __len__(self) -> int:
        return len(self["time"])


class SlipSampling(_Group):
    """/slip_sampling: attributes delta_th, dx, v0, mu, D, L; x; crossing_time [n_levels, N]."""

    @property
    def x(self) -> np.ndarray:
        return self["x"][()]

    @property
    def crossing_time(self) -> LazyDataset:
        return self["crossing_time"]


class RunFile:
    """A run file.  Attributes:

    path, attrs (root attributes), config (resolved config, dict), status,
    code_version, git_hash, units (dataset path -> units), timeseries (dict of
    arrays, read on each access), snapshots (lazy), slip_sampling (lazy, or
    None), events (catalog dict, or None).  Derived: length, height, nodes,
    driving_velocity, shear_wave_speed, length_transit_time (L / c_s)."""

    def __init__(self, path: str | os.PathLike):
        self.path = os.fspath(path)
        if not os.path.exists(self.path):
            raise FileNotFoundError(f"run file '{self.path}' does not exist")
        self.refresh()

    def refresh(self) -> "RunFile":
        """Re-read the root attributes (status changes while a run goes on)."""
        with open_h5(self.path) as f:
            self.attrs = {k: decode_attr(v) for k, v in f.attrs.items()}
            self._groups = set(f.keys())
        text = self.attrs.get("config", "")
        self.config = tomllib.loads(text) if text else {}
        return self

    # --- metadata ---------------------------------------------------------------
    @property
    def status(self) -> str:
        return self.attrs.get("status", "")

    @property
    def code_version(self) -> str:
        return self.attrs.get("code_version", "")

    @property
    def git_hash(self) -> str:
        return self.attrs.get("git_hash", "")

    @property
    def units(self) -> dict[str, str]:
        """Dataset path -> units attribute, e.g. units["timeseries/time"] == "s"."""
        out: dict[str, str] = {}
        with open_h5(self.path) as f:
            def visit(name, obj):
                if isinstance(obj, h5py.Dataset) and "units" in obj.attrs:
                    out[name] = decode_attr(obj.attrs["units"])
            f.visititems(visit)
        return out

    @property
    def units_table(self) -> str:
        """The root `units` attribute (a short text table)."""
        return self.attrs.get("units", "")

    # --- derived scalars (from the resolved config) ------------------------------
    def _cfg(self, section: str, key: str):
        try:
            return self.config[section][key]
        except KeyError:
            raise KeyError(f"[{section}] {key} is not in the config of {self.path}") from None

    @property
    def length(self) -> float:
        return float(self._cfg("geometry", "length"))

    @property
    def height(self) -> float:
        return float(self._cfg("geometry", "height"))

    @property
    def nodes(self) -> int:
        return int(self._cfg("geometry", "nodes"))

    @property
    def interface_2d(self) -> bool:
        """True for a 2D interface (x and z, docs/3d.md): snapshots are maps."""
        return self.attrs.get("format", "") == "slipstrip interface_2d"

    @property
    def width(self) -> float:
        """L_z [m], the period across x of a 2D interface."""
        return float(self._cfg("geometry", "width"))

    @property
    def nodes_z(self) -> int:
        """Nodes across x (1 on a one-dimensional interface)."""
        return int(self.config.get("geometry", {}).get("nodes_z", 1))

    @property
    def driving_velocity(self) -> float:
        return float(self._cfg("loading", "driving_velocity"))

    @property
    def shear_wave_speed(self) -> float:
        return float(np.sqrt(self._cfg("material", "shear_modulus") / self._cfg("material", "density")))

    @property
    def length_transit_time(self) -> float:
        """L / c_s [s]: a shear wave's transit of the period L, the time unit of the
        paper's figures (time.duration_transits).  Not the 2H/c_s of
        scan.height_round_trip_time."""
        return self.length / self.shear_wave_speed

    # --- data ----------------------------------------------------------------------
    @property
    def timeseries(self) -> dict[str, np.ndarray]:
        with open_h5(self.path) as f:
            g = f["timeseries"]
            return {k: g[k][()] for k in g.keys()}

    @property
    def snapshots(self) -> Snapshots:
        return Snapshots(self.path, "snapshots")

    @property
    def slip_sampling(self) -> SlipSampling | None:
        return SlipSampling(self.path, "slip_sampling") if "slip_sampling" in self._groups else None

    @property
    def rupture_front(self) -> np.ndarray | None:
        """First time [s] each node's slip rate exceeded output.front_slip_rate
        (NaN: not yet): [N] on a line, [N_z, N] (z, x) on a 2D interface;
        None without /rupture_front."""
        if "rupture_front" not in self._groups:
            return None
        with open_h5(self.path) as f:
            arrival = f["rupture_front/arrival_time"][()]
        return arrival.reshape(self.nodes_z, -1) if self.interface_2d else arrival

    @property
    def events(self) -> dict[str, Any] | None:
        """The /events catalog (see slipstrip.read_event_catalog), None if absent."""
        with open_h5(self.path) as f:
            present = "events" in f
        if not present:
            return None
        from . import _slipstrip
        return _slipstrip.read_event_catalog(self.path)

    def detect_events(self, **options) -> dict[str, Any]:
        """Detect events from /slip_sampling (options: alpha, min_extent_dx,
        min_mean_slip_dth, exclude_first_last, block_rows, min_slip_rate_v0);
        does not write."""
        from . import _slipstrip
        return _slipstrip.detect_events_in_file(self.path, **options)

    def __repr__(self) -> str:
        return (f"<RunFile {self.path!r} status={self.status!r} L={self.config.get('geometry', {}).get('length')} "
                f"H={self.config.get('geometry', {}).get('height')} N={self.config.get('geometry', {}).get('nodes')}>")


def open_run(path: str | os.PathLike) -> RunFile:
    """Open a run file written by `slipstrip run` or slipstrip.run()."""
    return RunFile(path)
