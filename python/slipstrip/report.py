"""The paper's quantitative claims side by side with slipstrip (issue 11).

    python3 -m slipstrip report RUNDIR [--out docs/reproduction.md]
        [--figures docs/figures/reproduction] [--allow-missing] [--allow-incomplete]

RUNDIR holds one run file per case, named after its config: RUNDIR/reference.h5
is `slipstrip run configs/reference.toml --out RUNDIR/reference.h5` (then
`slipstrip events RUNDIR/reference.h5`).  The report reads them (never writes
to them), computes every slipstrip number from them or from the linear
stability of the bindings, and writes the Markdown table and the figures anew.

Paper values are the constants of PAPER below, each with its place in the
paper.  No other number of the report is typed by hand.

Exit codes: 0 written; 2 a run file is missing, unreadable or incomplete
(without --allow-missing / --allow-incomplete), or bad arguments.
"""
from __future__ import annotations

import argparse
import dataclasses
import datetime
import math
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import numpy as np
from scipy import stats

from . import analysis as an
from . import runfile
from . import transition

REPO = Path(__file__).resolve().parents[2]

# ---------------------------------------------------------------------------
# Paper values: the only typed-in numbers of the report, with their location
# in the paper (LaTeX source in shared/seed/; main text, captions, supplement).
# ---------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class PaperValue:
    value: object     # number, or a short statement for qualitative claims
    where: str        # location in the paper
    text: str = ""    # how the paper puts it


PAPER = {
    "exp_u": PaperValue(2.45, "Fig. 1c caption", "power law, exponent ~ -2.45 (guide to the eye)"),
    "exp_T": PaperValue(2.2, "Fig. 1d caption", "exponent ~ -2.2"),
    "exp_M0": PaperValue(2.0, "Fig. 1e caption", "exponent ~ -2"),
    "lognormal": PaperValue("log-normal", "Fig. 1d inset; main text 'Statistical complexity'",
                            "large events (u > D) log-normally distributed"),
    "small_slip_fraction": PaperValue(0.08, "main text, discussion of Fig. 2",
                                      "small events carry 8 % of the total slip"),
    "small_nonpropagating": PaperValue("L_s/T > c_d", "main text 'Statistical complexity'",
                                       "u < D: L_s/T significantly larger than c_d (non-propagating)"),
    "fig3a_duration": PaperValue(1.0, "Fig. 3a caption and text",
                                 "event duration comparable to 2H/c_s (H = 0.1 m), then arrest"),
    "fig3b_pulses": PaperValue(2, "Fig. 3b text", "two pulses leave the nucleation site"),
    "fig3b_speed": PaperValue(1.0, "Fig. 3b text", "pulses supershear, close to c_d"),
    "fig3b_width": PaperValue(1.0, "Fig. 3b caption and text", "pulse size ~ H (H = 0.2 m)"),
    "fig3_peak_arrow": PaperValue(1.0, "Fig. 3c/3d captions (arrows at 2H/c_s)",
                                  "large-event peak of p(T) near 2H/c_s"),
    "fig3c_shift": PaperValue("increasing", "Fig. 3c, main text", "peak shifts to larger T with H"),
    "fig3d_shift": PaperValue("increasing", "Fig. 3d, main text", "peak shifts to larger T as c_s decreases"),
    "fig3_collapse": PaperValue("similar", "main text on Fig. 3d",
                                "doubling/halving c_s ~ halving/doubling H ('similar, not strictly identical')"),
    "fig3_small": PaperValue("weak", "Summary and Discussion", "small-event statistics weakly dependent on H, c_s"),
    "fig4_larger": PaperValue("larger", "Fig. 4 caption (a)", "slip law: events span a larger part of the interface"),
    "complexity": PaperValue("complex", "Figs. 4, S10-S12 captions", "complexity retained, exponents as Fig. 1"),
    "fig5_pulse": PaperValue("pulse", "Fig. 5 caption", "periodic travelling pulse after a short coarsening"),
    "fig5_H02": PaperValue("no complexity", "main text, discussion of Fig. 5", "Fig. 5 friction, H = 0.2 m: no complexity"),
    "reference_no_pulse": PaperValue("no pulse", "main text 'Statistical complexity'",
                                     "complex stationary state, no periodic solution"),
    "stationary": PaperValue("stationary", "Fig. S8, Sect. 'Statistical stationarity'",
                             "first and last fifths essentially the same"),
    "alpha": PaperValue("weak effect", "Fig. S9, Sect. 'effect of the threshold'",
                        "alpha = 8, 15, 30, 60: same power law for small events"),
    "clusters": PaperValue("most n_c = 1", "Fig. S6", "most events are a single cluster"),
    "Lc_01": PaperValue(0.35, "main text (Fig. 5 discussion); Fig. S2", "Lc(H = 0.1 m) ~ 0.35 m"),
    "Lc_over_H_01": PaperValue(3.5, "main text (Fig. 5 discussion)", "Lc/H ~ 3.5"),
    "Lc_ratio_005": PaperValue(0.65, "supplement, Sect. 'Lc(H)'", "~65 % of Lc(inf) at H = 0.05 m"),
    "Lc_ratio_01": PaperValue(0.80, "supplement, Sect. 'Lc(H)'", "~80 % of Lc(inf) at H = 0.1 m"),
    "Lc_ratio_02": PaperValue(1.00, "supplement, Sect. 'Lc(H)'", "almost ~100 % at H = 0.2 m"),
    "Lc5_01": PaperValue(0.7, "main text (Fig. 5 discussion)", "Fig. 5 friction: Lc ~ 0.7 m, Lc/H ~ 7"),
    "Lc5_02": PaperValue(0.9, "main text (Fig. 5 discussion)", "Fig. 5 friction, H = 0.2 m: Lc ~ 0.9 m, Lc/H ~ 4.5"),
}

# The run files (RUNDIR/<name>.h5), each made from configs/<name>.toml.
RUNS = {
    "reference": "Fig. 1, 2, S6, S8, S9 (H = 0.1 m, L = 4 m)",
    "fig2_L2": "Fig. 2 (H = 0.1 m, L = 2 m)",
    "fig3a": "Fig. 3a (controlled nucleation, H = 0.1 m)",
    "fig3b": "Fig. 3b (controlled nucleation, H = 0.2 m)",
    "fig3c_H005": "Fig. 3c (H = 0.05 m)",
    "fig3c_H02": "Fig. 3c (H = 0.2 m)",
    "fig3d_rho300": "Fig. 3d (rho = 300, c_s x 2)",
    "fig3d_rho4800": "Fig. 3d (rho = 4800, c_s / 2)",
    "fig4_slip_law": "Fig. 4 (slip law)",
    "fig5": "Fig. 5 (f0 = 0.18, a = 0.015, b = 0.116)",
    "fig5_H02": "Fig. 5 friction at H = 0.2 m (main text, 'not shown')",
    "s10_D_over_3": "Fig. S10 (D / 3)",
    "s11_a_over_3": "Fig. S11 (a / 3)",
    "s12": "Fig. S12 (f0 = 0.313, a = 0.00166, b = 0.067)",
}
STATISTICS_RUNS = ("reference", "fig2_L2", "fig3c_H005", "fig3c_H02", "fig3d_rho300", "fig3d_rho4800", "fig4_slip_law",
                   "fig5", "fig5_H02", "s10_D_over_3", "s11_a_over_3", "s12")
FIG3_FAMILY = ("fig3c_H005", "reference", "fig3c_H02", "fig3d_rho300", "fig3d_rho4800")

# Rules of the verdicts (stated in the doc).
SIGMA_RULE = 2.0        # a value with an error agrees if |slipstrip - paper| <= 2 sigma
RELATIVE_RULE = 0.10    # an exact number (Lc) agrees within 10 %
FACTOR_RULE = 2.0       # an order-of-magnitude claim ("comparable", "~ H") agrees within a factor 2
N_BOOTSTRAP = 200
FRONT_MIN_RATE = 3.0    # slip-rate threshold of the Fig. 3a/b fronts: >= 3 v0 and sqrt(v0 v_peak)


class MissingRun(Exception):
    """A run file that cannot be used; str() is the one-line reason."""


# ---------------------------------------------------------------------------
# Run files
# ---------------------------------------------------------------------------

@dataclasses.dataclass
class Run:
    name: str
    path: Path
    status: str
    config: dict
    start_time: str
    end_time: str
    git_hash: str
    info: an.RunInfo

    @property
    def wall_seconds(self) -> float:
        try:
            t0 = datetime.datetime.strptime(self.start_time, "%Y-%m-%dT%H:%M:%SZ")
            t1 = datetime.datetime.strptime(self.end_time, "%Y-%m-%dT%H:%M:%SZ")
        except (ValueError, TypeError):
            return math.nan
        return (t1 - t0).total_seconds()

    @property
    def length_transit_time(self) -> float:
        """L / c_s [s]"""
        return self.info.L / self.info.c_s


def open_run_file(rundir: Path, name: str, allow_incomplete: bool = False) -> Run:
    """The run RUNDIR/name.h5, or MissingRun naming the file and the reason."""
    path = Path(rundir) / f"{name}.h5"
    shown = f"RUNDIR/{name}.h5"
    if not path.is_file():
        raise MissingRun(f"{shown} missing")
    try:
        attrs = {k: str(v) for k, v in runfile.read_attrs(path).items()
                 if k in ("status", "config", "start_time", "end_time", "git_hash")}
        if "config" not in attrs or not runfile.has_group(path, "timeseries"):
            raise MissingRun(f"{shown} unreadable: not a slipstrip run file (no config or /timeseries)")
        info = an.read_run_info(path)
    except MissingRun:
        raise
    except Exception as err:  # h5py raises OSError, KeyError, ...
        raise MissingRun(f"{shown} unreadable: {str(err).splitlines()[0] if str(err) else type(err).__name__}")
    status = attrs.get("status", "")
    if status != "completed" and not allow_incomplete:
        raise MissingRun(f"{shown} incomplete (status '{status}', t = {info.duration:.4g} s)")
    return Run(name=name, path=path, status=status, config=tomllib.loads(attrs["config"]),
               start_time=attrs.get("start_time", ""), end_time=attrs.get("end_time", ""),
               git_hash=attrs.get("git_hash", ""), info=info)


def material_label(config: dict) -> str:
    """Which reading of Table S1 a run uses, from its resolved config."""
    m = config.get("material", {})
    mu, nu, rho = float(m.get("shear_modulus", math.nan)), float(m.get("poisson_ratio", math.nan)), \
        float(m.get("density", math.nan))
    e = 2 * mu * (1 + nu)
    if abs(e - 9e9) < 1e-6 * 9e9:
        reading = "paper-as-run (E = 9 GPa)"
    elif abs(mu - 9e9) < 1e-6 * 9e9:
        reading = "Table S1 as printed (mu = 9 GPa)"
    else:
        reading = f"mu = {mu / 1e9:.3g} GPa"
    return reading + ("" if rho == 1200.0 else f", rho = {rho:g}")


def wave_speeds(config: dict) -> dict:
    """c_s, c_d and the Rayleigh speed c_R [m/s] of the run's material."""
    m = config["material"]
    mu, nu, rho = float(m["shear_modulus"]), float(m["poisson_ratio"]), float(m["density"])
    cs = math.sqrt(mu / rho)
    if str(m.get("plane", "strain")) == "stress":
        cd = cs * math.sqrt(2.0 / (1.0 - nu))
    else:
        cd = cs * math.sqrt(2.0 * (1.0 - nu) / (1.0 - 2.0 * nu))
    k2 = (cs / cd) ** 2
    from scipy.optimize import brentq
    # Rayleigh equation in xi = (c_R/c_s)^2: (2 - xi)^2 = 4 sqrt(1 - xi) sqrt(1 - k2 xi).
    xi = brentq(lambda q: (2 - q) ** 2 - 4 * math.sqrt(1 - q) * math.sqrt(1 - k2 * q), 1e-6, 1 - 1e-12)
    return {"c_s": cs, "c_d": cd, "c_R": cs * math.sqrt(xi)}


def catalog_of(run: Run, alpha: float, workdir: Path) -> dict:
    """/events of the run file if made with this alpha, else a fresh detection
    into workdir (the run file is never written)."""
    with runfile.open_h5(run.path) as f:
        stored = float(f["events"].attrs["alpha"]) if "events" in f else None
    if stored is not None and stored == float(alpha) and run.status == "completed":
        return an.read_catalog(run.path)
    out = Path(workdir) / f"{run.name}_events_alpha{alpha:g}.h5"
    if not out.exists():
        an.run_event_detection(run.path, alpha, out)
    return an.read_catalog(out)


# ---------------------------------------------------------------------------
# Measurements
# ---------------------------------------------------------------------------

def _finite(x) -> bool:
    try:
        return x is not None and math.isfinite(float(x))
    except (TypeError, ValueError):
        return False


def combined_error(fit_err: float, boot_err: float) -> float:
    """The larger of the Fisher and the bootstrap error (either may be NaN)."""
    vals = [e for e in (fit_err, boot_err) if _finite(e)]
    return max(vals) if vals else math.nan


def bootstrap(values, statistic, n: int = N_BOOTSTRAP, seed: int = 0) -> float:
    """Bootstrap standard error of statistic(values)."""
    x = np.asarray(values)
    if x.shape[0] < 2:
        return math.nan
    rng = np.random.default_rng(seed)
    reps = [statistic(x[rng.integers(0, x.shape[0], x.shape[0])]) for _ in range(n)]
    reps = np.asarray(reps, float)
    reps = reps[np.isfinite(reps)]
    return float(np.std(reps, ddof=1)) if reps.size > 1 else math.nan


def peak_of_pT(T, grid_points: int = 512) -> float:
    """Mode of p(T) (density per unit T, as plotted in Fig. 3c/d) of the
    samples T > 0: a Gaussian kernel density of ln T (Scott's bandwidth),
    p(T) = p_lnT(ln T) / T maximised on a grid.  NaN for < 10 samples."""
    x = np.log(np.asarray(T, float)[np.asarray(T, float) > 0])
    if x.size < an.MIN_FIT_EVENTS or np.ptp(x) == 0:
        return math.nan
    kde = stats.gaussian_kde(x)
    g = np.linspace(x.min() - 0.5, x.max() + 0.5, grid_points)
    return float(math.exp(g[np.argmax(np.log(np.maximum(kde(g), 1e-300)) - g)]))


def local_peaks_of_pT(T, grid_points: int = 512, min_relative_height: float = 0.1) -> list[tuple[float, float]]:
    """Every local maximum of the same density p(T) as `peak_of_pT`, as (T, height
    relative to the highest), highest first; maxima lower than
    `min_relative_height` are dropped.  A bimodal large-event p(T) (e.g. short
    bursts plus events lasting ~2H/c_s) is then visible in the report instead of
    being reduced to whichever mode happens to be higher."""
    x = np.log(np.asarray(T, float)[np.asarray(T, float) > 0])
    if x.size < an.MIN_FIT_EVENTS or np.ptp(x) == 0:
        return []
    kde = stats.gaussian_kde(x)
    g = np.linspace(x.min() - 0.5, x.max() + 0.5, grid_points)
    log_p = np.log(np.maximum(kde(g), 1e-300)) - g
    inner = np.flatnonzero((log_p[1:-1] > log_p[:-2]) & (log_p[1:-1] > log_p[2:])) + 1
    heights = np.exp(log_p[inner] - log_p[inner].max()) if inner.size else np.zeros(0)
    peaks = [(float(math.exp(g[i])), float(h)) for i, h in zip(inner, heights) if h >= min_relative_height]
    return sorted(peaks, key=lambda p: -p[1])


def statistics_of(run: Run, workdir: Path, n_bootstrap: int = N_BOOTSTRAP) -> dict:
    """Transient cut, stationarity, fits and regime of one statistics run."""
    catalog = catalog_of(run, an.DEFAULT_ALPHA, workdir)
    part = an.stationary_part(catalog, run.info)
    kept = part["catalog"]
    st = an.catalog_statistics(kept, run.info, n_bootstrap=n_bootstrap)
    obs = an.normalised_observables(kept, run.info)
    small = obs["u"] < 1.0
    large = ~small
    res = {"run": run, "catalog": catalog, "part": part, "kept": kept, "stats": st, "obs": obs}
    res["pulse"] = an.periodic_pulse_of_run(run.path, catalog, run.info)
    # One definition of "complexity" for the report and the transition map: the
    # multi-observable classifier of transition.py (docs/transition.md), not a
    # looser rule of its own (a run with 95 % of its slip in system-spanning
    # ruptures is coarsened, however many small events it also has).
    res["regime"] = transition.classify_run(run.path)
    res["complex"] = res["regime"]["state"] == "complex"
    T_large = np.asarray(kept["T"], float)[large]
    res["T_peak"] = peak_of_pT(T_large)
    res["T_local_peaks"] = local_peaks_of_pT(T_large)
    res["T_peak_err"] = bootstrap(T_large, peak_of_pT, n=n_bootstrap) if _finite(res["T_peak"]) else math.nan
    res["tau"] = 2 * run.info.H / run.info.c_s
    return res


def ring_components(mask: np.ndarray) -> list[np.ndarray]:
    """Connected runs of True on a periodic ring of nodes (node N-1 neighbours node 0)."""
    m = np.asarray(mask, bool)
    n = m.size
    if not m.any():
        return []
    if m.all():
        return [np.arange(n)]
    start = int(np.argmin(m))  # a False node: rotate so that no run wraps
    r = np.roll(m, -start)
    d = np.diff(np.concatenate(([0], r.astype(int), [0])))
    begins, ends = np.nonzero(d == 1)[0], np.nonzero(d == -1)[0]
    return [(np.arange(b, e) + start) % n for b, e in zip(begins, ends)]


def nucleation_event(time, x, slip_rate, v0: float, x0: float, L: float, c_d: float) -> dict:
    """Fronts of the rupture nucleated at x0 (Fig. 3a/b), from snapshots.

    A node slips when v > v_th = max(FRONT_MIN_RATE v0, sqrt(v0 v_peak)), half-way
    on the log colour scale between v0 and v_peak, the largest slip rate at x0
    during its first stretch above FRONT_MIN_RATE v0.  The event
    starts at the first snapshot where the node nearest x0 slips; its region
    is the slipping component holding x0, then, snapshot by snapshot, every
    slipping component within c_d dt + 2 dx of the previous region.  It ends
    (arrest) when the region is empty, or when it reaches the antipode
    (traversal).  Measured: duration of slip at x0, front positions relative
    to x0, front speeds (least squares over 20-80 % of each front's largest
    offset), the number and widths of the pulses (components of the region
    while x0 no longer slips)."""
    t = np.asarray(time, float)
    v = np.abs(np.asarray(slip_rate, float))
    n = v.shape[1]
    dx = L / n
    i0 = int(np.argmin(np.abs(((np.asarray(x) - x0 + L / 2) % L) - L / 2)))
    # Peak of the nucleated event: the largest slip rate at x0 during its first
    # stretch above FRONT_MIN_RATE v0 (later events do not set the threshold).
    above = np.nonzero(v[:, i0] > FRONT_MIN_RATE * v0)[0]
    if above.size:
        stop = np.nonzero(np.diff(above) > 1)[0]
        last = above[stop[0]] if stop.size else above[-1]
        v_peak = float(v[above[0]: last + 1, i0].max())
    else:
        v_peak = float(v[:, i0].max())
    v_th = max(FRONT_MIN_RATE * v0, math.sqrt(v0 * v_peak))
    slipping = v > v_th
    out = {"v_th": v_th, "v_peak": v_peak, "found": False}
    start = np.nonzero(slipping[:, i0])[0]
    if start.size == 0:
        return out
    k0 = int(start[0])
    offsets = ((np.arange(n) - i0 + n // 2) % n) - n // 2  # signed node offsets from x0
    comps = ring_components(slipping[k0])
    region = next(c for c in comps if i0 in set(c.tolist()))
    rows = []
    k_end, reason = None, "end of run"
    center_end = None
    for k in range(k0, t.size):
        if k > k0:
            margin = int(math.ceil(c_d * (t[k] - t[k - 1]) / dx)) + 2
            near = np.zeros(n, bool)
            for off in range(-margin, margin + 1):
                near[(region + off) % n] = True
            comps = [c for c in ring_components(slipping[k]) if near[c].any()]
            region = np.concatenate(comps) if comps else np.array([], int)
        if region.size == 0:
            k_end, reason = k, "arrest"
            break
        if center_end is None and not slipping[k, i0]:
            center_end = k
        off = offsets[region]
        pulses = [] if slipping[k, i0] else [c.size * dx for c in ring_components(np.isin(np.arange(n), region))]
        rows.append((t[k], off.max() * dx, off.min() * dx, pulses))
        if off.max() >= n // 2 - 1 or off.min() <= -(n // 2) + 1 or region.size >= n - 2:
            k_end, reason = k, "traversal"
            break
    if center_end is None:
        center_end = k_end if k_end is not None else t.size - 1
    tr = np.array([r[0] for r in rows])
    right = np.array([r[1] for r in rows])
    left = -np.array([r[2] for r in rows])
    snap_dt = float(np.median(np.diff(t))) if t.size > 1 else math.nan
    out.update(found=True, t_start=float(t[k0]), end_reason=reason,
               t_end=float(t[k_end]) if k_end is not None else float(t[-1]),
               center_duration=float(t[center_end] - t[k0]), snapshot_interval=snap_dt,
               max_extent=float(right.max() + left.max() + dx), times=tr, right=right, left=left)
    speeds, errs = [], []
    for front in (right, left):
        top = front.max()
        sel = (front >= 0.2 * top) & (front <= 0.8 * top)
        if sel.sum() >= 3 and np.ptp(tr[sel]) > 0:
            r = stats.linregress(tr[sel], front[sel])
            speeds.append(r.slope)
            errs.append(math.hypot(r.stderr, dx / np.ptp(tr[sel])))
    out["front_speeds"] = speeds
    out["front_speed"] = float(np.mean(speeds)) if speeds else math.nan
    out["front_speed_err"] = (float(max(max(errs), 0.5 * abs(speeds[0] - speeds[-1]))) if speeds else math.nan)
    # Pulses: snapshots where x0 no longer slips and the fronts are 25-45 % of L away.
    counts, widths = [], []
    for (tk, rk, lk, pulses) in rows:  # lk: most negative offset
        if pulses and min(rk, -lk) >= 0.25 * L and max(rk, -lk) <= 0.45 * L:
            counts.append(len(pulses))
            widths.extend(pulses)
    out["n_pulses"] = int(np.median(counts)) if counts else 0
    out["pulse_width"] = float(np.median(widths)) if widths else math.nan
    out["pulse_width_err"] = (float(0.5 * (np.quantile(widths, 0.75) - np.quantile(widths, 0.25)) + dx)
                              if widths else math.nan)
    return out


# ---------------------------------------------------------------------------
# Verdicts and formatting
# ---------------------------------------------------------------------------

def fmt(x, err=None, digits=3) -> str:
    if not _finite(x):
        return "n/a"
    s = f"{x:.{digits}g}"
    if err is not None:
        s += f" ± {err:.2g}" if _finite(err) else " ± n/a"
    return s


def verdict_sigma(value, err, paper) -> str:
    if not (_finite(value) and _finite(err)):
        return "no value"
    d = value - paper
    k = abs(d) / err if err > 0 else math.inf
    return (f"agrees ({k:.1f} σ)" if k <= SIGMA_RULE else f"differs by {d:+.2g} ({k:.1f} σ)")


def verdict_relative(value, paper) -> str:
    if not _finite(value):
        return "no value"
    r = value / paper - 1
    return f"agrees ({r:+.0%})" if abs(r) <= RELATIVE_RULE else f"differs by {r:+.0%}"


def verdict_factor(ratio) -> str:
    """ratio = slipstrip / paper scale."""
    if not _finite(ratio) or ratio <= 0:
        return "no value"
    return (f"agrees (ratio {ratio:.2g})" if 1 / FACTOR_RULE <= ratio <= FACTOR_RULE
            else f"differs (ratio {ratio:.2g})")


def xmin_sweep_cell(sweep: list[dict]) -> str:
    """The exponents of analysis.exponent_xmin_sweep, one per x_min."""
    if not sweep:
        return "n/a (too few events)"
    parts = [f"x_min = {fmt(f['xmin_factor'], digits=2)} x_opt: {fmt(f['exponent'], f['stderr'])} (n = {f['n']})"
             for f in sweep]
    lo, hi = min(f["exponent"] for f in sweep), max(f["exponent"] for f in sweep)
    return "; ".join(parts) + f"; range {fmt(lo)}-{fmt(hi)} (x_opt: the KS-optimal x_min of the row above)"


def verdict_xmin_sweep(sweep: list[dict], paper: float) -> str:
    """Agrees if the paper's value lies within the sweep's exponents widened by
    SIGMA_RULE of their statistical errors: the slope of a guide to the eye
    (no stated fit range) cannot be held to a tighter standard."""
    if not sweep:
        return "no value"
    lo = min(f["exponent"] - SIGMA_RULE * f["stderr"] for f in sweep)
    hi = max(f["exponent"] + SIGMA_RULE * f["stderr"] for f in sweep)
    if lo <= paper <= hi:
        return f"agrees within the fit-range systematic ({lo:.3g}-{hi:.3g})"
    return f"differs even allowing for the fit range ({lo:.3g}-{hi:.3g})"


def verdict_bool(ok, detail="") -> str:
    if ok is None:
        return "no value"
    return ("agrees" if ok else "differs") + (f" ({detail})" if detail else "")


@dataclasses.dataclass
class Row:
    claim: str
    paper: str
    value: str
    verdict: str
    basis: str       # run(s) and material reading


def paper_cell(key: str, value_fmt=None) -> str:
    p = PAPER[key]
    v = value_fmt(p.value) if value_fmt else (f"{p.value:g}" if isinstance(p.value, (int, float)) else p.value)
    return f"{v} — {p.text} [{p.where}]"


# ---------------------------------------------------------------------------
# The report
# ---------------------------------------------------------------------------

class Report:
    def __init__(self, rundir: Path, figdir: Path, allow_missing: bool, allow_incomplete: bool,
                 doc_dir: Path, workdir: Path, n_bootstrap: int = N_BOOTSTRAP,
                 alphas=an.SENSITIVITY_ALPHAS, log=print):
        self.rundir, self.figdir, self.doc_dir, self.workdir = Path(rundir), Path(figdir), Path(doc_dir), Path(workdir)
        self.allow_missing, self.allow_incomplete = allow_missing, allow_incomplete
        self.n_bootstrap, self.alphas, self.log = n_bootstrap, alphas, log
        self.runs: dict[str, Run] = {}
        self.missing: dict[str, str] = {}
        self.rows: list[tuple[str, Row]] = []   # (section, row)
        self.figures: list[tuple[str, str]] = []  # (caption, relative path)
        self.stats: dict[str, dict] = {}
        self.stationarity_rows: list[list[str]] = []

    # -- inputs -------------------------------------------------------------
    def load(self):
        for name in RUNS:
            try:
                self.runs[name] = open_run_file(self.rundir, name, self.allow_incomplete)
            except MissingRun as err:
                if not self.allow_missing:
                    raise
                self.missing[name] = str(err)

    def not_run(self, *names) -> str | None:
        why = [self.missing[n] for n in names if n in self.missing]
        return f"not run ({'; '.join(why)})" if why else None

    def stat(self, name) -> dict | None:
        if name in self.missing:
            return None
        if name not in self.stats:
            self.log(f"report: statistics of {name}")
            self.stats[name] = statistics_of(self.runs[name], self.workdir, self.n_bootstrap)
        return self.stats[name]

    def add(self, section, claim, paper, value, verdict, basis):
        self.rows.append((section, Row(claim, paper, value, verdict, basis)))

    def add_missing(self, section, claim, paper, names):
        self.add(section, claim, paper, self.not_run(*names), "—", ", ".join(names))

    def basis(self, *names) -> str:
        labels = {material_label(self.runs[n].config) for n in names if n in self.runs}
        return ", ".join(names) + ("; " + "; ".join(sorted(labels)) if labels else "")

    def figure(self, caption, name):
        rel = os.path.relpath(self.figdir / name, self.doc_dir)
        self.figures.append((caption, rel.replace(os.sep, "/")))

    # -- sections -----------------------------------------------------------
    def fig1(self):
        sec = "Fig. 1: statistics of the reference case"
        s = self.stat("reference")
        for key, obs, label in (("exp_u", "u", "p(u/D)"), ("exp_T", "T", "p(T v0/D)"), ("exp_M0", "M0", "p(M0/(mu D L))")):
            claim = f"small-event (u < D) exponent of {label}"
            if s is None:
                self.add_missing(sec, claim, paper_cell(key), ["reference"])
                continue
            st = s["stats"]
            a = st[f"small_exponent_{obs}"]
            e = combined_error(st[f"small_exponent_{obs}_err"], st[f"small_exponent_{obs}_bootstrap_err"])
            value = (f"{fmt(a, e)} (MLE of a truncated power law, n = {st[f'small_exponent_{obs}_n']}, "
                     f"x_min = {fmt(st[f'small_exponent_{obs}_xmin'])}; error: larger of Fisher and bootstrap)")
            self.add(sec, claim, paper_cell(key), value, verdict_sigma(a, e, PAPER[key].value), self.basis("reference"))
            sweep = st.get(f"small_exponent_{obs}_xmin_sweep", [])
            self.add(sec, f"{claim}: dependence on the fit's lower cut-off x_min (systematic)", paper_cell(key),
                     xmin_sweep_cell(sweep), verdict_xmin_sweep(sweep, PAPER[key].value), self.basis("reference"))
        for obs, label in (("T", "T v0/D"), ("u", "u/D"), ("M0", "M0/(mu D L)")):
            claim = f"large events (u ≥ D) log-normal: {label}"
            if s is None:
                self.add_missing(sec, claim, paper_cell("lognormal"), ["reference"])
                continue
            lf = s["stats"][f"lognormal_{obs}"]
            value = (f"mu = {fmt(lf['mu'])}, sigma = {fmt(lf['sigma'])}, n = {lf['n']}, KS = {fmt(lf['ks'])}, "
                     f"parametric-bootstrap p = {fmt(lf['ks_pvalue'])} (naive p = {fmt(lf['ks_pvalue_naive'])})")
            p = lf["ks_pvalue"]
            verdict = ("no value" if not _finite(p) else
                       f"agrees (not rejected at 5 %, p = {p:.2g})" if p >= 0.05 else f"differs (rejected, p = {p:.2g})")
            self.add(sec, claim, paper_cell("lognormal"), value, verdict, self.basis("reference"))
        claim = "slip fraction carried by small events"
        if s is None:
            self.add_missing(sec, claim, paper_cell("small_slip_fraction"), ["reference"])
        else:
            u, Ls = np.asarray(s["kept"]["u_mean"]), np.asarray(s["kept"]["L_s"])
            D, L = s["run"].info.D, s["run"].info.L
            f = an.slip_fractions(u, Ls, D, L)["small"]
            err = bootstrap(np.column_stack([u, Ls]), lambda a: an.slip_fractions(a[:, 0], a[:, 1], D, L)["small"],
                            n=self.n_bootstrap)
            self.add(sec, claim, paper_cell("small_slip_fraction"), f"{fmt(f, err)} (bootstrap over events)",
                     verdict_sigma(f, err, PAPER["small_slip_fraction"].value), self.basis("reference"))

    def fig2(self):
        sec = "Fig. 2: event hierarchy"
        # The paper's statement is about small events (L_s/T well above c_d: not
        # constrained by causality).  Large events are "propagating", i.e.
        # constrained by causality: a bilateral rupture widens at both ends, so
        # its extent grows at most at 2 c_d, L_s/T <= 2 c_d.
        claim = ("small events (u < D) non-propagating (L_s/T > c_d), large ones propagating "
                 "(causal: L_s/T <= 2 c_d for bilateral growth)")
        for name in ("fig2_L2", "reference"):
            s = self.stat(name)
            if s is None:
                self.add_missing(sec, claim, paper_cell("small_nonpropagating"), [name])
                continue
            k = s["kept"]
            cd = wave_speeds(s["run"].config)["c_d"]
            T, Ls = np.asarray(k["T"], float), np.asarray(k["L_s"], float)
            small = s["obs"]["u"] < 1.0
            ok = T > 0
            rs, rl = (Ls / np.where(ok, T, 1.0))[ok & small], (Ls / np.where(ok, T, 1.0))[ok & ~small]
            ms, ml = (float(np.median(rs)) if rs.size else math.nan), (float(np.median(rl)) if rl.size else math.nan)
            es, el = bootstrap(rs, np.median, n=self.n_bootstrap), bootstrap(rl, np.median, n=self.n_bootstrap)
            value = (f"median L_s/T: small {fmt(ms / cd, es / cd)} c_d (n = {rs.size}, {np.mean(rs > cd):.0%} above "
                     f"c_d), large {fmt(ml / cd, el / cd)} c_d (n = {rl.size}, {np.mean(rl > 2 * cd):.0%} above "
                     f"2 c_d); T = 0 events ({int((~ok).sum())}) left out; L = {s['run'].info.L:g} m "
                     f"(paper's Fig. 2: 2 m)")
            good = None if not (_finite(ms) and _finite(ml)) else bool(ms - SIGMA_RULE * es > cd and
                                                                       ml + SIGMA_RULE * el <= 2 * cd)
            self.add(sec, claim, paper_cell("small_nonpropagating"), value, verdict_bool(good), self.basis(name))

    def fig3ab(self):
        sec = "Fig. 3a/3b: controlled nucleation"
        for name, H in (("fig3a", "0.1"), ("fig3b", "0.2")):
            claims = ([("fig3a_duration", "H = 0.1 m: slip at the nucleation site lasts ~2H/c_s, then the rupture arrests")]
                      if name == "fig3a" else
                      [("fig3b_pulses", "H = 0.2 m: two pulses leave the nucleation site and traverse the interface"),
                       ("fig3b_speed", "H = 0.2 m: pulse (front) speed close to c_d"),
                       ("fig3b_width", "H = 0.2 m: pulse width ~ H")])
            if name in self.missing:
                for key, claim in claims:
                    self.add_missing(sec, claim, paper_cell(key), [name])
                continue
            run = self.runs[name]
            ws = wave_speeds(run.config)
            tau = 2 * run.info.H / run.info.c_s
            with runfile.open_h5(run.path) as f:
                t, x, v = f["snapshots/time"][:], f["snapshots/x"][:], f["snapshots/slip_rate"][:]
            x0 = float(run.config.get("initial", {}).get("local_center", run.info.L / 2))
            ev = nucleation_event(t, x, v, run.info.v0, x0, run.info.L, ws["c_d"])
            self._spacetime_figure(name, t, x, v, run, ws, ev, tau)
            if not ev["found"]:
                for key, claim in claims:
                    self.add(sec, claim, paper_cell(key), f"no slip above {fmt(ev['v_th'] / run.info.v0)} v0 at x0",
                             "no value", self.basis(name))
                continue
            speed = (f"front speed {fmt(ev['front_speed'] / ws['c_d'], ev['front_speed_err'] / ws['c_d'])} c_d "
                     f"= {fmt(ev['front_speed'] / ws['c_s'], ev['front_speed_err'] / ws['c_s'])} c_s")
            common = (f"threshold v > {fmt(ev['v_th'] / run.info.v0)} v0; snapshots every "
                      f"{fmt(ev['snapshot_interval'] / tau)} (2H/c_s)")
            for key, claim in claims:
                if key == "fig3a_duration":
                    r = ev["center_duration"] / tau
                    arrested = ev["end_reason"] == "arrest" and ev["max_extent"] < 0.9 * run.info.L
                    value = (f"duration at x0 {fmt(r, ev['snapshot_interval'] / tau)} (2H/c_s); event ends by "
                             f"{ev['end_reason']} after {fmt((ev['t_end'] - ev['t_start']) / tau)} (2H/c_s), extent "
                             f"{fmt(ev['max_extent'] / run.info.L)} L; {speed}; {common}")
                    v_ = verdict_factor(r)
                    verdict = v_ if arrested else f"differs (no arrest: {ev['end_reason']}); duration {v_}"
                elif key == "fig3b_pulses":
                    value = (f"{ev['n_pulses']} pulse(s) while the fronts are 0.25-0.45 L from x0; event ends by "
                             f"{ev['end_reason']} (extent {fmt(ev['max_extent'] / run.info.L)} L); {common}")
                    verdict = verdict_bool(ev["n_pulses"] == 2 and ev["end_reason"] == "traversal",
                                           f"{ev['n_pulses']} pulses, {ev['end_reason']}")
                elif key == "fig3b_speed":
                    value = f"{speed}; c_R = {fmt(ws['c_R'] / ws['c_d'])} c_d, c_s = {fmt(ws['c_s'] / ws['c_d'])} c_d"
                    verdict = verdict_sigma(ev["front_speed"] / ws["c_d"], max(ev["front_speed_err"] / ws["c_d"], 0.05), 1.0) \
                        + " (σ at least 0.05 c_d)"
                else:
                    r = ev["pulse_width"] / run.info.H
                    value = (f"width {fmt(r, ev['pulse_width_err'] / run.info.H)} H (median over snapshots with the "
                             f"fronts 0.25-0.45 L from x0; error: half inter-quartile range + dx); {common}")
                    verdict = verdict_factor(r)
                self.add(sec, claim, paper_cell(key), value, verdict, self.basis(name))

    def _spacetime_figure(self, name, t, x, v, run, ws, ev, tau):
        plt = an._plt()
        L, cs = run.info.L, run.info.c_s
        z = _downsample(np.log10(np.maximum(np.abs(v), 1e-6 * run.info.v0) / run.info.v0), 500, 400)
        fig, ax = plt.subplots(figsize=(4.6, 3.8))
        im = ax.imshow(z, origin="lower", aspect="auto", cmap="viridis", vmin=-2,
                       extent=(0, 1, t[0] * cs / L, t[-1] * cs / L))
        fig.colorbar(im, ax=ax, label=r"$\log_{10}(v/v_0)$")
        if ev.get("found"):
            x0 = float(run.config.get("initial", {}).get("local_center", L / 2)) / L
            t0 = ev["t_start"] * cs / L
            dt = np.linspace(0, (t[-1] - ev["t_start"]) * cs / L, 2)
            for key, style in (("c_R", ":"), ("c_s", "--"), ("c_d", "-")):
                c = ws[key] / cs
                for sgn in (1, -1):
                    ax.plot(x0 + sgn * c * dt, t0 + dt, "w" + style, lw=0.8, label=key if sgn > 0 else None)
            ax.plot([x0, x0], [t0, t0 + tau * cs / L], "w-", lw=3, label="2H/c_s")
            if name == "fig3b":
                ax.plot([0.8, 0.8 + run.info.H / L], [t0 + 0.3, t0 + 0.3], "r-", lw=3, label="H")
            ax.set_xlim(0, 1)
            ax.set_ylim(t[0] * cs / L, t[-1] * cs / L)
            ax.legend(fontsize=6, loc="upper left")
        ax.set_xlabel("$x/L$")
        ax.set_ylabel("$t c_s/L$")
        ax.set_title(f"{name}: H = {run.info.H:g} m", fontsize=8)
        self._save(fig, f"{name}_spacetime.png")
        self.figure(f"{name}: space-time map of log10(v/v0), wave-speed lines from the nucleation point, "
                    f"bar 2H/c_s", f"{name}_spacetime.png")

    def _save(self, fig, name):
        self.figdir.mkdir(parents=True, exist_ok=True)
        fig.savefig(self.figdir / name, dpi=80, bbox_inches="tight")
        an._plt().close(fig)

    def fig3cd(self):
        sec = "Fig. 3c/3d: large-event peak of p(T) vs 2H/c_s"
        fam = {n: self.stat(n) for n in FIG3_FAMILY}
        have = {n: s for n, s in fam.items() if s is not None and _finite(s["T_peak"]) and _finite(s["T_peak_err"])}
        for n in FIG3_FAMILY:
            claim = f"peak of large-event p(T), {RUNS[n] if n != 'reference' else 'reference (H = 0.1 m, rho = 1200)'}"
            if fam[n] is None:
                self.add_missing(sec, claim, paper_cell("fig3_peak_arrow"), [n])
                continue
            s = fam[n]
            r = s["T_peak"] / s["tau"]
            self.add(sec, claim, paper_cell("fig3_peak_arrow"),
                     f"T_peak = {fmt(s['T_peak'] * 1e3, s['T_peak_err'] * 1e3)} ms = "
                     f"{fmt(r, s['T_peak_err'] / s['tau'])} (2H/c_s); 2H/c_s = {fmt(s['tau'] * 1e3)} ms; "
                     f"{int(np.sum(s['obs']['u'] >= 1))} large events (mode of a kernel density of ln T, bootstrap error)"
                     + self._local_peaks_text(s),
                     verdict_factor(r), self.basis(n))

        def order(names, key, claim):
            if any(fam[n] is None for n in names):
                self.add_missing(sec, claim, paper_cell(key), [n for n in names if fam[n] is None])
                return
            vals = [(fam[n]["T_peak"], fam[n]["T_peak_err"]) for n in names]
            z = [(b[0] - a[0]) / math.hypot(a[1], b[1]) if _finite(a[1]) and _finite(b[1]) else math.nan
                 for a, b in zip(vals, vals[1:])]
            value = " < ".join(f"{fmt(v * 1e3, e * 1e3)} ms" for v, e in vals) + \
                "; steps " + ", ".join(f"{q:+.1f} σ" for q in z)
            ok = None if not all(_finite(q) for q in z) else all(q > 0 for q in z)
            self.add(sec, claim, paper_cell(key), value,
                     verdict_bool(ok, "each step > 0" if ok else "not increasing at every step"), self.basis(*names))

        order(("fig3c_H005", "reference", "fig3c_H02"), "fig3c_shift", "T_peak increases with H (0.05, 0.1, 0.2 m)")
        order(("fig3d_rho300", "reference", "fig3d_rho4800"), "fig3d_shift",
              "T_peak increases as c_s decreases (rho = 300, 1200, 4800)")
        claim = "H and c_s variations collapse on 2H/c_s (same 2H/c_s, same T_peak)"
        pairs = (("fig3c_H005", "fig3d_rho300"), ("fig3c_H02", "fig3d_rho4800"))
        if any(fam[n] is None for p in pairs for n in p):
            self.add_missing(sec, claim, paper_cell("fig3_collapse"), [n for p in pairs for n in p if fam[n] is None])
        else:
            parts, zs = [], []
            for a, b in pairs:
                sa, sb = fam[a], fam[b]
                z = (sa["T_peak"] - sb["T_peak"]) / math.hypot(sa["T_peak_err"], sb["T_peak_err"])
                zs.append(z)
                parts.append(f"{a} vs {b} (2H/c_s = {fmt(sa['tau'] * 1e3)} / {fmt(sb['tau'] * 1e3)} ms): "
                             f"{fmt(sa['T_peak'] * 1e3, sa['T_peak_err'] * 1e3)} vs "
                             f"{fmt(sb['T_peak'] * 1e3, sb['T_peak_err'] * 1e3)} ms ({z:+.1f} σ)")
            ok = None if not all(_finite(z) for z in zs) else all(abs(z) <= SIGMA_RULE for z in zs)
            self.add(sec, claim, paper_cell("fig3_collapse"), "; ".join(parts),
                     verdict_bool(ok, f"|Δ| ≤ {SIGMA_RULE:g} σ for both pairs" if ok else "a pair differs by > 2 σ"),
                     self.basis(*FIG3_FAMILY))
        claim = "fit T_peak = k (2H/c_s)^beta over the five runs"
        if len(have) < 3:
            self.add_missing(sec, claim, "not quantified in the paper", [n for n in FIG3_FAMILY if n not in have]) \
                if any(n in self.missing for n in FIG3_FAMILY) else \
                self.add(sec, claim, "not quantified in the paper", "fewer than 3 runs with a peak", "no value",
                         self.basis(*FIG3_FAMILY))
        else:
            fit = fit_peak_scaling([have[n]["tau"] for n in have], [have[n]["T_peak"] for n in have],
                                   [have[n]["T_peak_err"] for n in have])
            self.fit = fit
            value = (f"beta = {fmt(fit['beta'], fit['beta_err'])}, k = {fmt(fit['k'], fit['k_err'])} "
                     f"({len(have)} runs, weighted least squares in log); proportional fit T_peak = k1 (2H/c_s): "
                     f"k1 = {fmt(fit['k1'], fit['k1_err'])}, chi2/dof = {fmt(fit['chi2_1'] / max(1, fit['dof_1']))}, "
                     f"p = {fmt(fit['p_1'])}")
            self.add(sec, claim, "not quantified in the paper (arrows at 2H/c_s)", value,
                     "beta " + verdict_sigma(fit["beta"], fit["beta_err"], 1.0).replace("agrees", "consistent with 1")
                     .replace("differs by", "differs from 1 by"), self.basis(*FIG3_FAMILY))
        claim = "small-event exponent of p(u/D) across the five runs"
        if any(fam[n] is None for n in FIG3_FAMILY):
            self.add_missing(sec, claim, paper_cell("fig3_small"), [n for n in FIG3_FAMILY if fam[n] is None])
        else:
            ex = {n: (fam[n]["stats"]["small_exponent_u"],
                      combined_error(fam[n]["stats"]["small_exponent_u_err"],
                                     fam[n]["stats"]["small_exponent_u_bootstrap_err"])) for n in FIG3_FAMILY}
            ref = ex["reference"]
            zs = [(a - ref[0]) / math.hypot(e, ref[1]) for n, (a, e) in ex.items() if n != "reference"]
            ok = None if not all(_finite(z) for z in zs) else all(abs(z) <= SIGMA_RULE for z in zs)
            self.add(sec, claim, paper_cell("fig3_small"),
                     "; ".join(f"{n} {fmt(a, e)}" for n, (a, e) in ex.items()),
                     verdict_bool(ok, "all within 2 σ of the reference" if ok else "some differ by > 2 σ"),
                     self.basis(*FIG3_FAMILY))
        self._pT_figure(fam)

    def _pT_figure(self, fam):
        plt = an._plt()
        fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), sharey=True)
        groups = ((("fig3c_H005", "reference", "fig3c_H02"), "H family"),
                  (("fig3d_rho300", "reference", "fig3d_rho4800"), "c_s family"))
        drawn = False
        for ax, (names, title) in zip(axes, groups):
            for i, n in enumerate(names):
                s = fam[n]
                if s is None:
                    continue
                T = np.asarray(s["kept"]["T"], float)
                c, p, _ = an.log_binned_pdf(T)
                m = p > 0
                if m.any():
                    drawn = True
                    label = f"{n}: H = {s['run'].info.H:g} m, c_s = {s['run'].info.c_s:.0f} m/s"
                    ax.loglog(c[m], p[m], "-o", ms=2, color=f"C{i}", label=label)
                    ax.annotate("", xy=(s["tau"], p[m].min()), xytext=(s["tau"], p[m].min() * 0.1),
                                arrowprops=dict(arrowstyle="->", color=f"C{i}"))
                    if _finite(s["T_peak"]):
                        ax.axvline(s["T_peak"], color=f"C{i}", lw=0.6, ls=":")
            ax.set_xlabel("T [s]  (arrows: 2H/c_s; dotted: large-event peak)")
            ax.set_title(title, fontsize=8)
            ax.legend(fontsize=6)
        axes[0].set_ylabel("p(T)")
        if drawn:
            self._save(fig, "pT_families.png")
            self.figure("Fig. 3c/3d: p(T) of the kept events, arrows at 2H/c_s, dotted lines at the large-event peak",
                        "pT_families.png")
        else:
            an._plt().close(fig)
        if getattr(self, "fit", None):
            fig, ax = plt.subplots(figsize=(4.2, 3.4))
            for i, n in enumerate(FIG3_FAMILY):
                s = fam[n]
                if s is not None and _finite(s["T_peak"]):
                    ax.errorbar(s["tau"], s["T_peak"], yerr=s["T_peak_err"], fmt="o", color=f"C{i}", label=n, ms=4)
            g = np.logspace(math.log10(min(s["tau"] for s in fam.values() if s) / 1.5),
                            math.log10(max(s["tau"] for s in fam.values() if s) * 1.5), 20)
            ax.loglog(g, self.fit["k"] * g ** self.fit["beta"], "k-", lw=0.8,
                      label=f"beta = {self.fit['beta']:.2f}")
            ax.loglog(g, g, "k:", lw=0.8, label="T = 2H/c_s")
            ax.set_xlabel("2H/c_s [s]")
            ax.set_ylabel("T_peak [s]")
            ax.legend(fontsize=6)
            self._save(fig, "tpeak_fit.png")
            self.figure("T_peak of the large events against 2H/c_s, with the power-law fit", "tpeak_fit.png")

    @staticmethod
    def _local_peaks_text(s) -> str:
        peaks = s.get("T_local_peaks") or []
        if len(peaks) < 2:
            return ""
        return "; local maxima of p(T) at " + ", ".join(
            f"{fmt(T / s['tau'])} (height {fmt(h)})" for T, h in peaks) + " (2H/c_s)"

    @staticmethod
    def _regime_text(s) -> str:
        r = s["regime"]
        return (f"state {r['state']} ({'converged' if r['converged'] else 'NOT converged'}, thirds "
                f"{'/'.join(r['states_by_third'])}, agreement {fmt(r['agreement'])}; docs/transition.md)")

    def complexity_rows(self):
        sec = "Figs. 4, S10-S12: complexity retained"
        for name in ("fig4_slip_law", "s10_D_over_3", "s11_a_over_3", "s12"):
            claim = f"{RUNS[name]}: complexity retained, small-event exponents as in Fig. 1"
            paper = paper_cell("complexity") + f"; Fig. 1 exponents {PAPER['exp_u'].value:g} / " \
                f"{PAPER['exp_T'].value:g} / {PAPER['exp_M0'].value:g}"
            s = self.stat(name)
            if s is None:
                self.add_missing(sec, claim, paper, [name])
                continue
            st = s["stats"]
            parts, verdicts = [], []
            for key, obs in (("exp_u", "u"), ("exp_T", "T"), ("exp_M0", "M0")):
                a = st[f"small_exponent_{obs}"]
                e = combined_error(st[f"small_exponent_{obs}_err"], st[f"small_exponent_{obs}_bootstrap_err"])
                parts.append(f"{obs}: {fmt(a, e)}")
                verdicts.append(f"{obs} {verdict_sigma(a, e, PAPER[key].value)}")
            value = (self._regime_text(s) + f"; {st['n_events_small']} small / {st['n_events_large']} large "
                     f"events; " + ", ".join(parts))
            verdict = ("complexity " + ("agrees" if s["complex"] else "differs") + "; " + "; ".join(verdicts))
            self.add(sec, claim, paper, value, verdict, self.basis(name))
        claim = "slip law: large events span a larger part of the interface than with the aging law"
        s4, sr = self.stat("fig4_slip_law"), self.stat("reference")
        if s4 is None or sr is None:
            self.add_missing(sec, claim, paper_cell("fig4_larger"), ["fig4_slip_law", "reference"])
        else:
            def mean_extent(s):
                Ls = np.asarray(s["kept"]["L_s"], float)[s["obs"]["u"] >= 1] / s["run"].info.L
                return Ls
            a, b = mean_extent(s4), mean_extent(sr)
            ma, mb = (float(a.mean()) if a.size else math.nan), (float(b.mean()) if b.size else math.nan)
            ea, eb = bootstrap(a, np.mean, n=self.n_bootstrap), bootstrap(b, np.mean, n=self.n_bootstrap)
            ratio = ma / mb if _finite(ma) and _finite(mb) and mb > 0 else math.nan
            err = ratio * math.hypot(ea / ma, eb / mb) if _finite(ratio) else math.nan
            ok = None if not (_finite(ratio) and _finite(err)) else bool(ratio - 1 > SIGMA_RULE * err)
            self.add(sec, claim, paper_cell("fig4_larger"),
                     f"mean L_s/L of large events: slip law {fmt(ma, ea)}, aging {fmt(mb, eb)}; ratio {fmt(ratio, err)}",
                     verdict_bool(ok, "ratio > 1 by > 2 σ" if ok else "ratio not > 1 by 2 σ"),
                     self.basis("fig4_slip_law", "reference"))

    def fig5(self):
        sec = "Fig. 5: reverse transition"
        for name, key, claim in (("fig5", "fig5_pulse", "Fig. 5 friction (H = 0.1 m): periodic travelling pulse"),
                                 ("fig5_H02", "fig5_H02", "Fig. 5 friction, H = 0.2 m: no complexity"),
                                 ("reference", "reference_no_pulse", "reference case: no periodic pulse (same criterion)")):
            s = self.stat(name)
            if s is None:
                self.add_missing(sec, claim, paper_cell(key), [name])
                continue
            p = s["pulse"]
            ps = p["periodic_pulse_spacetime"]
            tr = s["run"].length_transit_time
            value = (f"periodic_pulse = {p['periodic_pulse']} (criterion: {p['periodic_pulse_basis']})")
            if ps.get("determined"):
                value += (f"; late half: min max-slip-rate {fmt(ps['min_max_slip_rate_v0'])} v0, slipping width "
                          f"{fmt(ps['median_width_fraction'])} L, shape correlation {fmt(ps['median_correlation'])}, "
                          f"moving one way {fmt(ps['moving_fraction'])}, travelled {fmt(ps['travelled_periods'])} L")
                if p["periodic_pulse"]:
                    value += (f"; speed {fmt(ps['speed_median'] / s['run'].info.c_s)} c_s "
                              f"(range {fmt(ps['speed_min'] / s['run'].info.c_s)}-"
                              f"{fmt(ps['speed_max'] / s['run'].info.c_s)}); pulse from t = "
                              f"{fmt(ps['onset_time'] / tr)} L/c_s (coarsening transient)")
            episodes = self._pulse_episodes(s)
            if episodes is not None:
                n_pulse = sum(episodes["flags"])
                value += (f"; same criterion in {fmt(an.PULSE_EPISODE_WINDOW_TRANSITS)} L/c_s windows: pulse in "
                          f"{n_pulse} of {len(episodes['flags'])}")
                if n_pulse:
                    value += (f", longest stretch t = {fmt(episodes['longest_start'] / tr)}-"
                              f"{fmt(episodes['longest_end'] / tr)} L/c_s")
            if name == "fig5":
                verdict = verdict_bool(p["periodic_pulse"])
                if not p["periodic_pulse"] and episodes is not None and sum(episodes["flags"]):
                    verdict = (f"differs (a pulse only for t = {fmt(episodes['longest_start'] / tr)}-"
                               f"{fmt(episodes['longest_end'] / tr)} L/c_s, not in the late half)")
            elif name == "fig5_H02":
                verdict = verdict_bool(not s["complex"], f"state {s['regime']['state']}")
                value += "; " + self._regime_text(s) + f"; {s['stats']['n_events_small']} small / " \
                         f"{s['stats']['n_events_large']} large events"
            else:
                verdict = verdict_bool(not p["periodic_pulse"])
            self.add(sec, claim, paper_cell(key), value, verdict, self.basis(name))
            if name == "fig5":
                self._fig5_figure(s)

    def _pulse_episodes(self, s):
        """pulse_episodes of a run's snapshots (None without snapshots); cached per run."""
        cache = s.setdefault("_pulse_episodes", {})
        if "value" not in cache:
            st = an.read_spacetime(s["run"].path, max_rows=6000)
            cache["value"] = None if st is None else an.pulse_episodes(
                st[0], st[2], s["run"].info.v0, s["run"].info.L / st[2].shape[1],
                window=an.PULSE_EPISODE_WINDOW_TRANSITS * s["run"].length_transit_time)
        return cache["value"]

    def _fig5_figure(self, s):
        st = an.read_spacetime(s["run"].path, max_rows=2000)
        if st is None:
            return
        t, x, v = st
        run = s["run"]
        plt = an._plt()
        z = _downsample(np.log10(np.maximum(np.abs(v), 1e-6 * run.info.v0) / run.info.v0), 500, 400)
        fig, ax = plt.subplots(figsize=(4.6, 3.8))
        im = ax.imshow(z, origin="lower", aspect="auto", cmap="viridis", vmin=-2,
                       extent=(0, 1, t[0] / run.length_transit_time, t[-1] / run.length_transit_time))
        fig.colorbar(im, ax=ax, label=r"$\log_{10}(v/v_0)$")
        episodes = self._pulse_episodes(s)
        for (t0, t1), flag in zip(episodes["windows"] if episodes else [], episodes["flags"] if episodes else []):
            if flag:  # windows where the space-time pulse criterion holds
                ax.axvspan(0.97, 1.0, ymin=(t0 - t[0]) / (t[-1] - t[0]), ymax=(t1 - t[0]) / (t[-1] - t[0]),
                           color="r")
        onset = s["pulse"]["periodic_pulse_spacetime"].get("onset_time", math.nan)
        if _finite(onset):
            ax.axhline(onset / run.length_transit_time, color="w", ls="--", lw=0.8, label="pulse onset (criterion)")
            ax.legend(fontsize=6)
        ax.set_xlabel("$x/L$")
        ax.set_ylabel("$t c_s/L$")
        self._save(fig, "fig5_spacetime.png")
        self.figure("Fig. 5 friction: space-time map of log10(v/v0) (whole run); red bar at the right edge: "
                    "windows where the space-time pulse criterion holds", "fig5_spacetime.png")
        # Zoom: 10 L/c_s in the middle of the longest pulse stretch, and the last 10 L/c_s.
        zooms = []
        if episodes and _finite(episodes["longest_start"]):
            mid = 0.5 * (episodes["longest_start"] + episodes["longest_end"])
            zooms.append(("pulse stretch", mid - 5 * run.length_transit_time, mid + 5 * run.length_transit_time))
        zooms.append(("end of the run", t[-1] - 10 * run.length_transit_time, t[-1]))
        fig, axes = plt.subplots(1, len(zooms), figsize=(4.2 * len(zooms), 3.6), squeeze=False)
        for ax, (label, t0, t1) in zip(axes[0], zooms):
            rows = (t >= t0) & (t <= t1)
            zz = np.log10(np.maximum(np.abs(v[rows]), 1e-6 * run.info.v0) / run.info.v0)
            im = ax.imshow(_downsample(zz, 400, 400), origin="lower", aspect="auto", cmap="viridis", vmin=-2,
                           vmax=1.5, extent=(0, 1, t[rows][0] / run.length_transit_time, t[rows][-1] / run.length_transit_time))
            ax.set(xlabel="$x/L$", ylabel="$t c_s/L$", title=label)
        fig.colorbar(im, ax=axes[0, -1], label=r"$\log_{10}(v/v_0)$")
        self._save(fig, "fig5_zoom.png")
        self.figure("Fig. 5 friction: 10 L/c_s in the middle of the longest stretch where the pulse criterion "
                    "holds, and the last 10 L/c_s", "fig5_zoom.png")

    def stationarity_section(self):
        sec = "Stationarity, threshold, clusters (Figs. S6, S8, S9)"
        for name in STATISTICS_RUNS:
            s = self.stat(name)
            if s is None:
                self.stationarity_rows.append([name, self.not_run(name), "", "", "", "", "", "", "", "", "", ""])
                continue
            part, run = s["part"], s["run"]
            st = part["stationarity"]
            cut = part["cut"]
            self.stationarity_rows.append([
                name, f"{fmt(cut['t_cut'])} s = {fmt(cut['t_cut'] / run.length_transit_time)} L/c_s "
                      f"({cut['batches_dropped_rate']}/{cut['batches_dropped_slip']} of {cut['n_batches']} batches)",
                f"{fmt(run.info.duration / run.length_transit_time)} L/c_s", str(len(part["catalog"]["t_start"])),
                f"{st['n_first']} / {st['n_last']}",
                *(fmt(st[k]["pvalue"], digits=2) for k in ("u", "T", "M0")),
                "yes" if part["stationary"] else "no",
                *(fmt(part["stationarity_blocks"][k]["pvalue"], digits=2) for k in ("u", "T", "M0")),
                "yes" if part["stationary_blocks"] else "no"])
            if name != "reference":
                continue
            sb = part["stationarity_blocks"]
            value = (f"cut {fmt(cut['t_cut'] / run.length_transit_time)} L/c_s of {fmt(run.info.duration / run.length_transit_time)}; "
                     "first vs last fifth of what is kept, block-permutation KS p (serially dependent events, "
                     f"{sb['n_blocks']} blocks): " +
                     ", ".join(f"{k} {fmt(sb[k]['pvalue'], digits=2)}" for k in ("u", "T", "M0")) +
                     "; plain KS p (assumes independent events): " +
                     ", ".join(f"{k} {fmt(st[k]['pvalue'], digits=2)}" for k in ("u", "T", "M0")))
            detail = ("block-permutation p ≥ 0.05 for u, T, M0" if part["stationary_blocks"] else
                      "some block-permutation p < 0.05")
            if part["stationary_blocks"] and not part["stationary"]:
                detail += "; the plain KS test, which assumes independent events, has some p < 0.05"
            self.add(sec, "reference: statistics stationary after the transient cut", paper_cell("stationary"), value,
                     verdict_bool(part["stationary_blocks"], detail), self.basis(name))
        if "reference" in self.missing:
            self.add_missing(sec, "reference: statistics stationary after the transient cut", paper_cell("stationary"),
                             ["reference"])
            self.add_missing(sec, "small-event exponent of p(u/D) vs the waiting-time threshold alpha",
                             paper_cell("alpha"), ["reference"])
            self.add_missing(sec, "number of clusters per event", paper_cell("clusters"), ["reference"])
            return
        s = self.stat("reference")
        run = s["run"]
        t_cut = s["part"]["cut"]["t_cut"]
        res = {}
        for a in self.alphas:
            self.log(f"report: reference at alpha = {a:g}")
            cat = s["catalog"] if float(a) == an.DEFAULT_ALPHA else catalog_of(run, a, self.workdir)
            kept = an.subset_catalog(cat, np.asarray(cat["t_start"], float) >= t_cut)
            st = an.catalog_statistics(kept, run.info, n_bootstrap=0)
            res[a] = (st["small_exponent_u"], st["small_exponent_u_err"], st["n_events"])
        base = res.get(an.DEFAULT_ALPHA, (math.nan, math.nan, 0))
        zs = [(e[0] - base[0]) / math.hypot(e[1], base[1]) for a, e in res.items() if a != an.DEFAULT_ALPHA]
        ok = None if not all(_finite(z) for z in zs) else all(abs(z) <= SIGMA_RULE for z in zs)
        self.add(sec, "small-event exponent of p(u/D) vs the waiting-time threshold alpha", paper_cell("alpha"),
                 "; ".join(f"alpha {a:g}: {fmt(e[0], e[1])} (n = {e[2]})" for a, e in res.items())
                 + " (same transient cut; Fisher errors)",
                 verdict_bool(ok, "all within 2 σ of alpha = 15" if ok else "some differ by > 2 σ from alpha = 15"),
                 self.basis("reference"))
        nc = np.asarray(s["kept"]["n_clusters"], int) if "n_clusters" in s["kept"] else np.array([], int)
        if nc.size:
            f1 = float(np.mean(nc == 1))
            e1 = math.sqrt(f1 * (1 - f1) / nc.size)
            dist = ", ".join(f"n_c = {k}: {np.mean(nc == k):.1%}" for k in range(0, 4)) + \
                f", n_c ≥ 4: {np.mean(nc >= 4):.1%}"
            self.add(sec, "number of clusters per event", paper_cell("clusters"),
                     f"{dist} (n = {nc.size}); fraction with one cluster {fmt(f1, e1)} (binomial error)",
                     verdict_bool(f1 - SIGMA_RULE * e1 > 0.5, "single-cluster fraction > 0.5 by 2 σ"
                                  if f1 - SIGMA_RULE * e1 > 0.5 else "single-cluster fraction not > 0.5"),
                     self.basis("reference"))
        self._reference_figures(s)

    def _reference_figures(self, s):
        run = s["run"]
        tmp = Path(tempfile.mkdtemp(dir=self.workdir))
        for path in an.plot_pdfs(s["kept"], run.info, s["stats"], tmp):
            self.figdir.mkdir(parents=True, exist_ok=True)
            shutil.move(path, self.figdir / "reference_pdfs.png")
        self.figure("Reference: p(u/D), p(T v0/D), p(M0/(mu D L)) of the kept events, power-law fits of the small "
                    "events, log-normal fits of the large events", "reference_pdfs.png")
        k, t_cut, t_end = s["kept"], s["part"]["cut"]["t_cut"], run.info.duration
        t = np.asarray(k["t_start"], float)
        span = t_end - t_cut
        sets = {"kept": k, "first fifth": an.subset_catalog(k, t < t_cut + 0.2 * span),
                "last fifth": an.subset_catalog(k, t > t_cut + 0.8 * span)}
        for path in an.plot_pdf_comparison(sets, run.info, tmp, "stationarity"):
            shutil.move(path, self.figdir / "reference_stationarity.png")
        self.figure("Reference: PDFs of the kept events, of the first and of the last fifth of the kept time "
                    "(Fig. S8)", "reference_stationarity.png")
        self._space_slip_figure(run, t_cut)

    def _space_slip_figure(self, run, t_cut, window_D=400.0, max_rows=1500):
        """v(x, delta)/v0 over window_D of mean slip after the transient cut (Fig. 1b)."""
        with runfile.open_h5(run.path) as f:
            ct = f["slip_sampling/crossing_time"]
            n_levels = ct.shape[0]
            j0 = int(min(max(1, run.info.v0 * t_cut / run.info.delta_th), max(1, n_levels - 2)))
            j1 = int(min(n_levels, j0 + window_D * run.info.D / run.info.delta_th))
            if j1 - j0 < 2:
                return
            step = max(1, (j1 - j0) // max_rows)
            rows = np.arange(j0, j1, step)
            cur = ct[rows.tolist()]
            prev = ct[(rows - 1).tolist()]
        with np.errstate(divide="ignore", invalid="ignore"):
            z = np.log10(np.clip(run.info.delta_th / (cur - prev) / run.info.v0, 1e-4, 1e4))
        plt = an._plt()
        fig, ax = plt.subplots(figsize=(4.6, 3.8))
        im = ax.imshow(_downsample(np.ma.filled(np.ma.masked_invalid(z), np.nan), 500, 400), origin="lower",
                       aspect="auto", cmap="viridis_r",
                       extent=(0, 1, rows[0] * run.info.delta_th / run.info.D, rows[-1] * run.info.delta_th / run.info.D))
        fig.colorbar(im, ax=ax, label=r"$\log_{10}(v(x,\delta)/v_0)$")
        ax.set_xlabel("$x/L$")
        ax.set_ylabel(r"$\delta/D$")
        self._save(fig, "reference_space_slip.png")
        self.figure(f"Reference: space-slip map v(x, δ)/v0 over {window_D:g} D of slip after the transient cut "
                    "(Fig. 1b)", "reference_space_slip.png")

    def lc_rows(self):
        sec = "Lc(H): linear stability (bindings), paper-as-run material"
        try:
            import slipstrip as ss
        except ImportError as err:
            if not self.allow_missing:
                raise MissingRun(f"the slipstrip bindings (_slipstrip) are not importable: {err}")
            for key, claim in (("Lc_01", "Lc(H = 0.1 m)"),):
                self.add(sec, claim, paper_cell(key), f"not computed (bindings not importable: {err})", "—", "")
            return
        ref = ss.load_config(str(REPO / "configs" / "reference.toml"))
        f5 = ss.load_config(str(REPO / "configs" / "fig5.toml"))
        label = material_label(ref.as_dict())
        lc = ss.critical_wavelength_vs_height(ref, [0.05, 0.1, 0.2, math.inf])
        lc5 = ss.critical_wavelength_vs_height(f5, [0.1, 0.2])
        printed = ss.critical_wavelength_vs_height(
            ss.load_config(str(REPO / "configs" / "reference.toml"), {"material.shear_modulus": 9e9}), [0.1])
        tol = "bisection to 1e-10 relative"
        self.add(sec, "Lc(H = 0.1 m), Table S1 friction", paper_cell("Lc_01"), f"{lc[1]:.4g} m ({tol})",
                 verdict_relative(lc[1], PAPER["Lc_01"].value), "configs/reference.toml; " + label)
        self.add(sec, "Lc/H at H = 0.1 m", paper_cell("Lc_over_H_01"), f"{lc[1] / 0.1:.3g}",
                 verdict_relative(lc[1] / 0.1, PAPER["Lc_over_H_01"].value), "configs/reference.toml; " + label)
        for i, (H, key) in enumerate(((0.05, "Lc_ratio_005"), (0.1, "Lc_ratio_01"), (0.2, "Lc_ratio_02"))):
            self.add(sec, f"Lc(H = {H:g} m) / Lc(inf)", paper_cell(key, lambda v: f"{v:.0%}"),
                     f"{lc[i] / lc[3]:.1%} (Lc = {lc[i]:.4g} m, Lc(inf) = {lc[3]:.4g} m)",
                     verdict_relative(lc[i] / lc[3], PAPER[key].value), "configs/reference.toml; " + label)
        for i, (H, key) in enumerate(((0.1, "Lc5_01"), (0.2, "Lc5_02"))):
            self.add(sec, f"Lc(H = {H:g} m), Fig. 5 friction", paper_cell(key),
                     f"{lc5[i]:.4g} m, Lc/H = {lc5[i] / H:.3g}", verdict_relative(lc5[i], PAPER[key].value),
                     "configs/fig5.toml; " + label)
        self.add(sec, "Lc(H = 0.1 m), Table S1 as printed (for contrast)", paper_cell("Lc_01"),
                 f"{printed[0]:.4g} m", verdict_relative(printed[0], PAPER["Lc_01"].value),
                 "configs/reference.toml --set material.shear_modulus=9e9; Table S1 as printed (mu = 9 GPa)")
        try:
            g = ss.growth_rates(ref, [math.inf])
            rate = float(np.asarray(g["growth_rate"])[0])
            self.add(sec, "uniform (k = 0) mode of steady sliding, H = 0.1 m", "not discussed in the paper",
                     f"growth rate {rate:.4g} 1/s ({'unstable' if rate > 0 else 'stable'}; mu/(2H) vs the critical "
                     "stiffness, docs/stability.md)", "—", "configs/reference.toml; " + label)
        except Exception as err:  # not essential to the comparison
            self.log(f"report: k = 0 growth rate not computed ({err})")

    # -- output -------------------------------------------------------------
    def build(self):
        self.load()
        self.fig1()
        self.fig2()
        self.fig3ab()
        self.fig3cd()
        self.complexity_rows()
        self.fig5()
        self.stationarity_section()
        self.lc_rows()

    def markdown(self, command: str) -> str:
        out = ["# Reproduction of the paper: every quantitative claim side by side", "",
               "<!-- Generated by `python3 -m slipstrip report`; do not edit by hand: the whole file and its figures "
               "are rewritten on every run. -->", "",
               f"Generated {datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%d %H:%M UTC')} by slipstrip "
               f"{_code_version()} from the run files listed below (RUNDIR = `{self.rundir.name}/`).", ""]
        if self.missing:
            out += ["**Incomplete report:** " + "; ".join(self.missing[n] for n in self.missing) +
                    ". Rows that need these runs say \"not run\" and carry no number.", ""]
        inc = [n for n, r in self.runs.items() if r.status != "completed"]
        if inc:
            out += ["**Preliminary:** " + ", ".join(f"RUNDIR/{n}.h5 (status {self.runs[n].status})" for n in inc) +
                    " were still running; their numbers are not final.", ""]
        out += ["## How to read the table", "",
                "* Every slipstrip value is computed by `python/slipstrip/report.py` from the run files (event "
                "catalogs of `slipstrip events`, snapshots, time series) or from the linear stability of the "
                "bindings; the paper values are the constants of `PAPER` in that file, each with its place in the paper.",
                f"* Verdict rules: a value with an error agrees if it is within {SIGMA_RULE:g} σ of the paper "
                f"(the paper's exponents are guides to the eye without errors, so σ is ours alone); an exact "
                f"number (Lc) agrees within {RELATIVE_RULE:.0%}; an order-of-magnitude claim (\"comparable to\", "
                f"\"~ H\") agrees within a factor {FACTOR_RULE:g}; qualitative claims use the stated test.",
                "* A power-law exponent depends on where its fit starts. Each Fig. 1 exponent (KS-optimal x_min, "
                "statistical error only) is followed by the same fit with x_min held at 1/4 to 4 times that value "
                "(`analysis.exponent_xmin_sweep`): the paper's guides to the eye have no stated fit range, so they "
                f"agree with our data if they lie within that range widened by {SIGMA_RULE:g} σ.",
                "* Statistics use the events after the automatic transient cut (docs/analysis.md, \"Transient cut\"), "
                "alpha = 15; small events u < D, large u ≥ D.",
                "* The Fig. 5 case over five seeds, two meshes from the same start, other starts, lengths and "
                "the other material reading (not part of this report, 4.9 h of run time): "
                "[fig5_resolution.md](fig5_resolution.md).",
                "* The material column says which reading of Table S1 each row uses "
                "(docs/stability.md: the paper-as-run reading E = 9 GPa, mu = 3.38 GPa).", ""]
        section = None
        for sec, r in self.rows:
            if sec != section:
                out += ["", f"## {sec}", "", "| claim | paper [location] | slipstrip | verdict | runs; material |",
                        "|---|---|---|---|---|"]
                section = sec
            out.append("| " + " | ".join(_cell(c) for c in (r.claim, r.paper, r.value, r.verdict, r.basis)) + " |")
        out += ["", "## Stationarity of every statistics run", "",
                "Transient cut by MSER on batch series of the event rate and the mean log10(u/D) "
                "(`analysis.transient_cut`); then KS tests between the first and the last fifth of what "
                f"is kept (pass: every p ≥ {an.STATIONARITY_LEVEL:g}): the plain two-sample test, which assumes "
                "independent events, and the block-permutation test (`analysis.block_permutation_stationarity`, "
                f"{an.STATIONARITY_BLOCKS} time blocks, {an.STATIONARITY_PERMUTATIONS} permutations), which allows for "
                "the clustering of events. On synthetic stationary clustered catalogs the plain test rejects ~74 % "
                "at the 5 % level and the block test ~3 % (tests/python/test_analysis_stationarity.py); both reject "
                "a drift of event sizes. The verdict uses the block test.", "",
                "| run | cut (batches dropped: rate/slip) | run length | events kept | first / last fifth | "
                "plain p(u) | plain p(T) | plain p(M0) | plain: stationary | block p(u) | block p(T) | block p(M0) | "
                "block: stationary |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        out += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in self.stationarity_rows]
        out += ["", "## Figures", ""]
        for caption, rel in self.figures:
            out += [f"![{caption}]({rel})", "", f"*{caption}*", ""]
        out += ["## Run files", "",
                "| run | case | status | simulated | wall time | N | git | material |", "|---|---|---|---|---|---|---|---|"]
        total = 0.0
        for name in RUNS:
            if name in self.missing:
                out.append(f"| RUNDIR/{name}.h5 | {RUNS[name]} | {self.missing[name]} | | | | | |")
                continue
            r = self.runs[name]
            w = r.wall_seconds
            total += w if _finite(w) else 0.0
            out.append(f"| RUNDIR/{name}.h5 | {RUNS[name]} | {r.status} | {fmt(r.info.duration)} s = "
                       f"{fmt(r.info.duration / r.length_transit_time)} L/c_s | {_hms(w)} | {r.info.n_nodes} | {r.git_hash} | "
                       f"{material_label(r.config)} |")
        out += ["", f"Total wall time of the runs listed: {_hms(total)}.", "",
                f"Machine: {_machine()}.", "",
                "## Regenerate", "", "```bash",
                "cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSLIPSTRIP_PYTHON=ON -DPython3_EXECUTABLE=/usr/bin/python3",
                "cmake --build build -j2 --target slipstrip _slipstrip",
                "for c in " + " ".join(RUNS) + "; do",
                "  build/slipstrip run configs/$c.toml --out RUNDIR/$c.h5 --quiet && build/slipstrip events RUNDIR/$c.h5",
                "done",
                command, "```", ""]
        return "\n".join(out)


def fit_peak_scaling(tau, tpeak, err) -> dict:
    """Weighted least squares of ln T_peak = ln k + beta ln tau (weights from
    the relative errors), and of T_peak = k1 tau (chi^2 and its p-value)."""
    tau, y, e = (np.asarray(a, float) for a in (tau, tpeak, err))
    X = np.column_stack([np.ones_like(tau), np.log(tau)])
    w = (y / e) ** 2
    A = X.T @ (w[:, None] * X)
    cov = np.linalg.inv(A)
    coef = cov @ (X.T @ (w * np.log(y)))
    resid = np.log(y) - X @ coef
    dof = max(1, y.size - 2)
    chi2 = float(np.sum(w * resid ** 2))
    scale = max(1.0, chi2 / dof)  # inflate the errors when the scatter exceeds them
    lnk, beta = coef
    lnk_err, beta_err = np.sqrt(np.diag(cov) * scale)
    w1 = 1 / e ** 2
    k1 = float(np.sum(w1 * tau * y) / np.sum(w1 * tau ** 2))
    chi2_1 = float(np.sum(w1 * (y - k1 * tau) ** 2))
    dof1 = y.size - 1
    return {"beta": float(beta), "beta_err": float(beta_err), "k": float(math.exp(lnk)),
            "k_err": float(math.exp(lnk) * lnk_err), "chi2": chi2, "dof": dof,
            "k1": k1, "k1_err": float(math.sqrt(1 / np.sum(w1 * tau ** 2)) * math.sqrt(max(1.0, chi2_1 / max(1, dof1)))),
            "chi2_1": chi2_1, "dof_1": dof1, "p_1": float(stats.chi2.sf(chi2_1, dof1)) if dof1 > 0 else math.nan}


def _downsample(z: np.ndarray, max_rows: int, max_cols: int) -> np.ndarray:
    """Block maximum (NaN-aware) to at most max_rows x max_cols: keeps narrow pulses visible."""
    z = np.asarray(z, float)
    r = max(1, int(math.ceil(z.shape[0] / max_rows)))
    c = max(1, int(math.ceil(z.shape[1] / max_cols)))
    nr, nc = z.shape[0] // r, z.shape[1] // c
    if r == 1 and c == 1:
        return z
    b = z[: nr * r, : nc * c].reshape(nr, r, nc, c)
    with np.errstate(all="ignore"):
        import warnings
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            return np.nanmax(np.nanmax(b, axis=3), axis=1)


def _cell(text) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _hms(seconds) -> str:
    if not _finite(seconds):
        return "n/a"
    s = int(round(seconds))
    return f"{s // 3600}:{(s % 3600) // 60:02d}:{s % 60:02d} ({seconds:.0f} s)"


def _machine() -> str:
    model = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.lower().startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    n = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return f"{model}, nproc = {n}, {platform.system()} {platform.release()}, Python {platform.python_version()}"


def _code_version() -> str:
    try:
        h = subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], cwd=REPO, capture_output=True, text=True)
        return f"(git {h.stdout.strip()})" if h.returncode == 0 and h.stdout.strip() else ""
    except OSError:
        return ""


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m slipstrip report",
                                     description="The paper's quantitative claims side by side with slipstrip "
                                                 "(docs/reproduction.md) from a directory of run files.")
    parser.add_argument("rundir", help="directory of run files RUNDIR/<config name>.h5")
    parser.add_argument("--out", default="docs/reproduction.md", help="Markdown output (default docs/reproduction.md)")
    parser.add_argument("--figures", default="docs/figures/reproduction", help="directory of the PNG figures")
    parser.add_argument("--allow-missing", action="store_true",
                        help="a missing or unreadable run gives 'not run' rows instead of an error")
    parser.add_argument("--allow-incomplete", action="store_true",
                        help="use runs whose status is not 'completed' (marked preliminary)")
    parser.add_argument("--bootstrap", type=int, default=N_BOOTSTRAP, help="bootstrap resamples (default 200)")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(list(argv[1:] if argv and argv[0] == "report" else argv))
    rundir = Path(args.rundir)
    if not rundir.is_dir():
        print(f"report: run directory {args.rundir} not found", file=sys.stderr)
        return 2
    out, figdir = Path(args.out), Path(args.figures)
    log = (lambda *a: None) if args.quiet else (lambda *a: print(*a, file=sys.stderr))
    with tempfile.TemporaryDirectory() as work:
        rep = Report(rundir, figdir, args.allow_missing, args.allow_incomplete, out.parent, Path(work),
                     n_bootstrap=args.bootstrap, log=log)
        try:
            rep.load()
        except MissingRun as err:
            print(f"report: {err} (RUNDIR = {args.rundir}; use --allow-missing to report it as not run)",
                  file=sys.stderr)
            return 2
        # Never a stale number: old figures go before anything is written.
        if figdir.is_dir():
            for p in figdir.glob("*.png"):
                p.unlink()
        try:
            rep.fig1(); rep.fig2(); rep.fig3ab(); rep.fig3cd(); rep.complexity_rows(); rep.fig5()
            rep.stationarity_section(); rep.lc_rows()
        except MissingRun as err:
            print(f"report: {err}", file=sys.stderr)
            return 2
        command = ("python3 -m slipstrip report RUNDIR --out " + _rel(out) + " --figures " + _rel(figdir)
                   + (" --allow-missing" if args.allow_missing else "")
                   + (" --allow-incomplete" if args.allow_incomplete else ""))
        text = rep.markdown(command)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(out.suffix + ".tmp")
    tmp.write_text(text)
    tmp.replace(out)
    print(f"wrote {out} ({len(rep.rows)} rows, {len(rep.figures)} figures"
          + (f"; not run: {', '.join(rep.missing)}" if rep.missing else "") + ")")
    return 0


def _rel(p: Path) -> str:
    try:
        return str(Path(p).resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return Path(p).name


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
