"""Slip-event statistics and figures (paper Figs. 1b-e, 2b-d, S3-S9).

Input is one run file (docs/output.md) with a slip-event catalog in group
/events (docs/events.md).  The catalog is produced by the C++ detector, called
in this process through the bindings (`run_event_detection`, the same calls as
`slipstrip events`); this module never re-derives catalog numbers itself.  The one exception is the event-coloured space-slip map (Fig. S4b),
whose colours come from `group_nodal_slips`, a numpy re-implementation of the
grouping used for plotting only (a test checks that it finds the same number
of events as the C++ detector).

Conventions (see docs/analysis.md):
  * normalisations: u_mean / D, T v0 / D, M0 / (mu D L)   (Figs. S8 captions);
  * small events: u_mean < D, large events: u_mean >= D;
  * exponents are reported positive: p(x) ~ x^(-exponent).

Command line (dispatched by `python3 -m slipstrip analyze ...`):
    analyze RUN.h5 [--out-dir DIR] [--pdf] [--alpha 15] [--event INDEX]
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import sys
import tempfile
import tomllib
from pathlib import Path

import h5py
import numpy as np
from scipy import optimize, stats

from .paths import OutputPathError, check_outputs, lock_run, one_line
from .runfile import decode_attr, open_h5, read_times, unreadable_reason

DEFAULT_ALPHA = 15.0
SENSITIVITY_ALPHAS = (8.0, 15.0, 30.0, 60.0)
SPANNING_FRACTION = 0.9  # L_s >= 0.9 L counts as system-spanning
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
MIN_FIT_EVENTS = 10  # fewer than this in a subset: the fit returns NaN
# Below this many events in a fitted power-law tail the summary carries a
# caution: the exponent's standard error (a - 1)/sqrt(n) is above ~0.1 for
# a ~ 2, and the power-law form itself cannot be told apart from other
# heavy-tailed shapes with so few points.
POWER_LAW_CAUTION_EVENTS = 100
# Transient cut (docs/analysis.md, "Transient cut"): the run is split into
# TRANSIENT_BATCHES equal time batches; MSER (White 1997) on the batch series
# of event counts and of the mean log10(u/D) picks the truncation that
# minimises the standard error of the mean of what is kept, within the first
# TRANSIENT_MAX_FRACTION of the run; the cut is the later of the two.
TRANSIENT_BATCHES = 40
TRANSIENT_MAX_FRACTION = 0.5
STATIONARITY_LEVEL = 0.05    # first-vs-last-fifth KS tests on what is kept pass at p >= 5 %
CATALOG_FIELDS = ("t_start", "T", "x_start", "L_s", "u_mean", "M0", "max_slip_rate", "n_clusters")


# ---------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------

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
    n_nodes: int
    duration: float     # simulated time covered by the file [s]


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
        return RunInfo(D=D, L=L, H=H, v0=v0, mu=mu, c_s=math.sqrt(mu / rho) if rho > 0 else math.nan,
                       sigma0=float(config.get("loading", {}).get("normal_stress", math.nan)),
                       delta_th=float(ss.get("delta_th", math.nan)), n_nodes=n, duration=duration)


def read_catalog(path: str | os.PathLike) -> dict:
    """/events of `path` as {field: ndarray} plus 'attrs' (dict)."""
    with open_h5(path) as f:
        if "events" not in f:
            raise KeyError(f"{path}: no group /events (run `slipstrip events {path}` first)")
        g = f["events"]
        catalog = {k: np.asarray(g[k][:]) for k in CATALOG_FIELDS if k in g}
        catalog["attrs"] = {k: decode_attr(v) for k, v in g.attrs.items()}
    return catalog


# ---------------------------------------------------------------------------
# Event detection: the C++ detector through the bindings, in this process
# ---------------------------------------------------------------------------

def run_event_detection(run_path: str | os.PathLike, alpha: float = DEFAULT_ALPHA,
                        out: str | os.PathLike | None = None) -> str:
    """Detects slip events in /slip_sampling of `run_path` and writes the
    catalog as /events of `out` (default: the run file itself, replacing its
    /events); returns the file holding /events.  The same C++ calls as
    `slipstrip events RUN --alpha A [--out OUT]` (bindings, in-process), so
    the file is the CLI's byte for byte.  RuntimeError if the run file cannot
    be read or the target cannot be written."""
    from . import _slipstrip
    target = os.fspath(out if out is not None else run_path)
    _slipstrip.detect_events_into_file(os.fspath(run_path), target, alpha=float(alpha))
    return target


def catalog_for(run_path: str | os.PathLike, alpha: float = DEFAULT_ALPHA,
                workdir: str | os.PathLike | None = None, write_into_run: bool = False) -> dict:
    """The catalog of `run_path` for `alpha`: /events of the run file if it was
    made with this alpha; else detection is run into a catalog file in
    `workdir` (or a temporary one).  Only with write_into_run=True, and when
    the run file has no /events yet, is the catalog added to the run file."""
    with open_h5(run_path) as f:
        stored_alpha = float(f["events"].attrs["alpha"]) if "events" in f else None
    if stored_alpha is not None and stored_alpha == float(alpha):
        return read_catalog(run_path)
    if stored_alpha is None and write_into_run:
        # Not while a run or resume writes the file (LockHeldError, a ValueError,
        # is raised); a read-only directory or file falls back to a separate
        # catalog file.
        try:
            with lock_run(run_path):
                run_event_detection(run_path, alpha)
                return read_catalog(run_path)
        except (RuntimeError, OSError):
            pass
    if workdir is not None:
        out = Path(workdir) / f"events_alpha{alpha:g}.h5"
        run_event_detection(run_path, alpha, out)
        return read_catalog(out)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / f"events_alpha{alpha:g}.h5"
        run_event_detection(run_path, alpha, out)
        return read_catalog(out)


# ---------------------------------------------------------------------------
# Distributions and fits
# ---------------------------------------------------------------------------

def normalised_observables(catalog: dict, info: RunInfo) -> dict:
    """u_mean/D, T v0/D, M0/(mu D L) (the paper's Fig. S8 normalisations)."""
    return {
        "u": np.asarray(catalog["u_mean"], float) / info.D,
        "T": np.asarray(catalog["T"], float) * info.v0 / info.D,
        "M0": np.asarray(catalog["M0"], float) / (info.mu * info.D * info.L),
    }


def log_binned_pdf(values, bins_per_decade: int = 5, lo: float | None = None, hi: float | None = None):
    """Histogram density on logarithmic bins.

    Only finite positive values are used; pdf = count / (n_used * bin width), so
    sum(pdf * diff(edges)) = 1 when [lo, hi] covers all of them.  Returns
    (centres (geometric), pdf, edges); empty arrays if there is nothing to bin.
    """
    x = np.asarray(values, float)
    x = x[np.isfinite(x) & (x > 0)]
    if x.size == 0:
        return np.array([]), np.array([]), np.array([])
    lo = x.min() if lo is None else lo
    hi = x.max() if hi is None else hi
    if hi <= lo:
        hi = lo * 1.0001
    n_bins = max(1, int(math.ceil(bins_per_decade * math.log10(hi / lo))))
    edges = np.logspace(math.log10(lo), math.log10(hi), n_bins + 1)
    edges[0], edges[-1] = lo, hi  # logspace round-off must not drop the extreme samples
    counts, _ = np.histogram(x, bins=edges)
    pdf = counts / (x.size * np.diff(edges))
    return np.sqrt(edges[:-1] * edges[1:]), pdf, edges


@dataclasses.dataclass(frozen=True)
class PowerLawFit:
    exponent: float       # p(x) ~ x^-exponent on [xmin, xmax]
    stderr: float         # asymptotic (Fisher) standard error
    xmin: float
    xmax: float           # inf: untruncated
    n: int                # samples in [xmin, xmax]
    ks: float             # KS distance between data in [xmin, xmax] and the fit
    bootstrap_stderr: float = math.nan


def _log_norm(a: float, lo: float, hi: float) -> float:
    """ln of Z(a) = int_lo^hi x^-a dx (hi may be inf, then a > 1)."""
    if math.isinf(hi):
        return math.log(lo ** (1.0 - a) / (a - 1.0))
    ll, lh = math.log(lo), math.log(hi)
    s = 1.0 - a
    if abs(s) * (lh - ll) < 1e-8:
        return math.log(lh - ll) + 0.5 * s * (lh + ll)
    # Z = (hi^s - lo^s)/s, computed as lo^s expm1(s (lh - ll)) / s for accuracy.
    return s * ll + math.log(math.expm1(s * (lh - ll)) / s)


def _power_law_cdf(x, a, lo, hi):
    x = np.asarray(x, float)
    s = 1.0 - a
    if math.isinf(hi):
        return 1.0 - (x / lo) ** s
    if abs(s) < 1e-12:
        return np.log(x / lo) / math.log(hi / lo)
    return np.expm1(s * np.log(x / lo)) / math.expm1(s * math.log(hi / lo))


def _power_law_mle(x: np.ndarray, lo: float, hi: float) -> tuple[float, float]:
    """Exponent and Fisher standard error for samples x in [lo, hi]."""
    n = x.size
    mean_log = float(np.mean(np.log(x)))
    if math.isinf(hi):
        a = 1.0 + 1.0 / (mean_log - math.log(lo))  # Clauset et al. (2009), Eq. 3.1
        return a, (a - 1.0) / math.sqrt(n)

    def nll(a):  # per sample
        return a * mean_log + _log_norm(a, lo, hi)

    res = optimize.minimize_scalar(nll, bounds=(-10.0, 20.0), method="bounded",
                                   options={"xatol": 1e-10})
    a = float(res.x)
    # d^2 ln Z / da^2 = Var_a(ln x): the log-likelihood is an exponential family in ln x.
    h = 1e-4
    curv = (_log_norm(a + h, lo, hi) - 2 * _log_norm(a, lo, hi) + _log_norm(a - h, lo, hi)) / h ** 2
    return a, 1.0 / math.sqrt(n * curv) if curv > 0 else math.nan


EXPONENT_XMIN_FACTORS = (0.25, 0.5, 1.0, 2.0, 4.0)  # x_min / (KS-optimal x_min) of the fit-range sweep


def exponent_xmin_sweep(values, xmin_opt: float, xmax: float = math.inf,
                        factors=EXPONENT_XMIN_FACTORS, min_tail: int = 50) -> list[PowerLawFit]:
    """The power-law MLE with its lower cut-off held at factor * xmin_opt, for
    each factor (fits with x_min below the smallest sample or with fewer than
    `min_tail` samples in [x_min, x_max] are left out).  The spread of the exponents over a factor 16 in x_min is the
    systematic error of "the" exponent of a distribution that is not exactly a
    power law: a straight guide to the eye on a log-log plot (the paper's
    exponents) has no x_min, so its slope can be compared only with this range.
    """
    x = np.asarray(values, float)
    x = x[np.isfinite(x) & (x > 0) & (x <= xmax)]
    out = []
    if not (math.isfinite(xmin_opt) and xmin_opt > 0):
        return out
    for factor in factors:
        xmin = factor * xmin_opt
        # Below the smallest sample the model's normalisation covers a range
        # with no data (a detection floor, not a power law): left out.
        if x.size == 0 or xmin < x.min() or np.count_nonzero(x >= xmin) < min_tail or xmin >= xmax:
            continue
        fit = fit_power_law(x, xmin=xmin, xmax=xmax)
        if math.isfinite(fit.exponent):
            out.append(fit)
    return out


def fit_power_law(values, xmin: float | None = None, xmax: float = math.inf, min_tail: int = 50,
                  max_candidates: int = 200, n_bootstrap: int = 0, seed: int = 0) -> PowerLawFit:
    """Continuous power law p(x) ~ x^-a on [xmin, xmax] by maximum likelihood.

    xmax = inf: the Clauset-Shalizi-Newman estimator.  Finite xmax: the
    truncated power law, whose likelihood is maximised numerically.  If xmin
    is None it is chosen, as in Clauset et al., to minimise the KS distance
    between the data in [xmin, xmax] and the fit, among up to `max_candidates`
    sample values that leave at least `min_tail` samples.  Too few samples:
    NaN fields.  `n_bootstrap` > 0 adds a bootstrap standard error (resampling
    the samples in [xmin, xmax] with xmin held fixed).
    """
    x = np.asarray(values, float)
    x = np.sort(x[np.isfinite(x) & (x > 0) & (x <= xmax)])
    nan = PowerLawFit(math.nan, math.nan, math.nan, xmax, 0, math.nan)
    if xmin is None:
        if x.size < max(min_tail, 2):
            return nan
        candidates = np.unique(x[: x.size - min_tail + 1])
        if candidates.size > max_candidates:
            candidates = np.unique(np.quantile(candidates, np.linspace(0, 1, max_candidates),
                                               method="nearest"))
        best = None
        for c in candidates:
            fit = _fit_fixed(x, float(c), xmax)
            if np.isfinite(fit.ks) and (best is None or fit.ks < best.ks):
                best = fit
        if best is None:
            return nan
        fit = best
    else:
        fit = _fit_fixed(x, float(xmin), xmax)
        if fit.n < 2:
            return nan
    if n_bootstrap > 0 and fit.n >= 2:
        rng = np.random.default_rng(seed)
        tail = x[(x >= fit.xmin) & (x <= fit.xmax)]
        boot = [_power_law_mle(rng.choice(tail, tail.size), fit.xmin, fit.xmax)[0]
                for _ in range(n_bootstrap)]
        fit = dataclasses.replace(fit, bootstrap_stderr=float(np.std(boot, ddof=1)))
    return fit


def _fit_fixed(x_sorted: np.ndarray, xmin: float, xmax: float) -> PowerLawFit:
    tail = x_sorted[(x_sorted >= xmin) & (x_sorted <= xmax)]
    if tail.size < 2 or np.all(tail == tail[0]):
        return PowerLawFit(math.nan, math.nan, xmin, xmax, int(tail.size), math.nan)
    a, err = _power_law_mle(tail, xmin, xmax)
    cdf = _power_law_cdf(tail, a, xmin, xmax)
    n = tail.size
    ks = float(max(np.max(np.arange(1, n + 1) / n - cdf), np.max(cdf - np.arange(n) / n)))
    return PowerLawFit(a, err, xmin, xmax, int(n), ks)


@dataclasses.dataclass(frozen=True)
class LognormalFit:
    mu: float              # mean of ln x
    sigma: float           # std of ln x (MLE, ddof = 0)
    n: int
    ks: float              # KS distance data vs fitted log-normal
    ks_pvalue_naive: float  # scipy kstest p-value, ignores that mu, sigma were fitted
    ks_pvalue: float       # parametric-bootstrap (Lilliefors) p-value: accounts for the fit


def fit_lognormal(values, n_bootstrap: int = 500, seed: int = 0) -> LognormalFit:
    """scipy.stats.lognorm MLE with loc = 0, and how log-normal the data look.

    ks_pvalue is the fraction of synthetic log-normal samples (same n, refitted)
    whose KS distance exceeds the data's: the plain KS p-value is far too
    lenient when the parameters come from the same data.
    """
    x = np.asarray(values, float)
    x = x[np.isfinite(x) & (x > 0)]
    if x.size < MIN_FIT_EVENTS:
        return LognormalFit(math.nan, math.nan, int(x.size), math.nan, math.nan, math.nan)
    shape, _, scale = stats.lognorm.fit(x, floc=0)
    mu, sigma = math.log(scale), float(shape)
    res = stats.kstest(x, "lognorm", args=(sigma, 0, scale))
    p_boot = math.nan
    if n_bootstrap > 0 and sigma > 0:
        rng = np.random.default_rng(seed)
        exceed = 0
        for _ in range(n_bootstrap):
            y = np.log(rng.lognormal(mu, sigma, x.size))
            m, s = y.mean(), y.std()  # the loc = 0 lognorm MLE in closed form
            d = stats.kstest(y, "norm", args=(m, s)).statistic if s > 0 else 1.0
            exceed += d >= res.statistic
        p_boot = (exceed + 1) / (n_bootstrap + 1)
    return LognormalFit(mu, sigma, int(x.size), float(res.statistic), float(res.pvalue), p_boot)


# ---------------------------------------------------------------------------
# Slip partition, stationarity, regime
# ---------------------------------------------------------------------------

def slip_fractions(u_mean, L_s, D: float, L: float) -> dict:
    """Slip-weighted fractions: sum(u_mean L_s) over a subset / over all events.

    small: u_mean < D; spanning: L_s >= 0.9 L.  NaN when there are no events.
    """
    u = np.asarray(u_mean, float)
    Ls = np.asarray(L_s, float)
    w = u * Ls
    total = float(w.sum())
    if w.size == 0 or total <= 0:
        return {"small": math.nan, "spanning": math.nan}
    return {"small": float(w[u < D].sum() / total),
            "spanning": float(w[Ls >= SPANNING_FRACTION * L].sum() / total)}


def _cv(values) -> float:
    v = np.asarray(values, float)
    if v.size < 2 or v.mean() == 0:
        return math.nan
    return float(v.std(ddof=1) / abs(v.mean()))


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


def stationarity(catalog: dict, info: RunInfo, t_total: float | None = None, t_begin: float = 0.0) -> dict:
    """Events with t_start < 0.2 t_s vs t_start > 0.8 t_s (Fig. S8), with a
    two-sample KS test per observable.  t_s is the run duration (default: the
    time covered by the run file).  With t_begin > 0 (after a transient cut)
    the fifths are those of [t_begin, t_total] and earlier events are ignored."""
    t_total = info.duration if t_total is None else t_total
    t = np.asarray(catalog["t_start"], float)
    span = t_total - t_begin
    first = (t >= t_begin) & (t < t_begin + 0.2 * span)
    last = t > t_begin + 0.8 * span
    obs = normalised_observables(catalog, info)
    out = {"t_total": t_total, "t_begin": t_begin, "n_first": int(first.sum()), "n_last": int(last.sum())}
    for name, x in obs.items():
        if first.sum() >= 2 and last.sum() >= 2:
            r = stats.ks_2samp(x[first], x[last])
            out[name] = {"ks": float(r.statistic), "pvalue": float(r.pvalue)}
        else:
            out[name] = {"ks": math.nan, "pvalue": math.nan}
    return out


# ---------------------------------------------------------------------------
# Transient cut and stationarity of what is kept
# ---------------------------------------------------------------------------

STATIONARITY_BLOCKS = 40          # time blocks of the block-permutation test (as the transient cut's batches)
STATIONARITY_PERMUTATIONS = 1000  # permutations of the blocks; p resolution ~1e-3


def _ks_statistic(a: np.ndarray, b: np.ndarray) -> float:
    """Two-sample KS distance sup|F_a - F_b| (ties handled as scipy does)."""
    a, b = np.sort(a), np.sort(b)
    grid = np.concatenate([a, b])
    fa = np.searchsorted(a, grid, side="right") / a.size
    fb = np.searchsorted(b, grid, side="right") / b.size
    return float(np.max(np.abs(fa - fb)))


def block_permutation_stationarity(t_start, observables: dict, t_begin: float, t_end: float,
                                   n_blocks: int = STATIONARITY_BLOCKS,
                                   n_permutations: int = STATIONARITY_PERMUTATIONS, seed: int = 0) -> dict:
    """First-vs-last-fifth KS test that allows for serial dependence of events.

    The plain two-sample KS test (`stationarity`) assumes independent events.
    Slip events are not: they come in clusters (fore- and aftershock-like
    sequences) and a large event sets the stress for the next ones, so the
    plain test rejects stationary records far more often than its level says
    (tests/python/test_analysis_stationarity.py measures it).  Here the record
    [t_begin, t_end] is cut into n_blocks equal time blocks; the observed
    statistic is the KS distance between the first and the last fifth of the
    blocks, and its null distribution comes from assigning random fifths of
    blocks instead (blocks are exchangeable under stationarity when they are
    much longer than the correlation time; dependence inside a block is kept).
    p = (1 + #{D_perm >= D_obs}) / (1 + n_permutations).  The price is power:
    a regime change that fills many blocks also inflates the null spread.
    Returns {name: {"ks", "pvalue"}} per observable, plus n_blocks."""
    t = np.asarray(t_start, float)
    span = t_end - t_begin
    out = {"n_blocks": int(n_blocks), "n_permutations": int(n_permutations)}
    inside = (t >= t_begin) & (t <= t_end)
    block = np.minimum(((t[inside] - t_begin) / span * n_blocks).astype(int), n_blocks - 1)
    fifth = max(1, n_blocks // 5)
    rng = np.random.default_rng(seed)
    assignments = [rng.permutation(n_blocks) for _ in range(n_permutations)]
    for name, x in observables.items():
        x = np.asarray(x, float)[inside]
        first, last = block < fifth, block >= n_blocks - fifth
        if first.sum() < 2 or last.sum() < 2:
            out[name] = {"ks": math.nan, "pvalue": math.nan}
            continue
        d_obs = _ks_statistic(x[first], x[last])
        exceed = 0
        for perm in assignments:
            a, b = np.isin(block, perm[:fifth]), np.isin(block, perm[fifth:2 * fifth])
            if a.sum() >= 1 and b.sum() >= 1 and _ks_statistic(x[a], x[b]) >= d_obs - 1e-12:
                exceed += 1
        out[name] = {"ks": d_obs, "pvalue": (1 + exceed) / (1 + n_permutations)}
    return out



def mser_truncation(series, max_fraction: float = TRANSIENT_MAX_FRACTION) -> int:
    """Marginal Standard Error Rule (White 1997): the number d of leading
    entries to drop, 0 <= d <= max_fraction * n, that minimises
    sum((y - mean y)^2) / m^2 over the m finite entries y kept.  A leading
    transient inflates the sum of squares of what is kept, so the rule drops
    it; on stationary data the minimum is at (or near) d = 0, because the
    standard error grows as entries are dropped.  NaN entries are skipped."""
    x = np.asarray(series, float)
    n = x.size
    best, best_d = math.inf, 0
    for d in range(0, int(math.floor(max_fraction * n)) + 1):
        y = x[d:]
        y = y[np.isfinite(y)]
        if y.size < 2:
            break
        crit = float(np.sum((y - y.mean()) ** 2)) / y.size ** 2
        if crit < best * (1.0 - 1e-12):
            best, best_d = crit, d
    return best_d


def transient_cut(t_start, u_over_D, t_end: float, t_begin: float = 0.0,
                  n_batches: int = TRANSIENT_BATCHES, max_fraction: float = TRANSIENT_MAX_FRACTION) -> dict:
    """The automatic transient cut of a catalog (docs/analysis.md).

    [t_begin, t_end] is split into n_batches equal batches.  Two batch series
    are formed: the number of events (event rate) and the mean of
    log10(u_mean/D) over the events of the batch (mean event slip; NaN for an
    empty batch).  `mser_truncation` is applied to each, with at most
    max_fraction of the batches dropped; the cut is the start of the first
    kept batch of the later of the two.  Returns t_cut [s] and diagnostics."""
    t = np.asarray(t_start, float)
    u = np.asarray(u_over_D, float)
    edges = np.linspace(t_begin, t_end, n_batches + 1)
    idx = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, n_batches - 1)
    inside = (t >= t_begin) & (t <= t_end)
    counts = np.bincount(idx[inside], minlength=n_batches).astype(float)
    logu = np.full(n_batches, math.nan)
    ok = inside & np.isfinite(u) & (u > 0)
    if ok.any():
        sums = np.bincount(idx[ok], weights=np.log10(u[ok]), minlength=n_batches)
        n_ok = np.bincount(idx[ok], minlength=n_batches)
        logu = np.where(n_ok > 0, sums / np.maximum(n_ok, 1), math.nan)
    d_rate = mser_truncation(counts, max_fraction) if counts.sum() > 0 else 0
    d_slip = mser_truncation(logu, max_fraction) if np.isfinite(logu).sum() >= 2 else 0
    d = max(d_rate, d_slip)
    return {"t_cut": float(edges[d]), "batches_dropped": int(d), "batches_dropped_rate": int(d_rate),
            "batches_dropped_slip": int(d_slip), "n_batches": int(n_batches),
            "batch_duration": float((t_end - t_begin) / n_batches), "t_begin": float(t_begin),
            "t_end": float(t_end), "rule": f"MSER on {n_batches} batches (event count, mean log10 u/D), "
                                           f"cut <= {max_fraction:g} of the run"}


def subset_catalog(catalog: dict, mask) -> dict:
    """The events of `catalog` selected by a boolean mask (attrs kept)."""
    m = np.asarray(mask, bool)
    out = {k: np.asarray(v)[m] for k, v in catalog.items() if k != "attrs"}
    out["attrs"] = dict(catalog.get("attrs", {}))
    return out


def stationary_part(catalog: dict, info: RunInfo, t_total: float | None = None) -> dict:
    """Transient cut, then the first-vs-last-fifth KS tests on what is kept.

    Returns {"cut": transient_cut(...), "catalog": the kept events (t_start >=
    t_cut), "stationarity": stationarity(...) over [t_cut, t_total],
    "stationary": all three KS p-values >= STATIONARITY_LEVEL, and the same with
    the block-permutation test that allows for serially dependent events:
    "stationarity_blocks", "stationary_blocks"}."""
    t_total = info.duration if t_total is None else t_total
    obs = normalised_observables(catalog, info)
    cut = transient_cut(catalog["t_start"], obs["u"], t_total)
    kept = subset_catalog(catalog, np.asarray(catalog["t_start"], float) >= cut["t_cut"])
    st = stationarity(kept, info, t_total=t_total, t_begin=cut["t_cut"])
    ps = [st[k]["pvalue"] for k in ("u", "T", "M0")]
    blocks = block_permutation_stationarity(kept["t_start"], normalised_observables(kept, info),
                                            cut["t_cut"], t_total)
    pb = [blocks[k]["pvalue"] for k in ("u", "T", "M0")]
    return {"cut": cut, "catalog": kept, "stationarity": st, "stationarity_blocks": blocks,
            "stationary": bool(all(np.isfinite(p) and p >= STATIONARITY_LEVEL for p in ps)),
            "stationary_blocks": bool(all(np.isfinite(p) and p >= STATIONARITY_LEVEL for p in pb))}


# ---------------------------------------------------------------------------
# Periodic travelling pulse from the space-time field
# ---------------------------------------------------------------------------

def _best_shift(a: np.ndarray, b: np.ndarray) -> tuple[int, float, float]:
    """Circular shift s (nodes, signed, |s| <= N/2) that best maps profile a
    onto b (b[n] ~ a[n - s]), the normalised correlation at that shift, and
    the shift refined to a fraction of a node."""
    a = a - a.mean()
    b = b - b.mean()
    na, nb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
    if na == 0 or nb == 0:
        return 0, math.nan, 0.0
    c = np.fft.irfft(np.conj(np.fft.rfft(a)) * np.fft.rfft(b), n=a.size)
    s = int(np.argmax(c))
    r = float(c[s] / (na * nb))
    # Sub-node position of the peak (parabola through the three samples), for speeds.
    cm, cp = c[s - 1], c[(s + 1) % a.size]
    den = cm - 2 * c[s] + cp
    frac = float(0.5 * (cm - cp) / den) if den < 0 else 0.0
    if s > a.size // 2:
        s -= a.size
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

    def pairs(indices, lag):
        res = [(i, j) + _best_shift(z[i], z[j]) for i, j in zip(indices[:-lag], indices[lag:])]
        return res

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


def read_spacetime(path, max_rows: int | None = None):
    """(time, x, slip_rate) of /snapshots; None without enough snapshots.
    max_rows > 0 strides the rows evenly."""
    with open_h5(path) as f:
        if "snapshots" not in f or f["snapshots/time"].shape[0] < 2:
            return None
        t = read_times(f, "snapshots/time")
        step = 1 if not max_rows else _stride(t.size, max_rows)
        return t[::step], f["snapshots/x"][:], f["snapshots/slip_rate"][::step]


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


# ---------------------------------------------------------------------------
# Catalog statistics
# ---------------------------------------------------------------------------

def catalog_statistics(catalog: dict, info: RunInfo, seed: int = 0, n_bootstrap: int = 200) -> dict:
    """Fits and fractions of one catalog (no figures, no detection)."""
    obs = normalised_observables(catalog, info)
    small = obs["u"] < 1.0
    large = ~small
    res = {"n_events": int(obs["u"].size), "n_events_small": int(small.sum()),
           "n_events_large": int(large.sum())}
    # u: truncated at the split u = D (the power law describes u < D only).
    fits = {}
    for name in ("u", "T", "M0"):
        xs = obs[name][small]
        xs = xs[np.isfinite(xs) & (xs > 0)]
        if xs.size >= MIN_FIT_EVENTS:
            xmax = 1.0 if name == "u" else float(xs.max())
            fit = fit_power_law(xs, xmax=xmax, min_tail=max(MIN_FIT_EVENTS, min(50, xs.size // 4)),
                                n_bootstrap=n_bootstrap, seed=seed)
        else:
            fit = PowerLawFit(math.nan, math.nan, math.nan, math.nan, int(xs.size), math.nan)
        fits[name] = fit
        res[f"small_exponent_{name}"] = fit.exponent
        res[f"small_exponent_{name}_err"] = fit.stderr
        res[f"small_exponent_{name}_bootstrap_err"] = fit.bootstrap_stderr
        res[f"small_exponent_{name}_xmin"] = fit.xmin
        res[f"small_exponent_{name}_n"] = fit.n
        res[f"small_exponent_{name}_ks"] = fit.ks
        sweep = (exponent_xmin_sweep(xs, fit.xmin, xmax, min_tail=max(MIN_FIT_EVENTS, min(50, xs.size // 4)))
                 if xs.size >= MIN_FIT_EVENTS else [])
        res[f"small_exponent_{name}_xmin_sweep"] = [
            {"xmin_factor": f.xmin / fit.xmin, "xmin": f.xmin, "exponent": f.exponent, "stderr": f.stderr, "n": f.n}
            for f in sweep]
    logfits = {name: fit_lognormal(obs[name][large], seed=seed) for name in ("u", "T", "M0")}
    for name, lf in logfits.items():
        res[f"lognormal_{name}"] = dataclasses.asdict(lf)
    # The headline log-normal is the one of the paper's Fig. 1d inset: T of large events.
    res["lognormal_mu"] = logfits["T"].mu
    res["lognormal_sigma"] = logfits["T"].sigma
    res["lognormal_ks"] = logfits["T"].ks
    res["lognormal_ks_pvalue"] = logfits["T"].ks_pvalue
    res["lognormal_ks_pvalue_naive"] = logfits["T"].ks_pvalue_naive
    res["cautions"] = [
        f"the power law of {name} is fitted to only {fit.n} events (fewer than {POWER_LAW_CAUTION_EVENTS}): "
        f"its exponent {fit.exponent:.3g} +- {fit.stderr:.2g} is indicative at best, and so few events cannot "
        "tell a power law from other heavy-tailed shapes; run longer for more events"
        for name, fit in fits.items() if math.isfinite(fit.exponent) and fit.n < POWER_LAW_CAUTION_EVENTS]
    fr = slip_fractions(catalog["u_mean"], catalog["L_s"], info.D, info.L)
    res["slip_fraction_small"] = fr["small"]
    res["slip_fraction_spanning"] = fr["spanning"]
    res["_fits"] = fits
    res["_lognormal_fits"] = logfits
    return res


def _public(d: dict) -> dict:
    return {k: v for k, v in d.items() if not k.startswith("_")}


def summarize_run(path: str | os.PathLike, alpha: float = DEFAULT_ALPHA) -> dict:
    """Headline numbers of one run (used by the parameter scan).

    Keys: n_events, n_events_small, n_events_large, small_exponent_u,
    small_exponent_u_err, lognormal_mu, lognormal_sigma, lognormal_ks_pvalue
    (log-normal of T v0/D of the large events), slip_fraction_small,
    slip_fraction_spanning, periodic_pulse (bool; `periodic_pulse_of_run`),
    plus diagnostics.  Fits
    with too few events are NaN.  Runs detection through the CLI if needed.
    """
    info = read_run_info(path)
    # Scans call this on run files they wrote themselves: keep the catalog there.
    catalog = catalog_for(path, alpha, write_into_run=True)
    res = _public(catalog_statistics(catalog, info, n_bootstrap=0))
    res.update(periodic_pulse_of_run(path, catalog, info))
    res["alpha"] = float(alpha)
    return res


# ---------------------------------------------------------------------------
# numpy grouping of nodal slips (for the event-coloured map only)
# ---------------------------------------------------------------------------

@dataclasses.dataclass
class NodalSlipGroups:
    label: np.ndarray        # [n_levels, N] int64: detected-event index of each NS, -1 = no NS
    n_detected: int          # events before any exclusion or filter
    kept: np.ndarray         # [n_detected] bool: passes exclusion and size filters (C++ rules)
    waiting_time_threshold: float


def group_nodal_slips(crossing_time: np.ndarray, delta_th: float, v0: float, alpha: float = DEFAULT_ALPHA,
                      min_extent_dx: float = 2.0, min_mean_slip_dth: float = 2.0,
                      exclude_first_last: bool = True) -> NodalSlipGroups:
    """Groups the nodal slips of crossing_time [n_levels, N] into events by the
    global waiting time (> alpha delta_th / (v0 N) starts a new event), with
    the conventions of docs/events.md: a column ends at its first NaN, ties
    are ordered by node then level, first and last events are excluded before
    the size filters.  For plotting only; the catalog comes from the C++ code.
    """
    ct = np.asarray(crossing_time, float)
    n_levels, n = ct.shape
    finite = np.isfinite(ct)
    valid = np.cumprod(finite, axis=0).astype(bool)  # NaN tail: ignore after the first NaN
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


# ---------------------------------------------------------------------------
# Figures
# ---------------------------------------------------------------------------

def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(fig, out_dir: Path, name: str, pdf: bool) -> list[str]:
    paths = [out_dir / f"{name}.png"]
    fig.savefig(paths[0], dpi=130, bbox_inches="tight")
    if pdf:
        paths.append(out_dir / f"{name}.pdf")
        fig.savefig(paths[1], bbox_inches="tight")
    _plt().close(fig)
    return [str(p) for p in paths]


def _stride(n: int, target: int) -> int:
    return max(1, int(math.ceil(n / target)))


def plot_space_time(path, info: RunInfo, out_dir: Path, pdf: bool = False) -> list[str]:
    """log10(|v|/v0) in the x/L -- t c_s/L plane from /snapshots (Figs. 2a, S3a):
    the figure of `slipstrip plot` (plots.spacetime_axes, same colour map),
    with the colour scale starting at most 3 decades below v0."""
    from . import plots
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6, 5))
    mesh = plots.spacetime_axes(path, ax, floor=-3.0)
    fig.colorbar(mesh, ax=ax, label=r"$\log_{10}(v/v_0)$")
    return _save(fig, out_dir, "space_time", pdf)


def _read_crossing_time(path):
    with open_h5(path) as f:
        g = f["slip_sampling"]
        ct = g["crossing_time"][:]
        x = g["x"][:] if "x" in g else np.arange(ct.shape[1]) * float(g.attrs["dx"])
    return ct, x


def slip_rate_space_slip(crossing_time: np.ndarray, delta_th: float) -> np.ndarray:
    """v(x, delta) = delta_th / Delta t, Delta t = crossing_time[j] - crossing_time[j-1]
    (j = 0: from t = 0).  NaN where the level was not reached; inf for Delta t = 0."""
    ct = np.asarray(crossing_time, float)
    prev = np.vstack([np.zeros((1, ct.shape[1])), ct[:-1]])
    with np.errstate(divide="ignore", invalid="ignore"):
        return delta_th / (ct - prev)


def plot_space_slip(ct, x, info: RunInfo, out_dir: Path, pdf: bool = False, max_rows: int = 3000) -> list[str]:
    """v(x, delta)/v0 in the x/L -- delta/D plane (Figs. 1b, S3b)."""
    plt = _plt()
    v = slip_rate_space_slip(ct, info.delta_th)
    step = _stride(v.shape[0], max_rows)
    v = v[::step]
    delta = (np.arange(0, ct.shape[0], step) + 1) * info.delta_th / info.D
    fig, ax = plt.subplots(figsize=(6, 5))
    z = np.log10(np.clip(v / info.v0, 1e-4, 1e4))
    im = ax.pcolormesh(x / info.L, delta, np.ma.masked_invalid(z), shading="auto", cmap="viridis_r",
                       rasterized=True)
    fig.colorbar(im, ax=ax, label=r"$\log_{10}(v(x,\delta)/v_0)$")
    ax.set_xlabel("$x/L$")
    ax.set_ylabel(r"$\delta/D$")
    return _save(fig, out_dir, "space_slip", pdf)


def plot_event_map(groups: NodalSlipGroups, x, info: RunInfo, out_dir: Path, pdf: bool = False,
                   max_rows: int = 3000) -> list[str]:
    """Each nodal slip coloured by its (kept) event; grey: NS of removed events (Fig. S4b)."""
    plt = _plt()
    from matplotlib.colors import ListedColormap
    step = _stride(groups.label.shape[0], max_rows)
    lab = groups.label[::step]
    kept_index = np.cumsum(groups.kept) - 1  # colour index among kept events
    colour = np.full(lab.shape, np.nan)
    has = lab >= 0
    kept_ns = has.copy()
    kept_ns[has] = groups.kept[lab[has]]
    colour[kept_ns] = kept_index[lab[kept_ns]] % 20
    grey = has & ~kept_ns
    delta = (np.arange(0, groups.label.shape[0], step) + 1) * info.delta_th / info.D
    fig, ax = plt.subplots(figsize=(6, 5))
    ax.pcolormesh(x / info.L, delta, np.ma.masked_where(~grey, grey.astype(float)), shading="auto",
                  cmap=ListedColormap(["0.8"]), rasterized=True)
    ax.pcolormesh(x / info.L, delta, np.ma.masked_invalid(colour), shading="auto", cmap="tab20",
                  vmin=0, vmax=20, rasterized=True)
    ax.set_xlabel("$x/L$")
    ax.set_ylabel(r"$\delta/D$")
    ax.set_title(f"{int(groups.kept.sum())} events (alpha grouping re-done in numpy; grey: removed)",
                 fontsize=8)
    return _save(fig, out_dir, "event_map", pdf)


def _legend(ax) -> None:
    """A legend only for axes that show a labelled curve (matplotlib warns on an empty one)."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)


def _pdf_line(ax, x, label, **kw):
    c, p, _ = log_binned_pdf(x)
    m = p > 0
    if m.any():
        ax.loglog(c[m], p[m], label=label, **kw)


def plot_pdfs(catalog: dict, info: RunInfo, stats_: dict, out_dir: Path, pdf: bool = False) -> list[str]:
    """p(u/D), p(T v0/D), p(M0/(mu D L)) with the power-law and log-normal fits (Fig. 1c-e)."""
    plt = _plt()
    obs = normalised_observables(catalog, info)
    large = obs["u"] >= 1.0
    labels = {"u": r"$\bar u/D$", "T": r"$T v_0/D$", "M0": r"$M_0/(\mu D L)$"}
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    n_all = max(1, np.sum(np.isfinite(obs["u"]) & (obs["u"] > 0)))
    for ax, name in zip(axes, ("u", "T", "M0")):
        _pdf_line(ax, obs[name], "all events", marker="o", ms=3, color="C1")
        c, p, _ = log_binned_pdf(obs[name][large])
        m = p > 0
        if m.any():  # large events, weighted by their share so that both curves are on one scale
            ax.loglog(c[m], p[m] * large.sum() / n_all, "--", color="green", label=r"$\bar u \geq D$")
        fit = stats_["_fits"][name]
        if np.isfinite(fit.exponent):
            xs = np.logspace(math.log10(fit.xmin), math.log10(fit.xmax), 50)
            small_share = fit.n / n_all
            norm = math.exp(-_log_norm(fit.exponent, fit.xmin, fit.xmax))
            ax.loglog(xs, small_share * norm * xs ** -fit.exponent, "k--",
                      label=f"power law {fit.exponent:.2f}$\\pm${fit.stderr:.2f}")
        lf = stats_["_lognormal_fits"][name]
        if np.isfinite(lf.mu):
            xs = np.logspace(lf.mu / math.log(10) - 3 * lf.sigma / math.log(10),
                             lf.mu / math.log(10) + 3 * lf.sigma / math.log(10), 80)
            ax.loglog(xs, stats.lognorm.pdf(xs, lf.sigma, 0, math.exp(lf.mu)) * large.sum() / n_all,
                      "-", color="gold", label=f"log-normal ($\\sigma$={lf.sigma:.2f})")
        if name == "u":
            ax.axvline(1.0, color="k", lw=1)
        ax.set_xlabel(labels[name])
        ax.set_ylabel("p")
        _legend(ax)
    return _save(fig, out_dir, "pdfs", pdf)


def plot_pdf_comparison(sets: dict, info: RunInfo, out_dir: Path, name: str, pdf: bool = False) -> list[str]:
    """PDFs of several catalogs (stationarity, Fig. S8; thresholds, Fig. S9)."""
    plt = _plt()
    labels = {"u": r"$\bar u/D$", "T": r"$T v_0/D$", "M0": r"$M_0/(\mu D L)$"}
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    for label, catalog in sets.items():
        obs = normalised_observables(catalog, info)
        for ax, key in zip(axes, ("u", "T", "M0")):
            _pdf_line(ax, obs[key], f"{label} (n={obs[key].size})")
    for ax, key in zip(axes, ("u", "T", "M0")):
        ax.set_xlabel(labels[key])
        ax.set_ylabel("p")
        _legend(ax)
    return _save(fig, out_dir, name, pdf)


def plot_event_fields(path, catalog: dict, index: int, info: RunInfo, out_dir: Path, pdf: bool = False):
    """phi, tau/sigma0 and slip/D before and after event `index` (Fig. 2b-d):
    the last snapshot at or before t_start and the first at or after t_start + T."""
    plt = _plt()
    t0 = float(catalog["t_start"][index])
    t1 = t0 + float(catalog["T"][index])
    with open_h5(path) as f:
        ts = read_times(f, "snapshots/time")
        before = np.nonzero(ts <= t0)[0]
        after = np.nonzero(ts >= t1)[0]
        if before.size == 0 or after.size == 0:
            return [], None
        ib, ia = int(before[-1]), int(after[0])
        x = f["snapshots/x"][:]
        fields = {k: (f["snapshots"][k][ib], f["snapshots"][k][ia]) for k in ("slip", "state", "shear_stress")}
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    xs = x / info.L
    axes[0].plot(xs, (fields["slip"][1] - fields["slip"][0]) / info.D, "C0")
    axes[0].set_ylabel(r"$(\delta-\delta_{\rm before})/D$")
    for k, (ax, name, scale, lab) in enumerate(((axes[1], "state", 1.0, r"$\phi$ [s]"),
                                                 (axes[2], "shear_stress", info.sigma0, r"$\tau/\sigma_0$"))):
        ax.plot(xs, fields[name][0] / scale, "k", lw=1, label=f"before (t={ts[ib]:.4g} s)")
        ax.plot(xs, fields[name][1] / scale, "g", lw=1, label=f"after (t={ts[ia]:.4g} s)")
        ax.set_ylabel(lab)
        _legend(ax)
    axes[1].set_yscale("log")
    axes[2].set_xlabel("$x/L$")
    axes[0].set_title(f"event {index}: t_start={t0:.4g} s, T={t1 - t0:.3g} s, "
                      f"u_mean/D={catalog['u_mean'][index] / info.D:.3g}, L_s/L={catalog['L_s'][index] / info.L:.3g}",
                      fontsize=8)
    return _save(fig, out_dir, f"event_{index}_fields", pdf), (float(ts[ib]), float(ts[ia]))


# ---------------------------------------------------------------------------
# Full analysis and CLI
# ---------------------------------------------------------------------------

def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, (np.floating, float)):
        return None if not math.isfinite(float(obj)) else float(obj)
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj


def analyze(path, out_dir, pdf: bool = False, alpha: float = DEFAULT_ALPHA, event: int | None = None,
            sensitivity_alphas=SENSITIVITY_ALPHAS, seed: int = 0, write_events: bool = False) -> dict:
    """Everything: statistics, stationarity, threshold sensitivity, figures, summary.json."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    info = read_run_info(path)
    catalog = catalog_for(path, alpha, workdir=out_dir, write_into_run=write_events)
    if len(catalog["t_start"]) == 0:
        raise EmptyCatalog(f"{path}: {empty_catalog_reason(catalog['attrs'], info, alpha)}")
    st = catalog_statistics(catalog, info, seed=seed)
    summary = {"run": str(path), "alpha": float(alpha), "normalisation": {
        "u": "u_mean/D", "T": "T*v0/D", "M0": "M0/(mu*D*L)"}, "scales": dataclasses.asdict(info)}
    summary.update(_public(st))
    summary["catalog_counts"] = {k: catalog["attrs"].get(k) for k in (
        "n_nodal_slips", "n_events_detected", "n_events_excluded_first_last", "n_events_below_thresholds",
        "n_events")}
    with open_h5(path) as f:
        has_snap = "snapshots" in f and f["snapshots/time"].shape[0] > 0
        has_ss = "slip_sampling" in f
    summary.update(periodic_pulse_of_run(path, catalog, info))
    summary["stationarity"] = stationarity(catalog, info)
    kept = stationary_part(catalog, info)
    summary["transient_cut"] = kept["cut"]
    summary["stationarity_after_cut"] = dict(kept["stationarity"], stationary=kept["stationary"])

    sens = {}
    catalogs_by_alpha = {}
    for a in sensitivity_alphas:
        cat_a = catalog if float(a) == float(alpha) else catalog_for(path, a, workdir=out_dir)
        catalogs_by_alpha[f"alpha={a:g}"] = cat_a
        st_a = catalog_statistics(cat_a, info, n_bootstrap=0)
        sens[f"{a:g}"] = {k: st_a[k] for k in ("n_events", "small_exponent_u", "small_exponent_u_err",
                                                "small_exponent_T", "small_exponent_M0")}
    summary["threshold_sensitivity"] = sens

    figures = []
    if has_snap:
        figures += plot_space_time(path, info, out_dir, pdf)
    if has_ss:
        ct, x = _read_crossing_time(path)
        figures += plot_space_slip(ct, x, info, out_dir, pdf)
        groups = group_nodal_slips(ct, info.delta_th, info.v0, alpha,
                                   catalog["attrs"].get("min_extent_dx", 2.0),
                                   catalog["attrs"].get("min_mean_slip_dth", 2.0),
                                   bool(catalog["attrs"].get("exclude_first_last", 1)))
        figures += plot_event_map(groups, x, info, out_dir, pdf)
        summary["event_map"] = {"n_detected_numpy": groups.n_detected, "n_kept_numpy": int(groups.kept.sum()),
                                "n_detected_cpp": catalog["attrs"].get("n_events_detected")}
        del ct, groups
    figures += plot_pdfs(catalog, info, st, out_dir, pdf)
    t = np.asarray(catalog["t_start"], float)
    T_s = info.duration
    subset = lambda m: {k: np.asarray(v)[m] for k, v in catalog.items() if k != "attrs"}
    figures += plot_pdf_comparison({"all": catalog, "first fifth": subset(t < 0.2 * T_s),
                                    "last fifth": subset(t > 0.8 * T_s)}, info, out_dir, "stationarity", pdf)
    figures += plot_pdf_comparison(catalogs_by_alpha, info, out_dir, "threshold_sensitivity", pdf)
    n_ev = len(catalog["t_start"])
    if n_ev and has_snap:
        index = int(np.argmax(catalog["M0"])) if event is None else int(event)
        if not -n_ev <= index < n_ev:
            raise ValueError(f"--event {event}: allowed 0..{n_ev - 1} ({n_ev} events)")
        index %= n_ev
        paths, times = plot_event_fields(path, catalog, index, info, out_dir, pdf)
        figures += paths
        summary["event_fields"] = {"event": index, "snapshot_times": times}
    summary["figures"] = figures
    summary = _jsonable(summary)
    with open(out_dir / "summary.json", "w") as fh:
        json.dump(summary, fh, indent=2)
    return summary


class EmptyCatalog(ValueError):
    """The run has no kept events: there is nothing to analyse (exit code 1 of `analyze`)."""


def empty_catalog_reason(attrs: dict, info: RunInfo, alpha: float) -> str:
    """Why a catalog holds no event, and what to change, from its counts
    (docs/events.md: n_nodal_slips, n_events_detected, n_events_excluded_first_last,
    n_events_below_thresholds): the message of `slipstrip events`
    (events::empty_catalog_reason), with the run's duration."""
    from . import _slipstrip
    counts = dict(attrs)
    counts.setdefault("alpha", float(alpha))
    counts.setdefault("delta_th", info.delta_th)
    counts.setdefault("v0", info.v0)
    return _slipstrip.empty_catalog_reason(counts, run_duration=info.duration) + "; nothing to analyse"


def format_summary(s: dict) -> str:
    def f(v, fmt=".3g"):
        return "nan" if v is None else format(v, fmt)
    lines = [
        f"run: {s['run']}  (alpha = {s['alpha']:g})",
        f"events: {s['n_events']} ({s['n_events_small']} small u<D, {s['n_events_large']} large)",
        f"small-event exponent p(u/D) ~ x^-a: a = {f(s['small_exponent_u'])} +- {f(s['small_exponent_u_err'])}"
        f" (bootstrap {f(s.get('small_exponent_u_bootstrap_err'))}, xmin = {f(s['small_exponent_u_xmin'])},"
        f" n = {s['small_exponent_u_n']})",
        f"  T v0/D: a = {f(s['small_exponent_T'])} +- {f(s['small_exponent_T_err'])};"
        f"  M0/(mu D L): a = {f(s['small_exponent_M0'])} +- {f(s['small_exponent_M0_err'])}",
        f"large events, log-normal of T v0/D: mu = {f(s['lognormal_mu'])}, sigma = {f(s['lognormal_sigma'])},"
        f" KS = {f(s['lognormal_ks'])}, p = {f(s['lognormal_ks_pvalue'])} (naive {f(s['lognormal_ks_pvalue_naive'])})",
        f"slip fraction: small events {f(s['slip_fraction_small'])}, system-spanning {f(s['slip_fraction_spanning'])}",
        f"periodic pulse: {s['periodic_pulse']}",
        "stationarity (first vs last fifth, KS p): " + ", ".join(
            f"{k} {f(s['stationarity'][k]['pvalue'])}" for k in ("u", "T", "M0")),
        "threshold sensitivity: " + "; ".join(
            f"alpha={a}: n={v['n_events']}, a_u={f(v['small_exponent_u'])}"
            for a, v in s["threshold_sensitivity"].items()),
        f"figures: {len(s['figures'])} files",
    ]
    lines += [f"caution: {c}" for c in s.get("cautions", [])]
    return "\n".join(lines)


# The figures analyze() writes under fixed names (besides event_<i>_fields, whose
# index is known only after the detection).
FIGURE_NAMES = ("space_time", "space_slip", "event_map", "pdfs", "stationarity", "threshold_sensitivity")


def analysis_outputs(out_dir, alpha: float = DEFAULT_ALPHA, pdf: bool = False,
                     sensitivity_alphas=SENSITIVITY_ALPHAS) -> dict[str, Path]:
    """The files analyze() writes into out_dir under fixed names, as
    {"--out-dir NAME": path}, for the output-path check (slipstrip.paths)."""
    out_dir = Path(out_dir)
    names = ["summary.json"] + [f"{n}.png" for n in FIGURE_NAMES] + ([f"{n}.pdf" for n in FIGURE_NAMES] if pdf else [])
    names += [f"events_alpha{a:g}.h5" for a in dict.fromkeys([alpha, *sensitivity_alphas])]
    return {f"--out-dir {name}": out_dir / name for name in names}


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="slipstrip analyze",
                                     description="Slip-event statistics and figures of one run file")
    parser.add_argument("run", help="run file (HDF5, docs/output.md)")
    parser.add_argument("--out-dir", default=None, help="output directory (default: <run>_analysis)")
    parser.add_argument("--pdf", action="store_true", help="also write PDF figures")
    parser.add_argument("--alpha", type=float, default=DEFAULT_ALPHA, help="waiting-time threshold factor")
    parser.add_argument("--event", type=int, default=None,
                        help="event index for the before/after fields figure (default: largest M0)")
    parser.add_argument("--write-events", action="store_true",
                        help="add the catalog as /events to the run file when it has none "
                             "(default: the run file is only read; the catalog goes to --out-dir)")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace the files of an earlier analysis in --out-dir")
    args = parser.parse_args(list(argv[1:] if argv and argv[0] == "analyze" else argv))
    if not args.alpha > 0:
        print(f"analyze: --alpha {args.alpha}: must be > 0", file=sys.stderr)
        return 2
    if not (Path(args.run).is_file() and h5py.is_hdf5(args.run)):
        print(f"analyze: {unreadable_reason(args.run)}", file=sys.stderr)
        return 2
    out_dir = args.out_dir or str(Path(args.run).with_suffix("")) + "_analysis"
    try:
        check_outputs(analysis_outputs(out_dir, args.alpha, args.pdf), directories={"--out-dir": out_dir},
                      inputs=[args.run], overwrite=args.overwrite)
    except OutputPathError as err:
        print(f"analyze: {err}", file=sys.stderr)
        return 2
    try:
        summary = analyze(args.run, out_dir, pdf=args.pdf, alpha=args.alpha, event=args.event,
                          write_events=args.write_events)
    except EmptyCatalog as err:  # a valid run with nothing to analyse: no figures, exit 1
        print(f"analyze: {err}", file=sys.stderr)
        return 1
    except (FileNotFoundError, RuntimeError, KeyError, ValueError, OSError, TypeError, IndexError) as err:
        # A damaged or foreign run file: one line naming the file, never a traceback.
        print("analyze: " + one_line(f"{args.run}: {str(err) or type(err).__name__}"), file=sys.stderr)
        return 2
    print(format_summary(summary))
    print(f"summary: {Path(out_dir) / 'summary.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
