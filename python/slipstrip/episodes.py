"""`python3 -m slipstrip pulse-episodes`: the periodic-pulse criterion of one
run file, in the late half and window by window.

    python3 -m slipstrip pulse-episodes RUN.h5 [--json OUT.json] [--plot OUT.png [--zoom T0,T1]]
    python3 -m slipstrip pulse-episodes --table OUT1.json OUT2.json ...   (Markdown, one row per run)

The same functions as the report's Fig. 5 rows (slipstrip.analysis.criteria:
periodic_pulse_from_spacetime on the late half, pulse_episodes in windows of
PULSE_EPISODE_WINDOW_TRANSITS L/c_s), for a single run outside a full report
directory, e.g. a resolution check of the Fig. 5 case (docs/fig5_resolution.md).
Needs the run's snapshots, not its event catalog.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys

import numpy as np

from . import analysis as an
from .paths import OutputPathError, check_outputs, one_line
from . import runfile
from .runfile import open_h5, read_config


def pulse_summary(path: str, max_rows: int = 6000,
                  window_transits: float = an.PULSE_EPISODE_WINDOW_TRANSITS) -> dict:
    """The criterion on the late half and in windows of `window_transits` L/c_s,
    with each window's parts and the late half's largest slip rates, as a
    JSON-ready dict.  ValueError if the run has no snapshots."""
    info = an.read_run_info(path)
    st = an.read_spacetime(path, max_rows=max_rows)
    if st is None:
        raise ValueError(f"{path}: no snapshots, the space-time criterion needs them")
    t, x, v = st
    dx = info.L / v.shape[1]
    transit = info.L / info.c_s
    late = an.periodic_pulse_from_spacetime(t, v, info.v0, dx)
    episodes = an.pulse_episodes(t, v, info.v0, dx, window=window_transits * transit)
    windows = []
    for (t0, t1), f, d, r in zip(episodes["windows"], episodes["flags"], episodes["determined"],
                                 episodes["results"]):
        windows.append({"t0_transits": t0 / transit, "t1_transits": t1 / transit, "pulse": f, "determined": d,
                        **{k: r[k] for k in ("min_max_slip_rate_v0", "median_width_fraction", "median_correlation",
                                             "moving_fraction", "travelled_periods", "speed_median")}})
    config = read_config(path)
    peak = None
    with open_h5(path) as f:
        if "timeseries" in f and f["timeseries/time"].shape[0] > 1:
            # The largest slip rate on the interface at every time-series row,
            # over the same late half as the criterion: how violent the state is.
            ts_t = f["timeseries/time"][:]
            ts_v = f["timeseries/max_slip_rate"][:][ts_t >= ts_t[0] + 0.5 * (ts_t[-1] - ts_t[0])] / info.v0
            peak = {"median": float(np.median(ts_v)), "p99": float(np.percentile(ts_v, 99)),
                    "max": float(ts_v.max())}
    initial = config.get("initial", {})
    return {
        "run": os.path.basename(path),  # no machine paths in committed JSON
        "nodes": int(v.shape[1]),
        "beta": config.get("time", {}).get("beta"),
        "initial": {k: initial.get(k) for k in ("noise_amplitude", "noise_seed", "noise_modes",
                                                "local_amplitude", "local_width", "local_center")},
        "duration_transits": float((t[-1] - t[0]) / transit),
        "late_half": {k: (None if isinstance(val, float) and not math.isfinite(val) else val)
                      for k, val in late.items()},
        "late_half_max_slip_rate_v0": peak,
        "window_transits": float(window_transits),
        "windows": windows,
        "pulse_windows": int(sum(w["pulse"] for w in windows)),
        "longest_stretch_transits": [episodes["longest_start"] / transit, episodes["longest_end"] / transit]
        if math.isfinite(episodes["longest_start"]) else None,
    }


def plot(path: str, summary: dict, out: str, zoom: tuple[float, float] | None = None) -> None:
    """The space-time map of log10(v/v0) over t c_s/L, pulse windows marked by
    a red bar at the right edge; with zoom (T0, T1 in L/c_s), every snapshot
    of that stretch only."""
    from . import plots
    info = an.read_run_info(path)
    t, x, v = an.read_spacetime(path, max_rows=None if zoom else 2000)
    transit = info.L / info.c_s
    if zoom:  # every snapshot inside the window [zoom] (in L/c_s)
        keep = (t >= zoom[0] * transit) & (t <= zoom[1] * transit)
        t, v = t[keep], v[keep]
        if t.size < 2:
            raise ValueError(f"--zoom {zoom[0]:g},{zoom[1]:g}: fewer than two snapshots in that stretch")
    fig, ax = plots.plt.subplots(figsize=(4.6, 3.8))
    try:
        im = plots.draw_log_rate(ax, x / info.L, t / transit, v, info.v0, floor=-2.0)
        fig.colorbar(im, ax=ax, label=r"$\log_{10}(v/v_0)$")
        for w in summary["windows"] if not zoom else []:
            if w["pulse"]:
                ax.axhspan(w["t0_transits"], w["t1_transits"], xmin=0.97, xmax=1.0, color="red")
        ax.set_xlabel("x / L")
        ax.set_ylabel(r"$t c_s / L$")
        ax.set_title(f"N = {summary['nodes']}: pulse in {summary['pulse_windows']} of {len(summary['windows'])} "
                     "windows" if not zoom else f"N = {summary['nodes']}, t = {zoom[0]:g}-{zoom[1]:g} L/c_s",
                     fontsize=9)
        fig.tight_layout()
        fig.savefig(out, dpi=110)
    finally:
        plots.plt.close(fig)


def _initial_condition(initial: dict) -> str:
    """The initial perturbation of a run, in words (the table's 'start' column)."""
    parts = []
    if initial.get("noise_amplitude"):
        modes = initial.get("noise_modes") or 0
        kind = "white" if modes == 0 else f"modes 1-{modes}"
        parts.append(f"noise {initial['noise_amplitude']:g} ({kind}), seed {initial.get('noise_seed')}")
    if initial.get("local_amplitude"):
        parts.append(f"bump {initial['local_amplitude']:g} (width {initial.get('local_width'):g} m)")
    return "; ".join(parts) or "none"


def _peak_text(peak: dict | None) -> str:
    return "–" if not peak else f"{peak['median']:.2f} / {peak['p99']:.1f} / {peak['max']:.1f} v0"



def _stretch_text(summary: dict) -> str:
    """The longest stretch of pulse windows, "t0-t1" in whole L/c_s (the window
    bounds are multiples of the window length; the division leaves 60.00000000000001)."""
    stretch = summary.get("longest_stretch_transits")
    return f"{stretch[0]:.0f}-{stretch[1]:.0f}" if stretch else "none"

def markdown_table(summaries: list[dict]) -> str:
    """One row per run, and a total row for several: windows with a pulse; of
    the windows after the first (the start-up), how many move one way
    (criterion part d alone) and their median front speed; the longest pulse
    stretch; the late half."""
    rows = ["| run | N | start | L/c_s | windows with a pulse | after the first window: pulse / moving one way / "
            "all, median speed | longest stretch [L/c_s] | late half: pulse (min peak v, one-way fraction) | "
            "late half: largest slip rate, median / 99 % / max |",
            "|---|---|---|---|---|---|---|---|---|"]
    totals = [0, 0, 0, 0]
    for s in summaries:
        stretch_text = _stretch_text(s)
        lh = s["late_half"]
        rate = lh.get("min_max_slip_rate_v0")
        way = lh.get("moving_fraction")
        late = (f"{'**yes**' if lh['flag'] else 'no'} ({rate:.2f} v0, {way:.2f})"
                if rate is not None and way is not None else "undetermined")
        later = s["windows"][1:]
        pulses = sum(bool(w["pulse"]) for w in later)
        one_way = sum(w["moving_fraction"] >= an.PULSE_MIN_MOVING_FRACTION for w in later)
        speed = float(np.median([w["speed_median"] for w in later])) if later else math.nan
        totals = [totals[0] + s["pulse_windows"], totals[1] + len(s["windows"]), totals[2] + pulses,
                  totals[3] + one_way]
        rows.append(f"| {s['run']} | {s['nodes']} | {_initial_condition(s.get('initial', {}))} | "
                    f"{s['duration_transits']:.0f} | {s['pulse_windows']} of {len(s['windows'])} | "
                    f"{pulses} / {one_way} / {len(later)}, {speed:.0f} m/s | {stretch_text} | {late} | "
                    f"{_peak_text(s.get('late_half_max_slip_rate_v0'))} |")
    if len(summaries) > 1:
        later_total = totals[1] - len(summaries)
        rows.append(f"| **all {len(summaries)}** | | | | {totals[0]} of {totals[1]} | "
                    f"{totals[2]} / {totals[3]} / {later_total} | | | |")
    return "\n".join(rows) + "\n"


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(
        prog="python3 -m slipstrip pulse-episodes",
        description="The periodic-pulse criterion of one run file (docs/analysis.md): on the late half of the "
                    "record and in consecutive windows, with each window's parts; or, with --table, a Markdown "
                    "table of the JSON files written by --json (one row per run).")
    p.add_argument("inputs", nargs="+", metavar="RUN.h5 | JSON",
                   help="one run file (HDF5, with snapshots); with --table: the JSON files of --json")
    p.add_argument("--table", action="store_true", help="print a Markdown table of the given JSON files")
    p.add_argument("--json", help="write the summary (late half, every window) as JSON")
    p.add_argument("--plot", help="write the space-time map with the pulse windows marked (PNG)")
    p.add_argument("--zoom", help="T0,T1: plot only t in [T0, T1] L/c_s, every snapshot")
    p.add_argument("--window-transits", type=float, default=an.PULSE_EPISODE_WINDOW_TRANSITS,
                   help=f"window length in L/c_s (default {an.PULSE_EPISODE_WINDOW_TRANSITS:g}, as the report)")
    p.add_argument("--overwrite", action="store_true", help="replace existing --json / --plot files")
    a = p.parse_args(argv)
    if a.table:
        summaries = []
        for name in a.inputs:
            try:
                with open(name) as fh:
                    summaries.append(json.load(fh))
            except (OSError, ValueError) as err:
                print(f"pulse-episodes: {one_line(f'{name}: {err}')}", file=sys.stderr)
                return 2
        sys.stdout.write(markdown_table(summaries))
        return 0
    if len(a.inputs) != 1:
        p.error("give one run file (or --table with JSON files)")
    if not a.window_transits > 0:
        p.error(f"--window-transits {a.window_transits:g}: must be > 0")
    zoom = None
    if a.zoom:
        try:
            zoom = tuple(float(z) for z in a.zoom.split(","))
        except ValueError:
            zoom = ()
        if len(zoom) != 2 or not zoom[0] < zoom[1]:
            p.error(f"--zoom {a.zoom}: give T0,T1 with T0 < T1 (in L/c_s)")
    (run,) = a.inputs
    outputs = {k: v for k, v in (("--json", a.json), ("--plot", a.plot)) if v}
    try:
        check_outputs(outputs, inputs=[run], overwrite=a.overwrite)
    except OutputPathError as err:
        print(f"pulse-episodes: {err}", file=sys.stderr)
        return 2
    try:
        runfile.require_line(run, "pulse-episodes", "applies the paper's periodic-pulse criterion of a "
                             "one-dimensional interface; use analyze for a 2D interface's events")
        s = pulse_summary(run, window_transits=a.window_transits)
    except (ValueError, OSError, KeyError) as err:
        print(f"pulse-episodes: {one_line(err)}", file=sys.stderr)
        return 2
    text = json.dumps(s, indent=1, default=float)
    if a.json:
        with open(a.json, "w") as fh:
            fh.write(text + "\n")
    lh = s["late_half"]
    print(f"{run}: N = {s['nodes']}, {s['duration_transits']:.1f} L/c_s; late half: pulse = {lh['flag']} "
          f"(min max v {lh['min_max_slip_rate_v0']:.3g} v0, width {lh['median_width_fraction']:.3g} L, "
          f"correlation {lh['median_correlation']:.3g}, moving one way {lh['moving_fraction']:.3g}, "
          f"travelled {lh['travelled_periods']:.3g} L); pulse in {s['pulse_windows']} of {len(s['windows'])} "
          f"windows of {s['window_transits']:g} L/c_s, longest stretch {_stretch_text(s)}")
    for w in s["windows"]:
        print(f"  t = {w['t0_transits']:5.0f}-{w['t1_transits']:5.0f} L/c_s: pulse {str(w['pulse']):5s}  "
              f"min max v {w['min_max_slip_rate_v0']:.3g} v0 (> {an.PULSE_MIN_RATE:g}), "
              f"width {w['median_width_fraction']:.3g} L (<= {an.PULSE_MAX_WIDTH_FRACTION:g}), "
              f"correlation {w['median_correlation']:.3g} (>= {an.PULSE_MIN_CORRELATION:g}), "
              f"one way {w['moving_fraction']:.3g} (>= {an.PULSE_MIN_MOVING_FRACTION:g}), "
              f"travelled {w['travelled_periods']:.3g} L (>= {an.PULSE_MIN_TRAVEL:g}), speed {w['speed_median']:.3g} m/s")
    if a.plot:
        try:
            plot(run, s, a.plot, zoom)
        except ValueError as err:
            print(f"pulse-episodes: {one_line(err)}", file=sys.stderr)
            return 2
    return 0

