"""The report's measurements on run files and catalogs: bootstrap errors, the
peak of p(T), the fronts of a nucleated rupture, the Fig. 2 event hierarchy,
the T_peak scaling fit, wave speeds and the steady-state friction.

scipy is imported inside the functions that fit or estimate a density: it is
most of the start-up time of `python3 -m slipstrip report`, which should cost
little when it only refuses its arguments or a run file."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .. import analysis as an
from .. import hierarchy as hi
from .. import runfile
from .. import transition
from ..claims import BY_ID as PAPER
from .runs import Run, catalog_of
from .verdicts import _finite, within_factor


N_BOOTSTRAP = 200
FRONT_MIN_RATE = 3.0    # slip-rate threshold of the Fig. 3a/b fronts: >= 3 v0 and sqrt(v0 v_peak)
FIG2_T_BEGIN = 10.0     # [L/c_s] the Fig. 2 event analysis starts after the first 10 transits
EDGE_TOLERANCE = 4      # [nodes] an arrest edge "coincides" with a stress extremum within 4 dx (1 cm)
# The report's own criteria (not the paper's numbers: those are claims.CLAIMS
# values); the rows print these constants, so text and computation agree.
FAST_SLIP_RATE = 10.0   # [v0] "rapid" slip (Fig. 1b patches) and the first burst of a run
STICK_SLIP_RATE = 0.1   # [v0] "sticking" (Fig. 1b white lines)
MIN_SIDE_FRACTION = 0.1  # bilateral growth: the nucleation node at least this fraction of L_s inside both edges
CRACK_MIN_R2 = 0.9      # crack-like slip: R^2 of the fit of A sqrt(h^2 - (x - x_c)^2) to the event's slip
QUIET_FRACTION = 0.1    # snapshots bracket an event if nothing near it slipped more than this fraction of its slip
AGED_MIN_FRACTION = 0.9  # contact aging outside an event: phi grew at this fraction of the nodes that stuck
SMALL_EVENT_MIN_U = 0.2  # [D] events-2-3-like: small events with u at least this
FIXED_EXTENT_FRACTION = 0.8  # fixed extent: slip zone at half the duration >= this fraction of the final one
PRECEDING_TRANSITS = 2.0  # [L/c_s] event 4: arrest edges of large events this long before the event
NUCLEATION_RADIUS_H = 0.5  # [H] event 4: nucleated within this distance of such an arrest edge
EVENT5_MIN_EXTENT_H = 4.0  # [H] event-5-like: large events at least this long
PULSE_FRONT_WINDOW = (0.25, 0.45)  # [L] pulses counted while both fronts are this far from x0
TIP_FRONT_WINDOW = (0.05, 0.4)     # [L] tip zones measured while a front is this far from x0


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
    """Mode of p(T) (density per unit T, as plotted in Fig. 3c/d; also used for
    p(u) of Fig. S7) of the samples T > 0: a Gaussian kernel density of ln T (Scott's bandwidth),
    p(T) = p_lnT(ln T) / T maximised on a grid.  NaN for < 10 samples."""
    x = np.log(np.asarray(T, float)[np.asarray(T, float) > 0])
    if x.size < an.MIN_FIT_EVENTS or np.ptp(x) == 0:
        return math.nan
    from scipy import stats
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
    from scipy import stats
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
    # Fig. S7: the same peak for p(u) of the large events (u/D).
    u_large = obs["u"][large]
    res["u_peak"] = peak_of_pT(u_large)
    res["u_peak_err"] = bootstrap(u_large, peak_of_pT, n=n_bootstrap) if _finite(res["u_peak"]) else math.nan
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
    from scipy import stats
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
    # Pulses: snapshots where x0 no longer slips and the fronts are in PULSE_FRONT_WINDOW.
    counts, widths = [], []
    near, far = PULSE_FRONT_WINDOW
    for (tk, rk, lk, pulses) in rows:  # lk: most negative offset
        if pulses and min(rk, -lk) >= near * L and max(rk, -lk) <= far * L:
            counts.append(len(pulses))
            widths.extend(pulses)
    out["n_pulses"] = int(np.median(counts)) if counts else 0
    out["pulse_width"] = float(np.median(widths)) if widths else math.nan
    out["pulse_width_err"] = (float(0.5 * (np.quantile(widths, 0.75) - np.quantile(widths, 0.25)) + dx)
                              if widths else math.nan)
    return out


def friction_steady_state(fr: dict, v0: float) -> dict:
    """Steady-state friction of Eqs. S1-S2 at v0: f_ss = f0 [1 + b ln(phi_ss/phi*)]
    + a ln(1 + v0/v*), phi_ss = D / sqrt(v0^2 + v*^2), and its slope
    d f_ss / d ln v = -f0 b v0^2/(v0^2 + v*^2) + a v0/(v0 + v*)."""
    f0, a, b = float(fr["f0"]), float(fr["a"]), float(fr["b"])
    D, vs, ps = float(fr["characteristic_slip"]), float(fr["v_star"]), float(fr["phi_star"])
    phi = D / math.hypot(v0, vs)
    f = f0 * (1 + b * math.log(phi / ps)) + a * math.log1p(v0 / vs)
    slope = -f0 * b * v0 ** 2 / (v0 ** 2 + vs ** 2) + a * v0 / (v0 + vs)
    return {"f_ss": f, "slope": slope}


def tip_zones_of_run(run, t, x, v, ev, x0) -> dict:
    """Tip-zone sizes (hierarchy.tip_zone) at both fronts of a nucleated rupture, in
    every snapshot with a front TIP_FRONT_WINDOW (in L) from x0."""
    n = v.shape[1]
    dx = run.info.L / n
    i0 = int(np.argmin(np.abs(((np.asarray(x) - x0 + run.info.L / 2) % run.info.L) - run.info.L / 2)))
    sizes = []
    with runfile.open_h5(run.path) as f:
        tau_ds, slip_ds = f["snapshots/shear_stress"], f["snapshots/slip"]
        for tk, r, l in zip(ev["times"], ev["right"], ev["left"]):
            k = int(np.argmin(np.abs(t - tk)))
            tau = tau_ds[k]
            for off, direction in ((r, 1), (-l, -1)):
                if not (TIP_FRONT_WINDOW[0] * run.info.L <= abs(off) <= TIP_FRONT_WINDOW[1] * run.info.L):
                    continue
                front = (i0 + int(round(off / dx))) % n
                z = hi.tip_zone(x, tau, slip_ds[k], v[k], front, direction, run.info.D, ev["v_th"])
                if _finite(z["size"]):
                    sizes.append(z["size"])
    return {"sizes": np.asarray(sizes, float)}


def burst_onset(run) -> dict:
    """First time the largest slip rate exceeds FAST_SLIP_RATE v0 (time series), and whether
    the slip rate is then uniform along x (nearest snapshot: spread of log10 v
    over the nodes < 0.01, i.e. the k = 0 mode, not a localised burst)."""
    with runfile.open_h5(run.path) as f:
        t, vmax = f["timeseries/time"][:], f["timeseries/max_slip_rate"][:]
        above = np.flatnonzero(vmax > FAST_SLIP_RATE * run.info.v0)
        out = {"t": float(t[above[0]]) if above.size else math.nan, "duration": float(t[-1]) if t.size else math.nan,
               "max_deviation": float(np.max(np.abs(vmax / run.info.v0 - 1))) if t.size else math.nan}
        if above.size and "snapshots" in f and f["snapshots/time"].shape[0]:
            ts = f["snapshots/time"][:]
            k = int(np.flatnonzero(ts >= out["t"])[0]) if np.any(ts >= out["t"]) else ts.size - 1
            z = np.log10(np.maximum(np.abs(f["snapshots/slip_rate"][k]), 1e-30))
            out["spread"] = float(np.ptp(z))
            out["uniform"] = bool(out["spread"] < 0.01)
    return out


def _event_slip(hist, t0, t1, nodes=None):
    """Slip of every node (or `nodes`) from just before t0 to just after t1."""
    eps = 1e-12 * max(abs(t1), 1e-9)
    s = hist.at(np.array([t0 - eps, t1 + eps]), nodes)
    return s[1] - s[0]


def example_event(run, kept, obs) -> dict | None:
    """v(x, t) (slip sampling) and slip of the median large event of a run."""
    large = np.flatnonzero(obs["u"] >= 1)
    if not large.size:
        return None
    i = large[np.argsort(obs["u"][large])[large.size // 2]]
    t0, T = float(kept["t_start"][i]), float(kept["T"][i])
    band, off = hi.sampling_band(run.path, t0, t0 + T)
    with runfile.open_h5(run.path) as f:
        x = f["slip_sampling/x"][:]
    hist = hi.SlipHistory(band, run.info.delta_th, off)
    grid = np.linspace(t0, t0 + max(T, 1e-9), 200)
    return {"x": x, "t": 0.5 * (grid[1:] + grid[:-1]), "v": hist.velocity(grid), "slip": _event_slip(hist, t0, t0 + T)}


def fig2_hierarchy(run, catalog) -> dict:
    """The Fig. 2 measurements over every event of the kind the paper shows
    (see the report's rows): event-1-like (large, arrested, single cluster),
    events-2-3-like (small with SMALL_EVENT_MIN_U D <= u < D), event-4-like (large
    events and earlier arrest edges) and event-5-like (large, extent >=
    EVENT5_MIN_EXTENT_H H)."""
    info = run.info
    n, L, D, v0, H = info.n_nodes, info.L, info.D, info.v0, info.H
    dx = L / n
    tau = 2 * H / info.c_s
    cd = wave_speeds(run.config)["c_d"]
    t_begin = FIG2_T_BEGIN * L / info.c_s
    k = {key: np.asarray(val) for key, val in catalog.items() if key != "attrs"}
    sel = np.asarray(k["t_start"], float) >= t_begin
    with runfile.open_h5(run.path) as f:
        ct = np.asarray(f["slip_sampling/crossing_time"][:], float)
        snap_t = f["snapshots/time"][:] if "snapshots" in f else np.array([])
    dth = info.delta_th
    hist = hi.SlipHistory(ct, dth)
    del ct
    u = np.asarray(k["u_mean"], float) / D
    Ls = np.asarray(k["L_s"], float)
    T = np.asarray(k["T"], float)
    ncl = np.asarray(k.get("n_clusters", np.ones(u.size, int)), int)
    xs = np.asarray(k["x_start"], float)
    out = {"tau": tau}
    # -- event-1-like ----------------------------------------------------------
    e1_idx = np.flatnonzero(sel & (u >= 1) & (Ls < an.SPANNING_FRACTION * L) & (ncl == 1))
    e1 = {"n": 0, "bilateral": 0, "vmax_ok": 0, "duration_ok": 0, "crack_ok": 0, "sides": [], "r2": [], "vmax": [],
          "T_tau": []}
    edges_by_event = []
    fields = {"n": 0, "n_edges": 0, "edge_minima": 0, "edge_peaks": 0, "aging_ok": 0, "aged": [], "null_min": [],
              "null_peak": [], "max_gap": 0.0}
    example = None
    for i in e1_idx:
        t0, t1 = float(k["t_start"][i]), float(k["t_start"][i] + T[i])
        slip = _event_slip(hist, t0, t1)
        peak = int(np.argmax(slip))
        seg = hi.ring_segment(slip >= 2 * dth, peak)
        if seg is None:
            continue
        a, b = seg
        ext = (b - a) % n + 1
        if ext < 4:
            continue
        e1["n"] += 1
        i_s = int(round(xs[i] / dx)) % n
        pos = (i_s - a) % n
        side = min(pos, ext - 1 - pos) / ext if pos < ext else -1.0
        e1["sides"].append(side)
        e1["bilateral"] += side >= MIN_SIDE_FRACTION
        vm = float(k["max_slip_rate"][i]) / v0
        e1["vmax"].append(vm)
        e1["vmax_ok"] += vm > PAPER["fig2_event1_vmax"].value
        e1["T_tau"].append(T[i] / tau)
        e1["duration_ok"] += within_factor(T[i] / tau)
        nodes = (a + np.arange(ext)) % n
        fit = hi.crack_fit(np.arange(ext) * dx, slip[nodes])
        e1["r2"].append(fit["r2"])
        e1["crack_ok"] += _finite(fit["r2"]) and fit["r2"] >= CRACK_MIN_R2
        edges_by_event.append((t1, [(a - 1) % n, (b + 1) % n]))
        # Fields before and after: the snapshots bracketing the event, if nothing else slipped near it meanwhile.
        if snap_t.size:
            kb = np.flatnonzero(snap_t <= t0)
            ka = np.flatnonzero(snap_t >= t1)
            if kb.size and ka.size:
                ib, ia = int(kb[-1]), int(ka[0])
                # Between the snapshots and the event, nothing near it slipped more than a tenth
                # of the event's largest slip (creep and tiny events only): the snapshots show
                # the fields the event met and left.
                near = (a - ext // 2 + np.arange(2 * ext)) % n
                small_ = QUIET_FRACTION * float(slip.max())
                quiet_before = np.all(_event_slip(hist, snap_t[ib], t0, near) <= small_)
                quiet_after = np.all(_event_slip(hist, t1, snap_t[ia], near) <= small_)
                if quiet_before and quiet_after:
                    with runfile.open_h5(run.path) as f:
                        tb, ta = f["snapshots/shear_stress"][ib], f["snapshots/shear_stress"][ia]
                        pb, pa = f["snapshots/state"][ib], f["snapshots/state"][ia]
                    fields["n"] += 1
                    fields["max_gap"] = max(fields["max_gap"], t0 - snap_t[ib], snap_t[ia] - t1)
                    minima = hi.local_extrema(tb, "min", smooth=3)
                    window = (a - ext + np.arange(3 * ext)) % n
                    fields["null_min"].append(np.mean([hi.nearest_extremum_distance(minima, j, n) <= EDGE_TOLERANCE
                                                       for j in window]))
                    quarter = max(ext // 4, EDGE_TOLERANCE + 1)

                    def peak_at(center, field):
                        around = (center - quarter + np.arange(2 * quarter + 1)) % n
                        j = around[int(np.argmax(field[around]))]
                        return hi.ring_distance(j, center, n) <= EDGE_TOLERANCE

                    fields["null_peak"].append(np.mean([peak_at(j, ta) for j in window]))
                    for e in ((a - 1) % n, (b + 1) % n):
                        fields["n_edges"] += 1
                        fields["edge_minima"] += hi.nearest_extremum_distance(minima, e, n) <= EDGE_TOLERANCE
                        fields["edge_peaks"] += bool(peak_at(e, ta))
                    half = max(ext // 2, 1)
                    outside = np.concatenate([(a - 1 - np.arange(half)) % n, (b + 1 + np.arange(half)) % n])
                    # "nearly stick": slower than the loading rate v0 between the two snapshots.
                    still = outside[_event_slip(hist, snap_t[ib], snap_t[ia], outside)
                                    < v0 * (snap_t[ia] - snap_t[ib])]
                    if still.size:
                        aged = float(np.mean(pa[still] > pb[still]))
                        fields["aged"].append(aged)
                        fields["aging_ok"] += aged >= AGED_MIN_FRACTION
                    if example is None or ext > example["ext"]:
                        lo_ = a - ext // 2
                        idx = (lo_ + np.arange(2 * ext)) % n
                        grid = np.linspace(t0, t1 if t1 > t0 else t0 + tau, 120)
                        example = {"ext": ext, "x": (lo_ + np.arange(2 * ext)) * dx, "t": 0.5 * (grid[1:] + grid[:-1]),
                                   "v": hist.velocity(grid, idx), "slip": slip[idx],
                                   "tau_before": tb[idx], "tau_after": ta[idx], "phi_before": pb[idx],
                                   "phi_after": pa[idx], "edges": [(lo_ + ext // 2 - 1) * dx, (lo_ + ext // 2 + ext) * dx]}
    e1.update(median_side_fraction=float(np.median(e1["sides"])) if e1["sides"] else math.nan,
              median_vmax=float(np.median(e1["vmax"])) if e1["vmax"] else math.nan,
              median_T_tau=float(np.median(e1["T_tau"])) if e1["T_tau"] else math.nan,
              median_r2=float(np.nanmedian(e1["r2"])) if e1["r2"] else math.nan)
    fields.update(null_minima=float(np.mean(fields["null_min"])) if fields["null_min"] else math.nan,
                  null_peaks=float(np.mean(fields["null_peak"])) if fields["null_peak"] else math.nan,
                  aged_fraction=float(np.mean(fields["aged"])) if fields["aged"] else math.nan)
    out.update(event1=e1, fields=fields, example=example)
    # -- events-2-3-like ---------------------------------------------------------
    e23_idx = np.flatnonzero(sel & (u >= SMALL_EVENT_MIN_U) & (u < 1) & (ncl == 1) & (T > 0))
    e23 = {"n": 0, "nonprop": 0, "crack": 0, "fixed": 0, "all": 0}
    for i in e23_idx[:2000]:
        t0, t1 = float(k["t_start"][i]), float(k["t_start"][i] + T[i])
        slip = _event_slip(hist, t0, t1)
        seg = hi.ring_segment(slip >= dth, int(np.argmax(slip)))
        if seg is None:
            continue
        a, b = seg
        ext = (b - a) % n + 1
        if ext < 4:
            continue
        e23["n"] += 1
        nodes = (a + np.arange(ext)) % n
        nonprop = Ls[i] / T[i] > cd
        fit = hi.crack_fit(np.arange(ext) * dx, slip[nodes])
        crack = _finite(fit["r2"]) and fit["r2"] >= CRACK_MIN_R2
        half = _event_slip(hist, t0, 0.5 * (t0 + t1))
        fixed = np.count_nonzero(half[nodes] >= dth) >= FIXED_EXTENT_FRACTION * np.count_nonzero(slip[nodes] >= dth)
        e23["nonprop"] += nonprop
        e23["crack"] += crack
        e23["fixed"] += fixed
        e23["all"] += nonprop and crack and fixed
    out["events23"] = e23
    # -- event-4-like: large events and the arrest edges of earlier large arrested events ------
    big = np.flatnonzero(sel & (u >= 1))
    e4 = {"n": 0, "near": 0, "null": math.nan}
    nulls = []
    radius = max(1, int(round(NUCLEATION_RADIUS_H * H / dx)))
    for i in big:
        t0 = float(k["t_start"][i])
        edges = [e for (t_end, es) in edges_by_event if t0 - PRECEDING_TRANSITS * L / info.c_s <= t_end <= t0 for e in es]
        if not edges:
            continue
        e4["n"] += 1
        i_s = int(round(xs[i] / dx)) % n
        e4["near"] += hi.nearest_extremum_distance(edges, i_s, n) <= radius
        covered = np.zeros(n, bool)
        for e in edges:
            covered[(e - radius + np.arange(2 * radius + 1)) % n] = True
        nulls.append(covered.mean())
    e4["null"] = float(np.mean(nulls)) if nulls else math.nan
    out["event4"] = e4
    # -- event-5-like: bilateral stage then two pulses -----------------------------
    e5_idx = np.flatnonzero(sel & (u >= 1) & (Ls >= EVENT5_MIN_EXTENT_H * H))
    e5 = {"n": 0, "center_ok": 0, "two_pulses": 0, "pulses_ok": 0, "center": [], "widths": []}
    for i in e5_idx[:200]:
        t0, t1 = float(k["t_start"][i]), float(k["t_start"][i] + T[i])
        if t1 <= t0:
            continue
        grid = np.linspace(t0, t1, 400)
        vel = hist.velocity(grid)
        i_s = int(round(xs[i] / dx)) % n
        bp = hi.bilateral_then_pulses(vel, i_s, v0, dx)
        if not bp["found"]:
            continue
        e5["n"] += 1
        dt = grid[1] - grid[0]
        c = bp["center_steps"] * dt / tau
        e5["center"].append(c)
        e5["center_ok"] += within_factor(c)
        w = bp["pulse_width_nodes"] * dx / H if _finite(bp["pulse_width_nodes"]) else math.nan
        if bp["n_pulses"] == 2:
            e5["two_pulses"] += 1
            e5["widths"].append(w)
            e5["pulses_ok"] += within_factor(w)
    e5.update(median_center_tau=float(np.median(e5["center"])) if e5["center"] else math.nan,
              median_width_H=float(np.median(e5["widths"])) if e5["widths"] else math.nan)
    out["event5"] = e5
    return out


def fit_peak_scaling(tau, tpeak, err) -> dict:
    """Weighted least squares of ln T_peak = ln k + beta ln tau (weights from
    the relative errors), and of T_peak = k1 tau (chi^2 and its p-value)."""
    from scipy import stats
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
