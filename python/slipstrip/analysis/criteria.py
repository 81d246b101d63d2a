"""Criteria on a run: the periodic travelling pulse of the Fig. 5 regime
(event-based, time-series and space-time criteria, and the same criterion
window by window), and the grouping of nodal slips into events by the
waiting-time rule (for the event-coloured map; the catalog itself comes from
the C++ detector)."""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..runfile import open_h5, read_times
from .reading import DEFAULT_ALPHA, RunInfo, read_spacetime
from .statistics import SPANNING_FRACTION, _cv, slip_fractions


# Periodic travelling pulse (Fig. 5 regime), event-based criterion.
PULSE_MIN_SPANNING_SLIP = 0.8
PULSE_MAX_CV = 0.2
PULSE_MIN_SPANNING_EVENTS = 3
# Periodic travelling pulse, time-series criterion: a pulse that never stops
# is one never-ending event (excluded as first/last), so the catalog alone
# cannot see it.  In the second half of the run the fastest node must always
# slip faster than PULSE_MIN_RATE v0 and max slip rate must vary little.
PULSE_MIN_RATE = 3.0
# Periodic travelling pulse, space-time criterion (decisive when the run file has
# enough snapshots; docs/analysis.md).  Over the late part of the record: a
# localised slipping region (nodes above 0.1 of the current maximum slip rate
# cover at most PULSE_MAX_WIDTH_FRACTION of the interface), always faster than
# PULSE_MIN_RATE v0, keeping its shape between snapshots (median best-shift
# correlation of log10 v >= PULSE_MIN_CORRELATION), moving one way (>=
# PULSE_MIN_MOVING_FRACTION of the snapshot pairs shift it, in the majority
# direction) and travelling at least PULSE_MIN_TRAVEL periods in total.
PULSE_MAX_WIDTH_FRACTION = 0.5
PULSE_MIN_CORRELATION = 0.8
PULSE_MIN_MOVING_FRACTION = 0.9
PULSE_MIN_TRAVEL = 0.5       # periods L travelled over the late part, in total
PULSE_MIN_SNAPSHOTS = 10     # late snapshots needed for the space-time criterion to decide
PULSE_LATE_FRACTION = 0.5    # the criterion looks at the last half of the record


def periodic_pulse_from_catalog(catalog: dict, info: RunInfo) -> dict:
    """Event-based criterion of the Fig. 5 regime (a single periodic pulse):
    >= 80% of the slip in system-spanning events (L_s >= 0.9 L), at least 3
    such events, and coefficients of variation < 0.2 both of their
    inter-event times (t_start differences) and of their u_mean."""
    Ls = np.asarray(catalog["L_s"], float)
    spanning = Ls >= SPANNING_FRACTION * info.L
    fr = slip_fractions(catalog["u_mean"], Ls, info.D, info.L)["spanning"]
    t = np.sort(np.asarray(catalog["t_start"], float)[spanning])
    cv_dt = _cv(np.diff(t)) if t.size >= PULSE_MIN_SPANNING_EVENTS else math.nan
    cv_u = _cv(np.asarray(catalog["u_mean"], float)[spanning])
    flag = bool(spanning.sum() >= PULSE_MIN_SPANNING_EVENTS and fr >= PULSE_MIN_SPANNING_SLIP
                and cv_dt < PULSE_MAX_CV and cv_u < PULSE_MAX_CV)
    return {"flag": flag, "spanning_slip_fraction": fr, "cv_interevent": cv_dt, "cv_u_mean": cv_u,
            "n_spanning": int(spanning.sum())}


def periodic_pulse_from_timeseries(time, max_slip_rate, v0: float) -> dict:
    """Continuous-pulse criterion: over the second half of the record the
    largest slip rate on the interface never drops below 3 v0 (the interface
    never sticks everywhere, unlike stick-slip) and its coefficient of
    variation is < 0.2 (a steadily travelling pulse, not bursts)."""
    t = np.asarray(time, float)
    v = np.asarray(max_slip_rate, float)
    if t.size < 10:
        return {"flag": False, "min_max_slip_rate_v0": math.nan, "cv_max_slip_rate": math.nan}
    late = t >= 0.5 * (t[0] + t[-1])
    vmin = float(v[late].min() / v0)
    cv = float(v[late].std() / v[late].mean())
    return {"flag": bool(vmin > PULSE_MIN_RATE and cv < PULSE_MAX_CV),
            "min_max_slip_rate_v0": vmin, "cv_max_slip_rate": cv}


def _profile_spectrum(a: np.ndarray) -> tuple[float, np.ndarray]:
    """The norm and the spectrum of a profile less its mean: what _best_shift
    needs of each profile (the space-time criterion computes it once per
    snapshot, which it pairs with its two neighbours)."""
    a = a - a.mean()
    return float(np.linalg.norm(a)), np.fft.rfft(a)


def _best_shift(spectrum_a, spectrum_b, size: int) -> tuple[int, float, float]:
    """Circular shift s (nodes, signed, |s| <= N/2) that best maps profile a
    onto b (b[n] ~ a[n - s]), the normalised correlation at that shift, and
    the shift refined to a fraction of a node; a and b of `size` nodes are
    given by their _profile_spectrum."""
    (na, fa), (nb, fb) = spectrum_a, spectrum_b
    if na == 0 or nb == 0:
        return 0, math.nan, 0.0
    c = np.fft.irfft(np.conj(fa) * fb, n=size)
    s = int(np.argmax(c))
    r = float(c[s] / (na * nb))
    # Sub-node position of the peak (parabola through the three samples), for speeds.
    cm, cp = c[s - 1], c[(s + 1) % size]
    den = cm - 2 * c[s] + cp
    frac = float(0.5 * (cm - cp) / den) if den < 0 else 0.0
    if s > size // 2:
        s -= size
    return s, r, s + max(-0.5, min(0.5, frac))


def periodic_pulse_from_spacetime(time, slip_rate, v0: float, dx: float,
                                  late_fraction: float = PULSE_LATE_FRACTION) -> dict:
    """Space-time criterion of the Fig. 5 regime: a single pulse travelling
    steadily through the periodic boundaries (docs/analysis.md).

    slip_rate is [n_snapshots, N] (rows at `time`).  Over the last
    `late_fraction` of the record: (a) the largest slip rate of every
    snapshot exceeds PULSE_MIN_RATE v0 (never stuck everywhere); (b) the
    nodes slipping faster than 0.1 of it cover at most
    PULSE_MAX_WIDTH_FRACTION of the interface (median; a localised pulse,
    not the uniform k = 0 mode); (c) successive snapshots (lag chosen so that
    the median shift is >= 3 nodes, for slow pulses) are the same profile of
    log10 v shifted: median correlation at the best circular shift >=
    PULSE_MIN_CORRELATION; (d) at least PULSE_MIN_MOVING_FRACTION of the
    pairs shift it, in the majority direction; (e) the total displacement is
    at least one period L.  Speed changes are allowed.  With fewer than
    PULSE_MIN_SNAPSHOTS late snapshots the criterion does not decide
    (`determined` False).  `onset_time` (pulses only) is the earliest snapshot
    time from which every window of PULSE_MIN_SNAPSHOTS successive pairs has
    at least 90 % of its pairs meeting (a)-(d): the end of the coarsening.
    Speeds (m/s if dx is in m and time in s) use the sub-node shift."""
    t = np.asarray(time, float)
    v = np.abs(np.asarray(slip_rate, float))
    out = {"flag": False, "determined": False, "n_late": 0, "min_max_slip_rate_v0": math.nan,
           "median_width_fraction": math.nan, "median_correlation": math.nan, "moving_fraction": math.nan,
           "travelled_periods": math.nan, "speed_median": math.nan, "speed_min": math.nan,
           "speed_max": math.nan, "lag": 0, "onset_time": math.nan}
    if t.size < 2 or v.ndim != 2:
        return out
    n_nodes = v.shape[1]
    late = np.nonzero(t >= t[0] + (1.0 - late_fraction) * (t[-1] - t[0]))[0]
    out["n_late"] = int(late.size)
    if late.size < PULSE_MIN_SNAPSHOTS:
        return out
    out["determined"] = True
    vmax = v.max(axis=1)
    width = np.mean(v >= 0.1 * vmax[:, None], axis=1)
    z = np.log10(np.maximum(v, 1e-3 * v0) / v0)

    spectra = {}  # snapshot index -> _profile_spectrum of its profile, computed once

    def spectrum(i):
        if i not in spectra:
            spectra[i] = _profile_spectrum(z[i])
        return spectra[i]

    def pairs(indices, lag):
        return [(i, j) + _best_shift(spectrum(i), spectrum(j), n_nodes)
                for i, j in zip(indices[:-lag], indices[lag:])]

    lag = 1
    pr = pairs(late, lag)
    while np.median(np.abs([p[2] for p in pr])) < 3 and 2 * lag <= late.size // 4:
        lag *= 2
        pr = pairs(late, lag)
    shifts = np.array([p[2] for p in pr], float)
    corr = np.array([p[3] for p in pr], float)
    fine = np.array([p[4] for p in pr], float)
    dts = np.array([t[p[1]] - t[p[0]] for p in pr], float)
    moving = shifts != 0
    direction = np.sign(np.sum(np.sign(shifts))) or 1.0
    same_way = moving & (np.sign(shifts) == direction)
    speeds = fine[moving] * dx / dts[moving]
    L = n_nodes * dx
    # Non-overlapping pairs of the lag chain add up to the displacement over the late part.
    travelled = float(np.sum(np.abs(fine[::lag])) * dx / L)
    a = float(vmax[late].min() / v0)
    b = float(np.median(width[late]))
    c = float(np.nanmedian(corr)) if np.isfinite(corr).any() else math.nan
    d = float(np.mean(same_way))
    out.update(min_max_slip_rate_v0=a, median_width_fraction=b, median_correlation=c, moving_fraction=d,
               travelled_periods=travelled, lag=int(lag), direction=int(direction),
               speed_median=float(np.median(np.abs(speeds))) if speeds.size else math.nan,
               speed_min=float(np.min(np.abs(speeds))) if speeds.size else math.nan,
               speed_max=float(np.max(np.abs(speeds))) if speeds.size else math.nan)
    out["flag"] = bool(a > PULSE_MIN_RATE and b <= PULSE_MAX_WIDTH_FRACTION and c >= PULSE_MIN_CORRELATION
                       and d >= PULSE_MIN_MOVING_FRACTION and travelled >= PULSE_MIN_TRAVEL)
    if out["flag"]:
        # Onset: the same per-pair test over the whole record (same lag); every
        # window of PULSE_MIN_SNAPSHOTS pairs from the onset on is >= 90 % good.
        allpr = pairs(np.arange(t.size), lag)
        good = np.array([vmax[i] > PULSE_MIN_RATE * v0 and vmax[j] > PULSE_MIN_RATE * v0
                         and width[i] <= PULSE_MAX_WIDTH_FRACTION and np.isfinite(r)
                         and r >= PULSE_MIN_CORRELATION and np.sign(sh) == direction
                         for i, j, sh, r, _ in allpr], float)
        w = min(PULSE_MIN_SNAPSHOTS, good.size)
        frac = np.convolve(good, np.ones(w) / w, mode="valid")
        bad = np.nonzero(frac < PULSE_MIN_MOVING_FRACTION - 1e-12)[0]
        start = int(bad[-1] + 1) if bad.size else 0
        while start < good.size and not good[start]:
            start += 1
        out["onset_time"] = float(t[allpr[start][0]]) if start < len(allpr) else math.nan
    return out


PULSE_EPISODE_WINDOW_TRANSITS = 20.0  # window of pulse_episodes, in L/c_s


def pulse_episodes(time, slip_rate, v0: float, dx: float, window: float) -> dict:
    """Where in a record the space-time pulse criterion holds: the record is cut
    into consecutive windows of `window` seconds and the criterion of
    periodic_pulse_from_spacetime is applied, unchanged, to the whole of each
    window (late_fraction = 1).  A pulse that lives for a while and then breaks
    up (seen in the Fig. 5 run) is reported as such instead of only "no pulse
    in the late half".  The window must let a slow pulse travel the criterion's
    PULSE_MIN_TRAVEL periods: 20 L/c_s admits speeds down to 0.025 c_s.

    Returns windows [(t0, t1)], flags, determined, results (the criterion's
    full output per window), and the longest stretch of consecutive pulse
    windows (longest_start, longest_end; NaN if none)."""
    t = np.asarray(time, float)
    v = np.asarray(slip_rate)
    out = {"windows": [], "flags": [], "determined": [], "results": [], "longest_start": math.nan,
           "longest_end": math.nan, "pulse_fraction": math.nan}
    if t.size < 2 or not window > 0:
        return out
    edges = np.arange(t[0], t[-1] + 1e-12 * window, window)
    for t0 in edges:
        t1 = t0 + window
        if t1 > t[-1] + 1e-9 * window:
            break  # a partial last window would judge a shorter record
        rows = np.nonzero((t >= t0) & (t < t1))[0]
        r = periodic_pulse_from_spacetime(t[rows], v[rows], v0, dx, late_fraction=1.0)
        out["windows"].append((float(t0), float(t1)))
        out["results"].append(r)
        out["flags"].append(bool(r["flag"]))
        out["determined"].append(bool(r["determined"]))
    best, start = (0, None), None
    for i, flag in enumerate(out["flags"] + [False]):
        if flag and start is None:
            start = i
        elif not flag and start is not None:
            if i - start > best[0]:
                best = (i - start, start)
            start = None
    if best[0]:
        out["longest_start"] = out["windows"][best[1]][0]
        out["longest_end"] = out["windows"][best[1] + best[0] - 1][1]
    decided = [f for f, d in zip(out["flags"], out["determined"]) if d]
    out["pulse_fraction"] = float(np.mean(decided)) if decided else math.nan
    return out


def periodic_pulse_decision(by_events: dict, by_timeseries: dict, by_spacetime: dict | None) -> tuple[bool, str]:
    """The `periodic_pulse` flag: the space-time criterion when it can decide
    (enough snapshots), else the event OR time-series criteria."""
    if by_spacetime is not None and by_spacetime.get("determined"):
        return bool(by_spacetime["flag"]), "spacetime"
    return bool(by_events.get("flag") or by_timeseries.get("flag")), "events_or_timeseries"


def periodic_pulse_of_run(path, catalog: dict, info: RunInfo) -> dict:
    """All three periodic-pulse criteria of one run file and the decision."""
    by_events = periodic_pulse_from_catalog(catalog, info)
    with open_h5(path) as f:
        by_ts = (periodic_pulse_from_timeseries(read_times(f, "timeseries/time"), f["timeseries/max_slip_rate"][:], info.v0)
                 if "timeseries" in f else {"flag": False})
    st = read_spacetime(path)
    by_st = None
    if st is not None:
        by_st = periodic_pulse_from_spacetime(st[0], st[2], info.v0, info.L / st[2].shape[1])
    flag, basis = periodic_pulse_decision(by_events, by_ts, by_st)
    return {"periodic_pulse": flag, "periodic_pulse_basis": basis, "periodic_pulse_events": by_events,
            "periodic_pulse_timeseries": by_ts, "periodic_pulse_spacetime": by_st or {"determined": False}}


@dataclasses.dataclass
class NodalSlipGroups:
    label: np.ndarray        # [n_levels, N] int64: detected-event index of each NS, -1 = no NS
    n_detected: int          # events before any exclusion or filter
    kept: np.ndarray         # [n_detected] bool: passes exclusion and size filters (C++ rules)
    waiting_time_threshold: float


def group_nodal_slips(crossing_time: np.ndarray, delta_th: float, v0: float, alpha: float = DEFAULT_ALPHA,
                      min_extent_dx: float = 2.0, min_mean_slip_dth: float = 2.0,
                      exclude_first_last: bool = True, min_slip_rate_v0: float = 0.0) -> NodalSlipGroups:
    """Groups the nodal slips of crossing_time [n_levels, N] into events by the
    global waiting time (> alpha delta_th / (v0 N) starts a new event), with
    the conventions of docs/events.md: a column ends at its first NaN, ties
    are ordered by node then level, first and last events are excluded before
    the size filters; with min_slip_rate_v0 > 0 the nodal slips slower than
    min_slip_rate_v0 v0 (delta_th / Delta t, Delta t from the node's previous
    crossing or t = 0) are ignored (label -1).  For plotting only; the catalog
    comes from the C++ code.
    """
    ct = np.asarray(crossing_time, float)
    n_levels, n = ct.shape
    finite = np.isfinite(ct)
    valid = np.cumprod(finite, axis=0).astype(bool)  # NaN tail: ignore after the first NaN
    if min_slip_rate_v0 > 0:
        dt = np.diff(np.vstack([np.zeros((1, n)), ct]), axis=0)
        with np.errstate(invalid="ignore"):
            valid &= ~(delta_th < min_slip_rate_v0 * v0 * dt)  # the C++ below_min_slip_rate
    level, node = np.nonzero(valid)
    t = ct[level, node]
    order = np.lexsort((level, node, t))
    threshold = alpha * delta_th / (v0 * n)
    t_sorted = t[order]
    new_event = np.concatenate(([True], np.diff(t_sorted) > threshold)) if t.size else np.array([], bool)
    event_sorted = np.cumsum(new_event) - 1
    n_detected = int(event_sorted[-1] + 1) if t.size else 0
    label = np.full(ct.shape, -1, dtype=np.int64)
    label[level[order], node[order]] = event_sorted
    kept = np.zeros(n_detected, bool)
    if n_detected:
        ev_of_ns = label[level, node]
        n_ns = np.bincount(ev_of_ns, minlength=n_detected)
        pair = np.unique(ev_of_ns * n + node)  # distinct (event, node)
        n_nodes_ev = np.bincount(pair // n, minlength=n_detected)
        kept = (n_nodes_ev >= min_extent_dx) & (n_ns >= min_mean_slip_dth * n_nodes_ev)
        if exclude_first_last:
            kept[0] = False
            kept[-1] = False
    return NodalSlipGroups(label=label, n_detected=n_detected, kept=kept, waiting_time_threshold=threshold)
