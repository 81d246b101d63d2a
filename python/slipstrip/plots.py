"""Figures from run files (matplotlib, Agg backend: no display needed).

draw_log_rate(ax, x, y, slip_rate, v0): the one map of log10(|v|/v0) the
package draws -- the space-time fields of `plot`, `analyze`, `report` and
`pulse-episodes`, and the space-slip maps v(x, delta) -- with one colour map
(SPACETIME_CMAP) and one convention for the colour scale.
spacetime(run, out_png): log10(v / v0) over x / L (horizontal) and t c_s / L
(vertical) from /snapshots -- the paper's space-time representation.
timeseries(run, out_png): max slip rate and mean shear stress against time.
interface_2d_maps(run, out_png, times): a 2D interface (docs/3d.md): maps of
log10(|v|/v0) over (x, z) at chosen times with the rupture front drawn as
contours.
interface_2d_spacetime(run, out_png, z=None): a 2D interface's space-time
view: |v| along x on one row of nodes, the largest |v| across z at each x,
and the largest |v| along x at each z, each against t c_s / L.
"""
from __future__ import annotations

import math
import os
import warnings

import matplotlib

matplotlib.use("Agg")  # before pyplot: files only, works without a display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .runfile import RunFile, open_run  # noqa: E402

__all__ = ["SPACETIME_CMAP", "draw_log_rate", "interface_2d_maps", "interface_2d_map_axes",
           "interface_2d_spacetime", "interface_2d_spacetime_axes", "spacetime", "spacetime_axes", "timeseries"]

# Upper bound of cells drawn per axis: a longer run is subsampled (every k-th
# snapshot / node) so memory and drawing time stay bounded whatever the run size.
MAX_CELLS = 2000
# The colour map of every map of log10(v/v0): space-time fields and space-slip
# maps, in `plot`, `analyze`, `report` and `pulse-episodes` alike (all draw
# them with draw_log_rate).
SPACETIME_CMAP = "inferno"


def block_max(z: np.ndarray, max_rows: int, max_cols: int) -> np.ndarray:
    """Block maximum (NaN-aware) of a 2D array to at most max_rows x max_cols:
    unlike a stride it keeps narrow pulses visible.  Trailing rows and columns
    that do not fill a block are dropped; an all-NaN block stays NaN."""
    z = np.asarray(z, float)
    r = max(1, int(math.ceil(z.shape[0] / max_rows)))
    c = max(1, int(math.ceil(z.shape[1] / max_cols)))
    if r == 1 and c == 1:
        return z
    nr, nc = z.shape[0] // r, z.shape[1] // c
    b = z[: nr * r, : nc * c].reshape(nr, r, nc, c)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN blocks
        return np.nanmax(np.nanmax(b, axis=3), axis=1)


def _block_mean(c: np.ndarray, n: int, size: int) -> np.ndarray:
    """Coordinates of the blocks of block_max along one axis (size -> n blocks)."""
    c = np.asarray(c, float)
    step = size // n
    return c[: n * step].reshape(n, step).mean(axis=1)


def draw_log_rate(ax, x, y, slip_rate, v0: float, vmin: float | None = None, vmax: float | None = None,
                  floor: float | None = None, max_cells: int = MAX_CELLS):
    """Draws log10(|slip_rate| / v0) on `ax` and returns the QuadMesh.

    slip_rate is [len(y), len(x)]: rows along the vertical axis (time, or slip
    for a space-slip map), columns along x.  More than max_cells rows or
    columns are reduced by block maxima (narrow pulses stay visible).  The
    colour scale runs from vmin to vmax; by default from the smallest to the
    largest finite value, the minimum not below `floor` when given.  A zero
    slip rate (a stuck node) is drawn at the bottom of the scale, an infinite
    one at the top; NaN (no data) is left blank.  The colour map is
    SPACETIME_CMAP."""
    v = np.abs(np.asarray(slip_rate, float))
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.log10(v / v0)
    rows, cols = z.shape
    z = block_max(z, max_cells, max_cells)
    x = _block_mean(x, z.shape[1], cols) if z.shape[1] != cols else np.asarray(x, float)
    y = _block_mean(y, z.shape[0], rows) if z.shape[0] != rows else np.asarray(y, float)
    finite = np.isfinite(z)
    if not finite.any():
        raise ValueError("no finite positive slip rate to draw")
    lo = float(np.min(z[finite])) if vmin is None else vmin
    if vmin is None and floor is not None:
        lo = max(lo, floor)
    hi = float(np.max(z[finite])) if vmax is None else vmax
    if hi <= lo:  # uniform sliding: give the colour scale a visible width
        lo, hi = lo - 0.5, hi + 0.5
    z = np.where(z == -np.inf, lo, np.where(z == np.inf, hi, z))
    return ax.pcolormesh(x, y, np.ma.masked_invalid(z), shading="nearest", cmap=SPACETIME_CMAP,
                         vmin=lo, vmax=hi, rasterized=True)


def _as_run(run) -> RunFile:
    return run if isinstance(run, RunFile) else open_run(run)


def _format_length(value: float) -> str:
    return "inf" if math.isinf(value) else f"{value:g} m"


def spacetime_axes(run, ax, vmin: float | None = None, vmax: float | None = None,
                   max_cells: int = MAX_CELLS, floor: float | None = None):
    """Draws the space-time map of log10(v/v0) on `ax`; returns the QuadMesh.
    The colour scale runs from vmin to vmax (default: the smallest and largest
    finite value; with `floor`, the automatic minimum is not below it)."""
    run = _as_run(run)
    snaps = run.snapshots
    if "snapshots" not in run._groups or "time" not in snaps or len(snaps) == 0:
        raise ValueError(f"run file '{run.path}' has no snapshots: set [output] snapshot_interval "
                         "or snapshot_slip_increment > 0 to record them")
    n_snap, n_nodes = snaps["slip_rate"].shape
    row_step = max(1, math.ceil(n_snap / max_cells))
    col_step = max(1, math.ceil(n_nodes / max_cells))
    t = snaps.time[::row_step]
    x = snaps.x[::col_step]
    v = snaps["slip_rate"][::row_step, ::col_step]

    L = run.length
    finite = np.isfinite(v) & (v != 0)
    if not finite.any():
        raise ValueError(f"run file '{run.path}': no finite positive slip rate in /snapshots/slip_rate")
    mesh = draw_log_rate(ax, x / L, t * run.shear_wave_speed / L, v, run.driving_velocity, vmin=vmin, vmax=vmax,
                         floor=floor, max_cells=max_cells)
    ax.set_xlabel("x / L")
    ax.set_ylabel(r"t $c_s$ / L")
    ax.set_xlim(0.0, 1.0)
    return mesh


def spacetime(run, out_png: str | os.PathLike, vmin: float | None = None, vmax: float | None = None,
              dpi: int = 150) -> str:
    """Writes the space-time plot of `run` (path or RunFile) to out_png; returns the path."""
    run = _as_run(run)
    fig, ax = plt.subplots(figsize=(6.0, 7.0), constrained_layout=True)
    try:
        mesh = spacetime_axes(run, ax, vmin=vmin, vmax=vmax)
        cbar = fig.colorbar(mesh, ax=ax)
        cbar.set_label(r"$\log_{10}(v / v_0)$")
        ax.set_title(f"H = {_format_length(run.height)}, L = {_format_length(run.length)}, "
                     f"N = {run.nodes}  (status: {run.status})", fontsize=10)
        out = os.fspath(out_png)
        fig.savefig(out, dpi=dpi)
    finally:
        plt.close(fig)
    return out


def timeseries(run, out_png: str | os.PathLike, dpi: int = 150) -> str:
    """Max slip rate / v0 (log scale) and mean shear stress against t c_s / L."""
    run = _as_run(run)
    ts = run.timeseries
    if len(ts.get("time", ())) == 0:
        raise ValueError(f"run file '{run.path}' has an empty /timeseries")
    t = ts["time"] * run.shear_wave_speed / run.length
    fig, (a1, a2) = plt.subplots(2, 1, sharex=True, figsize=(7.0, 5.0), constrained_layout=True)
    try:
        a1.semilogy(t, np.maximum(ts["max_slip_rate"], np.finfo(float).tiny) / run.driving_velocity, lw=0.8)
        a1.set_ylabel(r"max $v$ / $v_0$")
        a2.plot(t, ts["mean_shear_stress"] / 1e6, lw=0.8)
        a2.set_ylabel("mean shear stress [MPa]")
        a2.set_xlabel(r"t $c_s$ / L")
        a1.set_title(f"H = {_format_length(run.height)}, L = {_format_length(run.length)}, N = {run.nodes}",
                     fontsize=10)
        out = os.fspath(out_png)
        fig.savefig(out, dpi=dpi)
    finally:
        plt.close(fig)
    return out


def stability(table_csv, out_png, dpi: int = 150):
    """Plot the table written by `slipstrip stability --out TABLE.csv`.

    Lc(H) table (columns height_m, critical_wavelength_m; a row "inf" holds the
    half-space value): Lc against H as a line, the H -> infinity value as a
    horizontal line, in the style of the supplement's Fig. S2.  Growth-rate
    table (wavelength_m, growth_rate_per_s, frequency_rad_per_s): Re Lambda and
    Im Lambda against wavelength, with the neutral line Re Lambda = 0.
    """
    import csv

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    with open(table_csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{table_csv}: empty table")
    fig, ax = plt.subplots(figsize=(5.5, 4.0))
    if "critical_wavelength_m" in rows[0]:
        finite = [r for r in rows if r["height_m"] != "inf"]
        half = [r for r in rows if r["height_m"] == "inf"]
        h = np.array([float(r["height_m"]) for r in finite])
        lc = np.array([float(r["critical_wavelength_m"]) for r in finite])
        ax.plot(h, lc, color="saddlebrown", lw=2, label=r"$L_c(H)$, linear stability")
        if half:
            ax.axhline(float(half[0]["critical_wavelength_m"]), color="green", lw=1.5,
                       label=r"$L_c(H\to\infty)$")
        ax.set_xlabel(r"strip height $H$ [m]")
        ax.set_ylabel(r"critical wavelength $L_c$ [m]")
        ax.set_ylim(bottom=0)
    elif "growth_rate_per_s" in rows[0]:
        w = np.array([float(r["wavelength_m"]) for r in rows])
        g = np.array([float(r["growth_rate_per_s"]) for r in rows])
        fr = np.array([float(r["frequency_rad_per_s"]) for r in rows])
        ax.plot(w, g, "o-", color="saddlebrown", label=r"Re $\Lambda$ [1/s]")
        ax.plot(w, fr, "s--", color="gray", label=r"Im $\Lambda$ [rad/s]")
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_xlabel(r"wavelength $2\pi/k$ [m]")
        ax.set_ylabel(r"$\Lambda$")
    else:
        raise ValueError(f"{table_csv}: not a table written by `slipstrip stability --out`")
    ax.legend(frameon=False)
    fig.tight_layout()
    fig.savefig(out_png, dpi=dpi)
    plt.close(fig)
    return out_png


def interface_2d_frame(ax, length: float, width: float, title: str) -> None:
    """The axes of a 2D interface drawn to scale: x over [0, length], z over [0, width] [m]."""
    ax.set_xlim(0.0, length)
    ax.set_ylim(0.0, width)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    ax.set_title(title, fontsize=9)


def _interface_2d_snapshots(run):
    """The run, its /snapshots and their times, for the figures of a 2D
    interface: refuses a line or a run without snapshots."""
    run = _as_run(run)
    if not run.interface_2d:
        raise ValueError(f"run file '{run.path}' is not a 2D interface (geometry.nodes_z = 1): "
                         "use spacetime() for its space-time map")
    snaps = run.snapshots
    t = snaps.time
    if len(t) == 0:
        raise ValueError(f"run file '{run.path}' has no snapshots: set [output] snapshot_interval > 0")
    return run, snaps, t


def interface_2d_map_axes(run, axes, times, front_slip_rate: float | None = None,
                          vmin: float | None = None, vmax: float | None = None) -> list[dict]:
    """A 2D interface (docs/3d.md): on each of `axes`, the map of
    log10(|v|/v0) over x (horizontal) and z (vertical) of the snapshot
    nearest to each of `times` [s], one colour scale for all (default: the
    range of the drawn maps), and the rupture front as the contour
    |v| = front_slip_rate (default: the run's output.front_slip_rate, else
    2 v0).  Returns per map: time (of the snapshot), index, the speed map
    [N_z, N] (z, x), the QuadMesh, the front's contour set (None if the map
    has no node on either side of the threshold) and the threshold."""
    run, snaps, t = _interface_2d_snapshots(run)
    x, z = snaps.x, snaps.z
    v0 = run.driving_velocity
    if front_slip_rate is None:
        front_slip_rate = float(run.config.get("output", {}).get("front_slip_rate", 0.0)) or 2.0 * v0
    chosen = [int(np.argmin(np.abs(t - time))) for time in times]
    speeds = [np.hypot(snaps["slip_rate_x"][k], snaps["slip_rate_z"][k]) for k in chosen]
    with np.errstate(divide="ignore"):
        logs = [np.log10(s[s > 0] / v0) for s in speeds]
    finite = np.concatenate([g[np.isfinite(g)] for g in logs])
    if finite.size == 0:
        raise ValueError(f"run file '{run.path}': no positive slip rate in the chosen snapshots")
    lo = float(finite.min()) if vmin is None else vmin
    hi = float(finite.max()) if vmax is None else vmax
    maps = []
    for ax, k, speed in zip(axes, chosen, speeds):
        mesh = draw_log_rate(ax, x, z, speed, v0, vmin=lo, vmax=hi)
        front = None
        if speed.min() < front_slip_rate < speed.max():
            front = ax.contour(x, z, speed, levels=[front_slip_rate], colors="cyan", linewidths=1.0)
        interface_2d_frame(ax, run.length, run.width, f"t = {t[k]:.4g} s")
        maps.append({"time": float(t[k]), "index": k, "speed": speed, "mesh": mesh, "front": front,
                     "front_slip_rate": front_slip_rate})
    return maps


def interface_2d_spacetime_axes(run, axes, z: float | None = None, max_cells: int = MAX_CELLS,
                                vmin: float | None = None, vmax: float | None = None) -> dict:
    """A 2D interface (docs/3d.md) in space and time, on three axes, each
    log10(|v|/v0) against t c_s / L with one colour scale (default: the range
    of the three fields):

    axes[0]: |v| along x on the row of nodes nearest to `z` [m] (default: the
             row that holds the largest |v| of the drawn snapshots), the
             paper's space-time map of one line of the interface;
    axes[1]: the largest |v| across z at each x: every front that crosses x,
             wherever it is in z (a front confined to other rows than
             axes[0]'s shows here and not there);
    axes[2]: the largest |v| along x at each z: how far across the width each
             event reaches.

    |v| is the slip speed hypot(v_x, v_z).  More than max_cells snapshots are
    subsampled (every k-th); each drawn snapshot is read once, so memory stays
    at one map plus the three fields whatever the run's length.  Returns the
    fields ("row" [n, N], "max_over_z" [n, N], "max_over_x" [n, N_z]), the
    snapshot indices and times drawn, the row index and its z, and the three
    QuadMeshes."""
    run, snaps, t = _interface_2d_snapshots(run)
    x, zs = snaps.x, snaps.z
    if z is not None and not (0.0 <= z <= run.width):
        raise ValueError(f"z = {z:g} m lies outside the interface's width [0, {run.width:g}] m")
    indices = np.arange(0, len(t), max(1, math.ceil(len(t) / max_cells)))
    n_z, n_x = len(zs), len(x)
    max_over_z = np.empty((len(indices), n_x))
    max_over_x = np.empty((len(indices), n_z))
    fixed_row = None if z is None else int(np.argmin(np.abs(zs - z)))
    row = np.empty((len(indices), n_x))
    best_row, best_speed = 0, -np.inf
    from .runfile import open_h5
    with open_h5(run.path) as f:
        vx, vz = f["snapshots/slip_rate_x"], f["snapshots/slip_rate_z"]
        for i, k in enumerate(indices):
            speed = np.hypot(vx[k], vz[k])  # [N_z, N]
            max_over_z[i] = speed.max(axis=0)
            max_over_x[i] = speed.max(axis=1)
            if fixed_row is not None:
                row[i] = speed[fixed_row]
            elif speed.max() > best_speed:
                best_speed, best_row = float(speed.max()), int(np.argmax(speed.max(axis=1)))
        if fixed_row is None:
            # The row is known only after the first pass: read it across the
            # drawn snapshots (one hyperslab per component).
            row = np.hypot(vx[indices, best_row, :], vz[indices, best_row, :])
    j = best_row if fixed_row is None else fixed_row
    v0 = run.driving_velocity
    fields = (row, max_over_z, max_over_x)
    with np.errstate(divide="ignore", invalid="ignore"):
        logs = np.concatenate([np.log10(a[a > 0] / v0) for a in fields])
    logs = logs[np.isfinite(logs)]
    if logs.size == 0:
        raise ValueError(f"run file '{run.path}': no positive slip rate in the drawn snapshots")
    lo = float(logs.min()) if vmin is None else vmin
    hi = float(logs.max()) if vmax is None else vmax
    L = run.length
    time_axis = t[indices] * run.shear_wave_speed / L
    meshes = [draw_log_rate(axes[0], x, time_axis, row, v0, vmin=lo, vmax=hi, max_cells=max_cells),
              draw_log_rate(axes[1], x, time_axis, max_over_z, v0, vmin=lo, vmax=hi, max_cells=max_cells),
              draw_log_rate(axes[2], zs, time_axis, max_over_x, v0, vmin=lo, vmax=hi, max_cells=max_cells)]
    titles = (f"|v| on z = {zs[j]:.4g} m", "largest |v| across z", "largest |v| along x")
    for ax, title, label, extent in zip(axes, titles, ("x [m]", "x [m]", "z [m]"), (L, L, run.width)):
        ax.set_title(title, fontsize=9)
        ax.set_xlabel(label)
        ax.set_xlim(0.0, extent)
        ax.set_ylabel(r"t $c_s$ / L")
    return {"row": row, "max_over_z": max_over_z, "max_over_x": max_over_x, "indices": indices,
            "time": t[indices], "row_index": j, "row_z": float(zs[j]), "meshes": meshes}


def interface_2d_spacetime(run, out_png: str | os.PathLike, z: float | None = None,
                           vmin: float | None = None, vmax: float | None = None, dpi: int = 150) -> str:
    """The space-time view of a 2D interface (interface_2d_spacetime_axes) as
    three panels side by side and one colour bar; returns the PNG's path."""
    run = _as_run(run)
    fig, axes = plt.subplots(1, 3, figsize=(13.0, 6.0), constrained_layout=True)
    try:
        drawn = interface_2d_spacetime_axes(run, axes, z=z, vmin=vmin, vmax=vmax)
        fig.colorbar(drawn["meshes"][0], ax=axes.tolist(), label=r"log$_{10}$(|v| / $v_0$)")
        fig.suptitle(f"{os.path.basename(run.path)}: H = {_format_length(run.height)}, "
                     f"L = {_format_length(run.length)}, width {_format_length(run.width)}, "
                     f"{run.nodes} x {run.nodes_z} nodes  (status: {run.status})", fontsize=10)
        out = os.fspath(out_png)
        fig.savefig(out, dpi=dpi)
    finally:
        plt.close(fig)
    return out


def interface_2d_maps(run, out_png: str | os.PathLike, times=None, front_slip_rate: float | None = None,
                      dpi: int = 150) -> str:
    """Slip-rate maps of a 2D interface at `times` [s] (default: four snapshots
    spread over the run) with the rupture-front contours, side by side, and one
    colour bar; returns the PNG's path."""
    run = _as_run(run)
    t = run.snapshots.time
    if times is None:
        times = t[np.linspace(0, len(t) - 1, min(4, len(t))).round().astype(int)] if len(t) else []
    times = list(times)
    if not times:
        raise ValueError("interface_2d_maps: give at least one time")
    fig, axes = plt.subplots(1, len(times), figsize=(3.2 * len(times) + 1.0, 3.4), squeeze=False,
                             constrained_layout=True)
    maps = interface_2d_map_axes(run, axes[0], times, front_slip_rate=front_slip_rate)
    fig.colorbar(maps[0]["mesh"], ax=axes[0].tolist(), label=r"log$_{10}$(|v| / $v_0$)")
    fig.suptitle(f"{os.path.basename(run.path)}: slip rate; rupture front (cyan) |v| = "
                 f"{maps[0]['front_slip_rate']:.3g} m/s", fontsize=9)
    fig.savefig(out_png, dpi=dpi)
    plt.close(fig)
    return os.fspath(out_png)
