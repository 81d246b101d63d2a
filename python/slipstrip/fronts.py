"""`python3 -m slipstrip rupture-fronts`: the two rupture fronts of a run that
nucleates locally, their speeds, and the wave speeds theory compares them with.

    python3 -m slipstrip rupture-fronts RUN.h5 [RUN2.h5 ...] [--center X] [--window D0,D1]
                                        [--json OUT.json] [--plot OUT.png [--titles "A;B"]]

The front is where the slip rate first exceeds `output.front_slip_rate`: the
run file's /rupture_front (one arrival time per node, docs/output.md).  Seen
from the nucleation centre x_c, the nodes on either side (periodic distance
d < L/2) carry the front running towards +x and the one running towards -x.

* Speed over a window: the least-squares slope of d against the arrival time
  for D0 <= d <= D1 (default 0.1 L ... 0.3 L: past the nucleation, and before
  the P waves of the other front reach this one around the period,
  d > L c_f / (c_f + c_d)).
* Limiting speed: a crack-like front accelerates as v(d) ~ c_lim (1 - l/d)
  (Freund's equation of motion, G = (1 - v/c_lim) G_static(d) with G_static
  proportional to the crack length at a fixed stress drop and fracture energy).
  The segment speeds over the window are fitted linearly in 1/d; the
  intercept is c_lim.  This is a model, stated as such in every output.

Wave speeds (plane stress or plane strain, from the run's resolved config):
each body's Rayleigh speed, and for two elastic bodies the generalised
Rayleigh speed of Weertman (1963): the speed c below both shear speeds at which
the normal surface compliances of the two bodies under zero shear traction add
to zero,  sum_i (c^2/c_si^2) sqrt(1 - c^2/c_di^2) / (mu_i R_i(c)) = 0,
R_i(c) = (2 - c^2/c_si^2)^2 - 4 sqrt(1 - c^2/c_si^2) sqrt(1 - c^2/c_di^2).
It exists for moderate contrasts only (None otherwise).

Direction convention: slipstrip's slip rate is V = v_x,top - v_x,bottom > 0
(the outer faces move at +share v0 and -(1 - share) v0).  The more compliant
body is the one with the lower shear-wave speed; it slides towards -x relative
to the other if it is the bottom body, towards +x if it is the top body.  That
direction is the "positive" direction of the bimaterial literature (Weertman
1980; Adams 1995; Andrews & Ben-Zion 1997; Rubin & Ampuero 2007), along which
a front is expected to run at the generalised Rayleigh speed.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
from dataclasses import dataclass

import numpy as np

from .paths import OutputPathError, check_outputs, one_line
from .runfile import open_h5, read_config

DEFAULT_WINDOW = (0.1, 0.3)   # speed window [d/L]: past the nucleation, before the wrap-around
SEGMENTS = 4                  # segments of the window for the 1/d fit of the limiting speed


@dataclass(frozen=True)
class Body:
    """An elastic body's material: shear modulus [Pa], Poisson ratio, density
    [kg/m^3] and the plane condition ("strain" or "stress")."""
    shear_modulus: float
    poisson_ratio: float
    density: float
    plane: str = "strain"

    @property
    def shear_wave_speed(self) -> float:
        return math.sqrt(self.shear_modulus / self.density)

    @property
    def dilatational_wave_speed(self) -> float:
        nu = self.poisson_ratio
        ratio = 2.0 / (1.0 - nu) if self.plane == "stress" else 2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)
        return self.shear_wave_speed * math.sqrt(ratio)


def _bisect(f, lo: float, hi: float) -> float:
    flo = f(lo)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        if (fm < 0) == (flo < 0):
            lo, flo = mid, fm
        else:
            hi = mid
        if hi - lo <= 1e-15 * hi:
            break
    return 0.5 * (lo + hi)


def rayleigh_speed(body: Body) -> float:
    """The Rayleigh speed [m/s]: the root of (2 - x)^2 = 4 sqrt(1 - x) sqrt(1 - x c_s^2/c_d^2),
    x = c^2/c_s^2, in (0, 1)."""
    k = (body.shear_wave_speed / body.dilatational_wave_speed) ** 2
    f = lambda x: (2 - x) ** 2 - 4 * math.sqrt(1 - x) * math.sqrt(1 - x * k)  # noqa: E731
    return body.shear_wave_speed * math.sqrt(_bisect(f, 1e-6, 1.0 - 1e-15))


def _weertman(bodies, c: float) -> float:
    total = 0.0
    for b in bodies:
        x = (c / b.shear_wave_speed) ** 2
        y = (c / b.dilatational_wave_speed) ** 2
        r = (2 - x) ** 2 - 4 * math.sqrt(1 - x) * math.sqrt(1 - y)
        if r == 0.0:
            return math.inf  # exactly on a body's Rayleigh pole
        total += x * math.sqrt(1 - y) / (b.shear_modulus * r)
    return total


def generalised_rayleigh_speed(top: Body, bottom: Body) -> float | None:
    """Weertman's generalised Rayleigh speed [m/s] of two bodies in frictionless
    contact: the zero of the summed normal compliances nearest below the slower
    shear speed, or None where no such wave exists (strong contrasts); for
    identical bodies its limit, the Rayleigh speed.  Each
    term has a pole at its body's Rayleigh speed, so a sign change across a pole
    is not a zero: a bracket is accepted only if |f| shrinks inside it."""
    if top == bottom:
        return rayleigh_speed(top)  # identical bodies: the slip wave is the Rayleigh wave
    bodies = (top, bottom)
    c_max = min(top.shear_wave_speed, bottom.shear_wave_speed) * (1.0 - 1e-9)
    f = lambda c: _weertman(bodies, c)  # noqa: E731
    n = 4000
    for i in range(n - 1, 0, -1):
        lo, hi = c_max * i / n, c_max * (i + 1) / n
        flo, fhi = f(lo), f(hi)
        if (flo < 0) != (fhi < 0):
            z = _bisect(f, lo, hi)
            if abs(f(z)) < max(abs(flo), abs(fhi)):
                return z
    return None


def bodies_of(config: dict) -> tuple[Body, Body | None]:
    """The top and bottom bodies of a resolved config (bottom None: rigid)."""
    m = config.get("material", {})
    plane = m.get("plane", "strain")
    if plane not in ("strain", "stress"):
        raise ValueError(f"material.plane = {plane!r}: rupture-front wave speeds are for in-plane runs "
                         "(\"strain\" or \"stress\")")
    top = Body(float(m["shear_modulus"]), float(m["poisson_ratio"]), float(m["density"]), plane)
    b = config.get("bottom", {})
    kind = b.get("body", "mirror")
    if kind == "rigid":
        return top, None
    if kind == "mirror":
        return top, top
    return top, Body(float(b["shear_modulus"]), float(b["poisson_ratio"]), float(b["density"]), plane)


def positive_direction(top: Body, bottom: Body | None) -> int:
    """+1 or -1: the direction of slip of the more compliant body (lower shear-wave
    speed) for slip rate V = v_x,top - v_x,bottom > 0; 0 for identical wave speeds.
    A rigid bottom is the stiffer body: the top one slides towards +x."""
    if bottom is None:
        return +1
    if top.shear_wave_speed == bottom.shear_wave_speed:
        return 0
    return +1 if top.shear_wave_speed < bottom.shear_wave_speed else -1


def front_branches(x: np.ndarray, arrival: np.ndarray, center: float, length: float) -> dict:
    """The arrival times on either side of `center`: {+1: (d, t), -1: (d, t)}, d the
    periodic distance [m] from the centre (0 < d < L/2), sorted by d; nodes never
    reached (NaN) are dropped."""
    x = np.asarray(x, float)
    arrival = np.asarray(arrival, float)
    offset = (x - center + 0.5 * length) % length - 0.5 * length   # in [-L/2, L/2)
    out = {}
    for sign in (+1, -1):
        sel = (sign * offset > 0) & np.isfinite(arrival)
        d = sign * offset[sel]
        order = np.argsort(d)
        out[sign] = (d[order], arrival[sel][order])
    return out


def front_speed(d: np.ndarray, t: np.ndarray, d_min: float, d_max: float) -> float:
    """Least-squares slope dd/dt [m/s] of the front's distance against its arrival
    time over d_min <= d <= d_max; NaN with fewer than 3 nodes there (a front
    that never got that far)."""
    sel = (d >= d_min) & (d <= d_max)
    if sel.sum() < 3 or np.ptp(t[sel]) <= 0:
        return math.nan
    return float(np.polyfit(t[sel], d[sel], 1)[0])


def limiting_speed(d: np.ndarray, t: np.ndarray, d_min: float, d_max: float,
                   segments: int = SEGMENTS) -> tuple[float, list[tuple[float, float]]]:
    """c_lim of the model v(d) = c_lim (1 - l/d): the speeds of `segments` equal
    segments of [d_min, d_max], fitted linearly against 1/d (their mean distance);
    returns (c_lim, [(mean d, speed), ...]).  NaN if a segment has no speed."""
    edges = np.linspace(d_min, d_max, segments + 1)
    rows = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (d >= lo) & (d <= hi)
        rows.append((float(d[sel].mean()) if sel.any() else math.nan, front_speed(d, t, lo, hi)))
    arr = np.array(rows)
    if not np.all(np.isfinite(arr)):
        return math.nan, rows
    slope, intercept = np.polyfit(1.0 / arr[:, 0], arr[:, 1], 1)
    return float(intercept), rows


def window_extremes(path: str, center: float, length: float, d_min: float, d_max: float) -> dict:
    """From the snapshots, per direction: the largest slip rate [m/s] and the
    smallest and largest normal stress [Pa] (in-plane dissimilar pairs) met on
    the nodes of the window at any snapshot.  {} without snapshots."""
    with open_h5(path) as f:
        if "snapshots" not in f or "slip_rate" not in f["snapshots"] or f["snapshots/time"].shape[0] == 0:
            return {}
        xs = f["snapshots/x"][()]
        v = f["snapshots/slip_rate"][()]
        sigma = f["snapshots/normal_stress"][()] if "normal_stress" in f["snapshots"] else None
    offset = (xs - center + 0.5 * length) % length - 0.5 * length
    out = {}
    for sign in (+1, -1):
        sel = (sign * offset >= d_min) & (sign * offset <= d_max)
        if not sel.any():
            continue
        row = {"max_slip_rate": float(np.max(v[:, sel]))}
        if sigma is not None:
            row["min_normal_stress"] = float(np.min(sigma[:, sel]))
            row["max_normal_stress"] = float(np.max(sigma[:, sel]))
        out[sign] = row
    return out


def nucleation_center(config: dict, x: np.ndarray, arrival: np.ndarray) -> float:
    """The load pulse's centre, else the weak patch's, else the first node to slip."""
    interface, initial = config.get("interface", {}), config.get("initial", {})
    if float(interface.get("load_pulse_amplitude", 0.0)) != 0.0:
        return float(interface["pulse_center"])
    if float(initial.get("local_amplitude", 0.0)) != 0.0:
        return float(initial["local_center"])
    if not np.isfinite(arrival).any():
        raise ValueError("no node reached the rupture-front threshold: no front to measure")
    return float(x[np.nanargmin(arrival)])


def rupture_fronts(path: str, center: float | None = None,
                   window: tuple[float, float] = DEFAULT_WINDOW) -> dict:
    """Both fronts of run file `path`: speed over the window [d/L], the limiting
    speed of the 1/d model, how far each got; with the bodies' wave speeds, the
    generalised Rayleigh speed and which direction is positive.  JSON-ready."""
    config = read_config(path)
    with open_h5(path) as f:
        if "rupture_front" not in f:
            raise ValueError(f"{path}: no /rupture_front; set output.front_slip_rate > 0 to record the fronts")
        arrival = f["rupture_front/arrival_time"][()]
        x = f["rupture_front/x"][()] if "x" in f["rupture_front"] else None
        threshold = float(f["rupture_front"].attrs.get("slip_rate_threshold", math.nan))
    length = float(config["geometry"]["length"])
    if x is None:
        x = np.arange(arrival.size) * length / arrival.size
    if center is None:
        center = nucleation_center(config, x, arrival)
    top, bottom = bodies_of(config)
    c_gr = generalised_rayleigh_speed(top, bottom) if bottom is not None else None
    d_min, d_max = window[0] * length, window[1] * length
    branches = front_branches(x, arrival, center, length)
    positive = positive_direction(top, bottom)
    extremes = window_extremes(path, center, length, d_min, d_max)
    fronts = {}
    for sign, (d, t) in branches.items():
        c_lim, rows = limiting_speed(d, t, d_min, d_max)
        fronts["+x" if sign > 0 else "-x"] = {
            "direction": sign,
            "role": ("positive" if sign == positive else "negative") if positive else "symmetric",
            "speed": front_speed(d, t, d_min, d_max),
            "limiting_speed_1_over_d": c_lim,
            "segments": [{"distance": a, "speed": b} for a, b in rows],
            "reached_distance": float(d.max()) if d.size else 0.0,
            **extremes.get(sign, {}),
        }
    return {
        "run": os.path.basename(path),
        "slip_rate_threshold": threshold,
        "center": center,
        "length": length,
        "window_m": [d_min, d_max],
        "top": {"shear_wave_speed": top.shear_wave_speed, "rayleigh_speed": rayleigh_speed(top),
                "dilatational_wave_speed": top.dilatational_wave_speed},
        "bottom": None if bottom is None else {
            "shear_wave_speed": bottom.shear_wave_speed, "rayleigh_speed": rayleigh_speed(bottom),
            "dilatational_wave_speed": bottom.dilatational_wave_speed},
        "generalised_rayleigh_speed": c_gr,
        "positive_direction": positive,
        "more_compliant_body": (None if positive == 0 else
                                "bottom" if (bottom is not None and positive < 0) else "top"),
        "fronts": fronts,
        "model": "speed: least-squares slope over the window; limiting speed: v(d) = c_lim (1 - l/d) "
                 "fitted to the segment speeds (Freund's equation of motion of a crack tip)",
    }


def format_fronts(summary: dict) -> str:
    lines = [f"{summary['run']}: fronts from x_c = {summary['center']:g} m, threshold "
             f"{summary['slip_rate_threshold']:g} m/s, window d = {summary['window_m'][0]:g}-"
             f"{summary['window_m'][1]:g} m"]
    top, bottom = summary["top"], summary["bottom"]
    lines.append(f"  top: c_s {top['shear_wave_speed']:.1f}, c_R {top['rayleigh_speed']:.1f} m/s"
                 + ("" if bottom is None else
                    f"; bottom: c_s {bottom['shear_wave_speed']:.1f}, c_R {bottom['rayleigh_speed']:.1f} m/s"))
    if summary["generalised_rayleigh_speed"] is not None and summary["positive_direction"] != 0:
        sign = "+x" if summary["positive_direction"] > 0 else "-x"
        lines.append(f"  generalised Rayleigh speed {summary['generalised_rayleigh_speed']:.2f} m/s; "
                     f"more compliant body: {summary['more_compliant_body']}; positive direction {sign}")
    for name, fr in summary["fronts"].items():
        seg = ", ".join(f"{s['speed']:.0f}" for s in fr["segments"])
        lines.append(f"  {name} ({fr['role']}): speed {fr['speed']:.1f} m/s, limiting (1/d model) "
                     f"{fr['limiting_speed_1_over_d']:.1f} m/s, segments [{seg}], reached {fr['reached_distance']:.3f} m")
        if "max_slip_rate" in fr:
            lines.append(f"      in the window: max slip rate {fr['max_slip_rate']:.3g} m/s"
                         + (f", normal stress {fr['min_normal_stress']:.4g}...{fr['max_normal_stress']:.4g} Pa"
                            if "min_normal_stress" in fr else ""))
    return "\n".join(lines)


def _draw_fronts(ax, path: str, summary: dict):
    from . import plots
    with open_h5(path) as f:
        t = f["snapshots/time"][()]
        xs = f["snapshots/x"][()]
        v = f["snapshots/slip_rate"][()]
        arrival = f["rupture_front/arrival_time"][()]
    v0 = float(read_config(path)["loading"]["driving_velocity"])
    length, center = summary["length"], summary["center"]
    x = np.arange(arrival.size) * length / arrival.size
    # x - x_c on (-L/2, L/2]: the nucleation in the middle of the panel
    order = np.argsort((xs - center + 0.5 * length) % length)
    rel = ((xs - center + 0.5 * length) % length - 0.5 * length)[order]
    mesh = plots.draw_log_rate(ax, rel, t * 1e3, v[:, order], v0, vmin=0.0, vmax=6.5)
    c_gr = summary["generalised_rayleigh_speed"]
    c_line = c_gr if c_gr is not None else summary["top"]["rayleigh_speed"]
    d_min = summary["window_m"][0]
    for sign, (d, ta) in front_branches(x, arrival, center, length).items():
        ax.plot(sign * d, ta * 1e3, "k-", lw=0.8)
        if d.size and d.max() >= d_min:
            i = int(np.searchsorted(d, d_min))
            dd = np.linspace(d[i], 0.5 * length, 20)
            ax.plot(sign * dd, (ta[i] + (dd - d[i]) / c_line) * 1e3, "w--", lw=1.0)
    ax.set_xlim(-0.5 * length, 0.5 * length)
    ax.set_ylim(t[0] * 1e3, t[-1] * 1e3)
    ax.set_xlabel(r"$x - x_c$ [m]")
    return mesh, c_line


def plot_fronts(runs, out_png: str, dpi: int = 150) -> str:
    """Space-time maps of log10(v/v0) (slipstrip.plots.draw_log_rate), one panel per
    (path, summary, title) in `runs`, with the measured front (first v above the
    threshold, black) and dashed lines at the generalised Rayleigh speed (the
    Rayleigh speed for identical bodies) from each front's arrival at the start
    of the speed window."""
    from . import plots
    plt = plots.plt
    fig, axes = plt.subplots(1, len(runs), figsize=(3.2 * len(runs) + 0.9, 3.6),
                             constrained_layout=True, squeeze=False)
    try:
        for ax, (path, summary, title) in zip(axes[0], runs):
            mesh, c_line = _draw_fronts(ax, path, summary)
            name = "c_GR" if summary["generalised_rayleigh_speed"] is not None and summary["positive_direction"] \
                else "c_R"
            pos = summary["positive_direction"]
            sub = f"{name} = {c_line:.0f} m/s" + (f"; positive: {'+x' if pos > 0 else '-x'}" if pos else "")
            ax.set_title(f"{title}\n{sub}", fontsize=8)
        axes[0][0].set_ylabel("t [ms]")
        fig.colorbar(mesh, ax=axes[0].tolist()).set_label(r"$\log_{10}(v/v_0)$")
        fig.savefig(out_png, dpi=dpi)
    finally:
        plt.close(fig)
    return out_png


def _json_ready(value):
    """NaN (a front that never got somewhere) as null: strict JSON has no NaN."""
    if isinstance(value, float) and math.isnan(value):
        return None
    if isinstance(value, dict):
        return {k: _json_ready(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_ready(v) for v in value]
    return value


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m slipstrip rupture-fronts",
                                     description="Rupture-front speeds in both directions of a locally "
                                                 "nucleated run, against the Rayleigh and generalised "
                                                 "Rayleigh speeds of its bodies.")
    parser.add_argument("runs", nargs="+", metavar="RUN.h5",
                        help="run file(s) with /rupture_front (output.front_slip_rate > 0)")
    parser.add_argument("--center", type=float, default=None,
                        help="nucleation centre [m] (default: interface.pulse_center, initial.local_center, "
                             "or the first node to slip)")
    parser.add_argument("--window", default=None,
                        help=f"speed window D0,D1 in units of L (default {DEFAULT_WINDOW[0]},{DEFAULT_WINDOW[1]})")
    parser.add_argument("--json", default=None, help="write the summary as JSON (a list for several runs)")
    parser.add_argument("--plot", default=None, help="write the space-time figure, one panel per run (needs snapshots)")
    parser.add_argument("--titles", default=None, help="panel titles separated by ';' (default: the file names)")
    parser.add_argument("--dpi", type=int, default=150, help="resolution of --plot")
    parser.add_argument("--overwrite", action="store_true", help="replace existing --json/--plot files")
    args = parser.parse_args(argv)
    try:
        window = DEFAULT_WINDOW if args.window is None else tuple(float(s) for s in args.window.split(","))
        if len(window) != 2 or not 0.0 <= window[0] < window[1] <= 0.5:
            raise ValueError(f"--window {args.window!r}: expected D0,D1 with 0 <= D0 < D1 <= 0.5 (units of L)")
        titles = [os.path.basename(r) for r in args.runs] if args.titles is None else args.titles.split(";")
        if len(titles) != len(args.runs):
            raise ValueError(f"--titles gives {len(titles)} titles for {len(args.runs)} runs")
        outputs = {k: v for k, v in (("--json", args.json), ("--plot", args.plot)) if v}
        check_outputs(outputs, inputs=list(args.runs), overwrite=args.overwrite)
        summaries = [rupture_fronts(r, center=args.center, window=window) for r in args.runs]
        print("\n".join(format_fronts(s) for s in summaries))
        if args.json:
            with open(args.json, "w") as f:
                json.dump(_json_ready(summaries[0] if len(summaries) == 1 else summaries), f, indent=1,
                          allow_nan=False)
            print(f"wrote {args.json}")
        if args.plot:
            plot_fronts(list(zip(args.runs, summaries, titles)), args.plot, dpi=args.dpi)
            print(f"wrote {args.plot}")
    except (OutputPathError, ValueError, OSError, KeyError) as e:
        print(f"error: {one_line(e)}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
