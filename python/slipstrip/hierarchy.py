"""Measurements behind the paper's event-hierarchy and procedure claims
(Figs. 1c, 2, S4-S7, S9 and the mesh section of the supplement), used by the
reproduction report (python/slipstrip/report/).

* Slip and slip rate of any time from the slip sampling (`slip_at`,
  `velocity_from_sampling`): the crossing times of the levels j delta_th give
  the slip of every node at every time to within delta_th, and the slip rate on
  a time grid, as the paper reconstructs v(x, t) of an event (Fig. S5b).
* The shape of an event's slip profile (`crack_fit`): least squares of
  A sqrt((L_s/2)^2 - (x - x_c)^2), the crack-like form of the paper's Fig. 2b.
* Where p(u) changes from its power law to the hump of large events
  (`density_split`), the first detected event's extent (`first_event`),
  local minima/maxima near an arrest edge, and the tip (process) zone of a
  propagating rupture in snapshots (`tip_zone`).

Every function is plain numpy on arrays; tests/python/test_hierarchy.py checks
each on synthetic data with a known answer.
"""
from __future__ import annotations

import math

import numpy as np

from .runfile import open_h5


# ---------------------------------------------------------------------------
# Slip and slip rate from the slip sampling
# ---------------------------------------------------------------------------

class SlipHistory:
    """Slip of every node at any time, from crossing_time [n_levels, N] (row
    j: the time node i reached (level_offset + j + 1) delta_th; NaN: not yet),
    linear in time between the crossings on either side.  Rows below the band
    count as reached (the band must start below the slip of every node at the
    earliest time asked).

    Columns are non-decreasing (docs/output.md), so the levels a node has
    reached by t are counted only inside the rows where some, but not every,
    node has crossed by t; the bounds of those rows are computed once."""

    def __init__(self, crossing_time: np.ndarray, delta_th: float, level_offset: int = 0):
        ct = np.asarray(crossing_time, float)
        self.filled = np.where(np.isnan(ct), np.inf, ct)
        self.delta_th, self.level_offset = float(delta_th), int(level_offset)
        n_rows = ct.shape[0]
        # first[j]: earliest crossing in rows >= j; last[j]: time by which every node crossed rows <= j.
        self.first = np.minimum.accumulate(self.filled.min(axis=1)[::-1])[::-1] if n_rows else np.zeros(0)
        self.last = np.maximum.accumulate(self.filled.max(axis=1)) if n_rows else np.zeros(0)

    def at(self, t, nodes=None) -> np.ndarray:
        """[len(t), len(nodes)] (or [len(nodes)] for a scalar t) slip [m]."""
        f = self.filled if nodes is None else self.filled[:, nodes]
        n_rows, n = f.shape
        ts = np.atleast_1d(np.asarray(t, float))
        out = np.empty((ts.size, n))
        cols = np.arange(n)
        for m, tm in enumerate(ts):
            j_full = int(np.searchsorted(self.last, tm, side="right"))
            j_none = max(int(np.searchsorted(self.first, tm, side="right")), j_full)
            k = j_full + np.count_nonzero(f[j_full:j_none] <= tm, axis=0)
            lo = np.where(k > 0, f[np.maximum(k - 1, 0), cols], -np.inf)
            hi_ = np.where(k < n_rows, f[np.minimum(k, n_rows - 1), cols], np.inf)
            frac = np.zeros(n)
            ok = np.isfinite(lo) & np.isfinite(hi_) & (hi_ > lo)
            frac[ok] = (tm - lo[ok]) / (hi_[ok] - lo[ok])
            out[m] = (self.level_offset + k + frac) * self.delta_th
        return out if np.ndim(t) else out[0]

    def velocity(self, t_grid, nodes=None) -> np.ndarray:
        """Slip rate [len(t_grid) - 1, nodes] on the midpoints of t_grid (the
        paper's Fig. S5b reconstruction of v(x, t))."""
        g = np.asarray(t_grid, float)
        return np.diff(self.at(g, nodes), axis=0) / np.diff(g)[:, None]


def slip_at(crossing_time: np.ndarray, delta_th: float, t, level_offset: int = 0) -> np.ndarray:
    """`SlipHistory(crossing_time, delta_th, level_offset).at(t)`."""
    return SlipHistory(crossing_time, delta_th, level_offset).at(t)


def velocity_from_sampling(crossing_time: np.ndarray, delta_th: float, t_grid, level_offset: int = 0) -> np.ndarray:
    """Slip rate [len(t_grid) - 1, N] on the midpoints of t_grid: the
    difference of `slip_at` between successive grid times over their spacing
    (the paper's Fig. S5b reconstruction)."""
    return SlipHistory(crossing_time, delta_th, level_offset).velocity(t_grid)


def sampling_band(path, t0: float, t1: float, margin_levels: int = 200, max_values: int = 20_000_000):
    """The rows of /slip_sampling/crossing_time that hold every crossing of
    every node in [t0, t1], plus `margin_levels` on either side: (band,
    level_offset).  Starts from the rows the mean slip rate would give and
    widens until, in every column, the first row is at or before t0 (or the
    column ends) and the last row is after t1 (or NaN), reading at most
    max_values crossing times (160 MB): a node locked far behind (or ahead of)
    the band then has no crossing in it, which is right for the slip it
    accumulates in [t0, t1] unless it slips that far then."""
    with open_h5(path) as f:
        ds = f["slip_sampling/crossing_time"]
        n_levels = ds.shape[0]
        max_rows = max(10 * margin_levels, max_values // max(1, ds.shape[1]))
        v0 = float(f["slip_sampling"].attrs["v0"])
        dth = float(f["slip_sampling"].attrs["delta_th"])
        lo = max(0, int(v0 * t0 / dth) - 5 * margin_levels)
        hi = min(n_levels, int(v0 * t1 / dth) + 5 * margin_levels)
        while True:
            band = ds[lo:hi]
            first_ok = lo == 0 or bool(np.all(~(band[0] > t0)))  # row lo reached at or before t0 (NaN: never)
            last_ok = hi == n_levels or bool(np.all(~(band[-1] <= t1)))
            if (first_ok and last_ok) or hi - lo >= max_rows:
                break
            if not first_ok:
                lo = max(0, lo - 2 * (hi - lo))
            if not last_ok:
                hi = min(n_levels, hi + 2 * (hi - lo))
        return np.asarray(band, float), lo


# ---------------------------------------------------------------------------
# Shapes of slip profiles and fields
# ---------------------------------------------------------------------------

def ring_segment(mask, center: int) -> tuple[int, int] | None:
    """(first, last) node of the run of True on a periodic ring that holds
    `center` (last may be < first when it wraps; None if mask[center] is False)."""
    m = np.asarray(mask, bool)
    n = m.size
    if not m[center]:
        return None
    if m.all():
        return 0, n - 1
    a = center
    while m[(a - 1) % n]:
        a = (a - 1) % n
    b = center
    while m[(b + 1) % n]:
        b = (b + 1) % n
    return a, b


def crack_fit(x, slip) -> dict:
    """How crack-like a slip profile is: least squares of
    slip(x) = A sqrt((L_s/2)^2 - (x - x_c)^2), the paper's Fig. 2b form, with
    L_s and the centre x_c those of the slip zone (x are its nodes, equally
    spaced; its edges half a spacing beyond the first and last node) and only
    A fitted.  R^2 = 1 - SS_res / SS_tot on the given points.  A profile piled
    up at one end or flat-topped gives a low R^2."""
    x = np.asarray(x, float)
    y = np.asarray(slip, float)
    out = {"r2": math.nan, "A": math.nan, "x_c": math.nan, "h": math.nan}
    if x.size < 4 or np.ptp(y) <= 0:
        return out
    dx = float(x[1] - x[0])
    xc = 0.5 * (x[0] + x[-1])
    h = 0.5 * (x[-1] - x[0]) + 0.5 * dx
    s = np.sqrt(np.maximum(0.0, h * h - (x - xc) ** 2))
    a = float(s @ y) / float(s @ s)
    ss_res = float(((a * s - y) ** 2).sum())
    ss_tot = float(((y - y.mean()) ** 2).sum())
    out.update(r2=1.0 - ss_res / ss_tot if ss_tot > 0 else math.nan, A=a, x_c=xc, h=h)
    return out


def local_extrema(y, kind: str = "min", smooth: int = 1) -> np.ndarray:
    """Indices of the strict local minima ("min") or maxima ("max") of y on a
    periodic ring, after a running mean over `smooth` nodes."""
    y = np.asarray(y, float)
    if smooth > 1:
        k = np.ones(smooth) / smooth
        y = np.convolve(np.concatenate([y[-smooth:], y, y[:smooth]]), k, mode="same")[smooth:-smooth]
    left, right = np.roll(y, 1), np.roll(y, -1)
    sel = (y < left) & (y <= right) if kind == "min" else (y > left) & (y >= right)
    return np.flatnonzero(sel)


def ring_distance(i, j, n: int):
    d = np.abs(np.asarray(i) - np.asarray(j)) % n
    return np.minimum(d, n - d)


def nearest_extremum_distance(indices, position: int, n: int) -> float:
    """Distance (nodes, periodic) from `position` to the nearest index in `indices`."""
    idx = np.asarray(indices)
    return float(ring_distance(idx, position, n).min()) if idx.size else math.inf


def bilateral_then_pulses(slip_rate, i0: int, v0: float, dx: float, min_rate: float = 3.0) -> dict:
    """The two stages of a large event's slip rate v [n_t, N] on a time grid
    (the paper's event 5): a node slips when v > v_th = max(min_rate v0,
    sqrt(v0 v_peak)), v_peak the largest rate at the nucleation node i0.
    center_steps: grid steps from the first step at which i0 slips to the
    first later step at which it does not (the bilateral stage).  After that,
    at every step, the slipping runs of >= 2 nodes are the pulses: n_pulses is
    the median count over the steps with any, pulse_width_nodes the median
    width of the runs at the steps with exactly n_pulses of them."""
    v = np.abs(np.asarray(slip_rate, float))
    out = {"found": False, "center_steps": 0, "n_pulses": 0, "pulse_width_nodes": math.nan, "v_th": math.nan}
    if v.ndim != 2 or v.shape[0] < 3:
        return out
    v_peak = float(v[:, i0].max())
    v_th = max(min_rate * v0, math.sqrt(v0 * v_peak))
    out["v_th"] = v_th
    slipping = v > v_th
    on = np.flatnonzero(slipping[:, i0])
    if on.size == 0:
        return out
    k0 = int(on[0])
    off = np.flatnonzero(~slipping[k0:, i0])
    k1 = k0 + int(off[0]) if off.size else v.shape[0]
    out.update(found=True, center_steps=k1 - k0)
    counts, widths = [], []
    for k in range(k1, v.shape[0]):
        runs = _runs(slipping[k])
        runs = [r for r in runs if r >= 2]
        if runs:
            counts.append(len(runs))
            widths.append(runs)
    if counts:
        n_p = int(np.median(counts))
        out["n_pulses"] = n_p
        w = [x for c, r in zip(counts, widths) if c == n_p for x in r]
        out["pulse_width_nodes"] = float(np.median(w)) if w else math.nan
    return out


def _runs(mask) -> list[int]:
    """Lengths of the runs of True on a periodic ring."""
    m = np.asarray(mask, bool)
    if not m.any():
        return []
    if m.all():
        return [m.size]
    r = np.roll(m, -int(np.argmin(m)))
    d = np.diff(np.concatenate(([0], r.astype(int), [0])))
    return list(np.flatnonzero(d == -1) - np.flatnonzero(d == 1))


# ---------------------------------------------------------------------------
# Statistics of the catalogs
# ---------------------------------------------------------------------------

def density_split(values, grid_points: int = 512) -> dict:
    """Where a distribution with a power-law part and a hump at larger values
    changes from one to the other: on a Gaussian kernel density of ln x (Scott
    bandwidth), the minimum between the two most prominent local maxima (the
    low one at the detection floor or in the power-law part, the other the
    hump).  Returns split (x at the minimum), hump (x at the hump's maximum),
    depth (density at the minimum over that at the hump); NaN split if the
    density of ln x has fewer than two local maxima (no hump)."""
    x = np.asarray(values, float)
    x = np.log(x[np.isfinite(x) & (x > 0)])
    out = {"split": math.nan, "hump": math.nan, "depth": math.nan}
    if x.size < 20 or np.ptp(x) == 0:
        return out
    from scipy import stats  # imported where used: most of a command's start-up time
    g = np.linspace(x.min(), x.max(), grid_points)
    d = stats.gaussian_kde(x)(g)
    peaks = np.flatnonzero((d[1:-1] > d[:-2]) & (d[1:-1] >= d[2:])) + 1
    if d[0] > d[1]:
        peaks = np.concatenate([[0], peaks])
    if d[-1] > d[-2]:
        peaks = np.concatenate([peaks, [d.size - 1]])
    if peaks.size < 2:
        return out

    def prominence(i):
        left = d[: i + 1].min() if i > 0 else d[i]
        right = d[i:].min() if i < d.size - 1 else d[i]
        higher_left = np.flatnonzero(d[:i] > d[i])
        higher_right = np.flatnonzero(d[i + 1:] > d[i])
        lo_l = d[higher_left[-1]: i + 1].min() if higher_left.size else left
        lo_r = d[i: i + 1 + higher_right[0] + 1].min() if higher_right.size else right
        return d[i] - max(lo_l, lo_r)

    top = sorted(peaks, key=prominence, reverse=True)[:2]
    a, b = sorted(top)
    m = a + int(np.argmin(d[a: b + 1]))
    out.update(split=float(math.exp(g[m])), hump=float(math.exp(g[b])), depth=float(d[m] / d[b]))
    return out


def first_event(path, alpha: float, rows_per_read: int = 512, max_values: int = 4_000_000) -> dict:
    """The first detected event of a run (before the catalog's first/last
    exclusion): the nodal slips from the start up to the first waiting time
    longer than alpha delta_th / (v0 N) (docs/events.md).  Reads the first rows
    of the slip sampling, more until every node's crossings are past the end of
    that event, at most max_values crossing times (32 MB); if the event is not
    over by then, `complete` is False and the extent is a lower bound (the
    nodes that slipped in it within the rows read).  Returns extent (nodes
    that slipped in it / N), n_ns, t_end, complete."""
    with open_h5(path) as f:
        ds = f["slip_sampling/crossing_time"]
        a = f["slip_sampling"].attrs
        n_levels, n = ds.shape
        threshold = alpha * float(a["delta_th"]) / (float(a["v0"]) * n)
        max_rows = max(rows_per_read, max_values // max(n, 1))
        rows = min(rows_per_read, n_levels)
        while True:
            ct = np.asarray(ds[:rows], float)
            valid = np.cumprod(np.isfinite(ct), axis=0).astype(bool)
            t = np.sort(ct[valid])
            gaps = np.flatnonzero(np.diff(t) > threshold)
            t_end = float(t[gaps[0]]) if gaps.size else math.inf
            # Complete if every column's last row read is after the event's end (or the column ended).
            last = ct[-1]
            complete = rows >= n_levels or bool(np.all(~(last <= t_end)))
            if complete or rows >= min(max_rows, n_levels):
                break
            rows = min(n_levels, max_rows, 2 * rows)
        in_event = valid & (ct <= t_end)
        nodes = in_event.any(axis=0)
        return {"extent": float(nodes.mean()), "n_ns": int(in_event.sum()), "t_end": t_end,
                "complete": bool(complete), "n_nodes": int(n)}


# ---------------------------------------------------------------------------
# Tip (process) zone of a propagating rupture
# ---------------------------------------------------------------------------

TIP_ZONE_DROP = 0.9  # the tip zone ends where the shear stress has made this fraction of its drop


def tip_zone(x, shear_stress, slip, slip_rate, front: int, direction: int, D: float,
             v_threshold: float, ahead: int = 20) -> dict:
    """Size of the zone at a rupture tip over which the strength breaks down:
    from the node of peak shear stress at the tip or up to `ahead` nodes ahead
    of it, back to the first node where the shear stress has dropped by TIP_ZONE_DROP
    of the way from that peak to its minimum over the slipping region behind
    the tip (nodes above v_threshold, from the tip back).  `front` is the tip
    node (outermost node above v_threshold), `direction` +1 for a tip moving to
    larger x, -1 otherwise.  Distance in the units of x (uniform spacing).
    NaN if the slipping region is shorter than 4 nodes or has no drop."""
    tau = np.asarray(shear_stress, float)
    n = tau.size
    dx = float(x[1] - x[0])
    i_peak = max(((front + direction * k) % n for k in range(0, ahead + 1)), key=lambda i: tau[i])
    v = np.abs(np.asarray(slip_rate, float))
    region = []
    for k in range(0, n // 2):
        i = (front - direction * k) % n
        if v[i] < v_threshold and k > 0:
            break
        region.append(i)
    if len(region) < 4:
        return {"size": math.nan, "peak": float(tau[i_peak]), "drop": math.nan}
    tmin = float(tau[region].min())
    drop = float(tau[i_peak]) - tmin
    if drop <= 0:
        return {"size": math.nan, "peak": float(tau[i_peak]), "drop": drop}
    level = tau[i_peak] - TIP_ZONE_DROP * drop
    # Walk back from the peak (through the tip into the slipping region).
    for k in range(0, n // 2):
        i = (i_peak - direction * k) % n
        if tau[i] <= level:
            return {"size": k * dx, "peak": float(tau[i_peak]), "drop": drop, "i_peak": int(i_peak)}
    return {"size": math.nan, "peak": float(tau[i_peak]), "drop": drop}
