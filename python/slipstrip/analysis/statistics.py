"""Statistics of an event catalog: normalised observables, log-binned PDFs,
power-law and log-normal fits, slip fractions, the transient cut and the
stationarity tests (docs/analysis.md).  Exponents are reported positive:
p(x) ~ x^(-exponent)."""
from __future__ import annotations

import dataclasses
import math

import numpy as np

# scipy is imported inside the functions that fit or test: it is most of the
# start-up time of every `python3 -m slipstrip` command (analyze, transition,
# report) and the commands' error paths (a missing or foreign file) need none of it.

from .reading import RunInfo


SPANNING_FRACTION = 0.9  # L_s >= 0.9 L counts as system-spanning
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


def normalised_observables(catalog: dict, info: RunInfo) -> dict:
    """u_mean/D, T v0/D, M0/(mu D L) (the paper's Fig. S8 normalisations; on
    a line M0 = mu L_s u_mean is a moment per unit width [N/m]).  On a 2D
    interface M0 = mu A u_mean is a moment [N m], normalised by mu D L W,
    and the area A/(L W) is a fourth observable."""
    obs = {
        "u": np.asarray(catalog["u_mean"], float) / info.D,
        "T": np.asarray(catalog["T"], float) * info.v0 / info.D,
        "M0": np.asarray(catalog["M0"], float) / (info.mu * info.D * info.L * (info.W if info.interface_2d else 1.0)),
    }
    if info.interface_2d:
        obs["A"] = np.asarray(catalog["A"], float) / (info.L * info.W)
    return obs


def observable_labels(info: RunInfo) -> dict:
    """Axis labels of the normalised observables (matplotlib mathtext)."""
    if info.interface_2d:
        return {"u": r"$\bar u/D$", "T": r"$T v_0/D$", "M0": r"$M_0/(\mu D L W)$", "A": r"$A/(L W)$"}
    return {"u": r"$\bar u/D$", "T": r"$T v_0/D$", "M0": r"$M_0/(\mu D L)$"}


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

    from scipy import optimize

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
    from scipy import stats

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


def slip_fractions(u_mean, L_s, D: float, L: float) -> dict:
    """Slip-weighted fractions: sum(u_mean L_s) over a subset / over all events.

    small: u_mean < D; spanning: L_s >= 0.9 L.  NaN when there are no events.
    On a 2D interface L_s is the area A of each event and L the interface's L W.
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
    from scipy import stats

    obs = normalised_observables(catalog, info)
    out = {"t_total": t_total, "t_begin": t_begin, "n_first": int(first.sum()), "n_last": int(last.sum())}
    for name, x in obs.items():
        if first.sum() >= 2 and last.sum() >= 2:
            r = stats.ks_2samp(x[first], x[last])
            out[name] = {"ks": float(r.statistic), "pvalue": float(r.pvalue)}
        else:
            out[name] = {"ks": math.nan, "pvalue": math.nan}
    return out


STATIONARITY_BLOCKS = 40          # time blocks of the block-permutation test (as the transient cut's batches)
STATIONARITY_PERMUTATIONS = 1000  # permutations of the blocks; p resolution ~1e-3


def _ks_statistic(a: np.ndarray, b: np.ndarray) -> float:
    """Two-sample KS distance sup|F_a - F_b| (ties handled as scipy does)."""
    return _ks_sorted(np.sort(a), np.sort(b))


def _ks_sorted(a: np.ndarray, b: np.ndarray) -> float:
    """_ks_statistic of two samples already sorted."""
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
    tested = {}  # name -> (values sorted, their blocks, observed distance, exceedances)
    for name, x in observables.items():
        x = np.asarray(x, float)[inside]
        first, last = block < fifth, block >= n_blocks - fifth
        if first.sum() < 2 or last.sum() < 2:
            out[name] = {"ks": math.nan, "pvalue": math.nan}
            continue
        # Sorted once: a mask of the sorted values selects them already sorted
        # (the same numbers _ks_statistic would sort).
        order = np.argsort(x, kind="stable")
        tested[name] = [x[order], block[order], _ks_statistic(x[first], x[last]), 0]
    # Each permutation's two sets of blocks as a lookup by block index, shared
    # by the observables (np.isin per permutation and observable was most of
    # the test's time).
    in_a, in_b = np.zeros(n_blocks, bool), np.zeros(n_blocks, bool)
    for perm in assignments:
        in_a[:] = False
        in_b[:] = False
        in_a[perm[:fifth]] = True
        in_b[perm[fifth:2 * fifth]] = True
        for entry in tested.values():
            xs, bs, d_obs = entry[0], entry[1], entry[2]
            a, b = in_a[bs], in_b[bs]
            if a.any() and b.any() and _ks_sorted(xs[a], xs[b]) >= d_obs - 1e-12:
                entry[3] += 1
    for name, (_, _, d_obs, exceed) in tested.items():
        out[name] = {"ks": d_obs, "pvalue": (1 + exceed) / (1 + n_permutations)}
    return {"n_blocks": out["n_blocks"], "n_permutations": out["n_permutations"],
            **{name: out[name] for name in observables}}


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


def catalog_statistics(catalog: dict, info: RunInfo, seed: int = 0, n_bootstrap: int = 200) -> dict:
    """Fits and fractions of one catalog (no figures, no detection)."""
    obs = normalised_observables(catalog, info)
    small = obs["u"] < 1.0
    large = ~small
    res = {"n_events": int(obs["u"].size), "n_events_small": int(small.sum()),
           "n_events_large": int(large.sum())}
    # u: truncated at the split u = D (the power law describes u < D only).
    fits = {}
    for name in obs:
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
    logfits = {name: fit_lognormal(obs[name][large], seed=seed) for name in obs}
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
    # Slip weighted by the extent of each event: its length on a line, its
    # area on a 2D interface (system-spanning: 90 % of L, of L W).
    fr = (slip_fractions(catalog["u_mean"], catalog["A"], info.D, info.L * info.W) if info.interface_2d
          else slip_fractions(catalog["u_mean"], catalog["L_s"], info.D, info.L))
    res["slip_fraction_small"] = fr["small"]
    res["slip_fraction_spanning"] = fr["spanning"]
    res["_fits"] = fits
    res["_lognormal_fits"] = logfits
    return res


def _public(d: dict) -> dict:
    return {k: v for k, v in d.items() if not k.startswith("_")}
