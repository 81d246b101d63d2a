"""Order parameter of a run's long-time state, for the coarsening-to-complexity
map (docs/transition.md).

The paper's open question is where, between H << L and H >> L, the interface
stops coarsening into one periodic travelling pulse and starts producing
statistical complexity.  A run is classified from three independent records
of the same window of time, so that a wrong verdict of one observable shows up
as a disagreement (`agreement` below):

* the space-time field (/snapshots): the travelling-pulse criterion of
  analysis.periodic_pulse_from_spacetime, the median spatial coefficient of
  variation of the slip rate while slipping (uniform k = 0 stick-slip is
  ~uniform), and the number of separate slipping patches (the coarsening
  length scale is L / patches);
* the global time series (/timeseries max_slip_rate): the fraction of time
  above PULSE_MIN_RATE v0 and the regularity of log v_max (its coefficient of
  variation and the height of its autocorrelation's first peak);
* the event catalog (/events): the spread of event sizes (standard deviation
  of log10 M0, in decades) and the fraction of slip in system-spanning events.

States (`classify_window`):
  arrested            v_max < ARRESTED_MAX_RATE v0 throughout: the interface
                      is locked (a half-space has no uniform-mode stiffness, so
                      nothing reloads a locked interface: docs/transition.md);
  steady              v_max < STEADY_MAX_RATE v0 throughout: no events;
  periodic_pulse      the travelling-pulse criterion holds;
  uniform_stick_slip  while slipping the slip rate is nearly uniform in x
                      (median spatial CV < UNIFORM_MAX_CV) and >= 80 % of the
                      slip is in system-spanning events;
  complex             a broad population of events (log10 M0 spread >=
                      COMPLEX_MIN_SIZE_SPREAD decades) with < 80 % of the slip
                      in system-spanning events;
  spanning_ruptures   >= 80 % of the slip in system-spanning ruptures that are
                      neither one steady pulse nor uniform: the interface has
                      coarsened to the system size L, the large-H/L behaviour
                      the paper cites (Rice 1996: "quasi-periodic slip bursts
                      that correspond to rupture propagating a distance
                      comparable to L");
  other               none of these, including windows with fewer than
                      MIN_EVENTS events: a broad size distribution cannot be
                      established from a handful of events, and rare
                      system-size ruptures (thick strips, small L) must not
                      pass for complexity.

A run is `converged` when its last two thirds give the same state (the
classification is unchanged over the last third).  All thresholds are module
constants, documented in docs/transition.md and tested on synthetic fields in
tests/python/test_transition.py.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import analysis, runfile

STEADY_MAX_RATE = 3.0          # [v0] below this everywhere and always: steady sliding
ARRESTED_MAX_RATE = 0.1        # [v0] below this everywhere and always: locked, not sliding
UNIFORM_MAX_CV = 0.3           # spatial CV of v while slipping, uniform k = 0 stick-slip
SPANNING_COHERENT = 0.8        # fraction of slip in spanning events of a coherent state
COMPLEX_MIN_SIZE_SPREAD = 0.5  # [decades] std of log10 M0 of a complex population
PATCH_RATE = 10.0              # [v0] a node slips "fast" above this (patch counting)
MIN_EVENTS = 5                 # fewer events in a window: the catalog does not vote

STATES = ("arrested", "steady", "periodic_pulse", "uniform_stick_slip", "spanning_ruptures", "complex", "other")
# Coarsened (to one pulse, one uniform mode or system-size ruptures) vs complex: the paper's dichotomy.
COARSENED_STATES = ("periodic_pulse", "uniform_stick_slip", "spanning_ruptures")


@dataclass
class WindowRecord:
    """What one window of a run holds (SI units)."""
    v0: float
    L: float
    dx: float
    snapshot_time: np.ndarray          # [n]
    slip_rate: np.ndarray              # [n, N]
    series_time: np.ndarray            # [m]
    max_slip_rate: np.ndarray          # [m]
    catalog: dict = field(default_factory=dict)  # analysis catalog fields (may be empty)


def patch_count(slip_rate_row: np.ndarray, threshold: float) -> int:
    """Separate (periodic) runs of nodes slipping faster than `threshold`."""
    fast = np.asarray(slip_rate_row) > threshold
    if not fast.any():
        return 0
    if fast.all():
        return 1
    # rising edges on the periodic ring
    return int(np.count_nonzero(fast & ~np.roll(fast, 1)))


def autocorrelation_peak(series: np.ndarray) -> float:
    """Height of the first maximum of the normalised autocorrelation after
    its first zero crossing (1 for a periodic signal, ~0 for noise; NaN if
    there is no zero crossing, e.g. for a trend)."""
    x = np.asarray(series, float)
    x = x - x.mean()
    if x.size < 8 or not np.any(x):
        return math.nan
    n = x.size
    spectrum = np.fft.rfft(x, 2 * n)
    ac = np.fft.irfft(spectrum * np.conj(spectrum))[:n]
    ac /= ac[0]
    crossing = np.nonzero(ac < 0)[0]
    if crossing.size == 0:
        return math.nan
    rest = ac[crossing[0]:n // 2]
    return float(rest.max()) if rest.size else math.nan


def window_observables(w: WindowRecord) -> dict:
    v0 = w.v0
    v = np.abs(np.asarray(w.slip_rate, float))
    vmax_series = np.asarray(w.max_slip_rate, float)
    obs: dict = {}
    obs["max_rate_v0"] = float(max(vmax_series.max(initial=0.0), v.max(initial=0.0)) / v0)
    obs["active_time_fraction"] = float(np.mean(vmax_series > analysis.PULSE_MIN_RATE * v0)) \
        if vmax_series.size else math.nan
    logv = np.log10(np.maximum(vmax_series, 1e-3 * v0) / v0)
    mean_vmax = float(vmax_series.mean()) if vmax_series.size else 0.0
    # A window stuck everywhere (v = 0 exactly) has no CV: NaN, and no vote from the series.
    obs["cv_max_slip_rate"] = float(vmax_series.std() / mean_vmax) if mean_vmax > 0 else math.nan
    obs["autocorrelation_peak"] = autocorrelation_peak(logv)
    # space-time
    if v.ndim == 2 and v.shape[0] >= 2:
        pulse = analysis.periodic_pulse_from_spacetime(w.snapshot_time, v, v0, w.dx, late_fraction=1.0)
        obs["pulse"] = pulse
        rows = v[v.max(axis=1) > analysis.PULSE_MIN_RATE * v0]
        if rows.shape[0]:
            cv = rows.std(axis=1) / rows.mean(axis=1)
            obs["spatial_cv_slipping"] = float(np.median(cv))
            patches = [patch_count(r, PATCH_RATE * v0) for r in rows]
            obs["median_patches"] = float(np.median(patches))
        else:
            obs["spatial_cv_slipping"] = math.nan
            obs["median_patches"] = 0.0
    else:
        obs["pulse"] = {"flag": False, "determined": False}
        obs["spatial_cv_slipping"] = math.nan
        obs["median_patches"] = math.nan
    # catalog
    cat = w.catalog or {}
    m0 = np.asarray(cat.get("M0", []), float)
    m0 = m0[m0 > 0]
    obs["n_events"] = int(m0.size)
    if m0.size >= MIN_EVENTS:
        obs["size_spread_decades"] = float(np.log10(m0).std(ddof=1))
        obs["spanning_slip_fraction"] = analysis.slip_fractions(
            cat["u_mean"], cat["L_s"], D=1.0, L=w.L)["spanning"]
    else:
        obs["size_spread_decades"] = math.nan
        obs["spanning_slip_fraction"] = math.nan
    return obs


def votes(obs: dict) -> dict:
    """What each independent record says on its own: 'coherent' (one pulse or
    uniform stick-slip), 'complex', 'steady', or None (cannot tell)."""
    out = {}
    if obs["max_rate_v0"] < STEADY_MAX_RATE:
        return {"spacetime": "steady", "timeseries": "steady", "catalog": "steady"}
    p = obs["pulse"]
    if p.get("determined"):
        coherent = p["flag"] or obs["spatial_cv_slipping"] < UNIFORM_MAX_CV
        out["spacetime"] = "coherent" if coherent else "complex"
    else:
        out["spacetime"] = None
    # A steady pulse keeps v_max nearly constant; periodic stick-slip repeats.
    cv, ac = obs["cv_max_slip_rate"], obs["autocorrelation_peak"]
    if cv < analysis.PULSE_MAX_CV or (not math.isnan(ac) and ac >= 0.7):
        out["timeseries"] = "coherent"
    elif not math.isnan(cv):
        out["timeseries"] = "complex"
    else:
        out["timeseries"] = None
    spread, spanning = obs["size_spread_decades"], obs["spanning_slip_fraction"]
    if math.isnan(spread):
        out["catalog"] = None
    elif spread >= COMPLEX_MIN_SIZE_SPREAD and spanning < SPANNING_COHERENT:
        out["catalog"] = "complex"
    else:
        out["catalog"] = "coherent"
    return out


def classify_window(w: WindowRecord) -> dict:
    obs = window_observables(w)
    vote = votes(obs)
    if obs["max_rate_v0"] < ARRESTED_MAX_RATE:
        state = "arrested"
    elif obs["max_rate_v0"] < STEADY_MAX_RATE:
        state = "steady"
    elif obs["pulse"].get("flag"):
        state = "periodic_pulse"
    elif (obs["spatial_cv_slipping"] < UNIFORM_MAX_CV
          and (math.isnan(obs["spanning_slip_fraction"]) or obs["spanning_slip_fraction"] >= SPANNING_COHERENT)):
        state = "uniform_stick_slip"
    elif (not math.isnan(obs["size_spread_decades"]) and obs["size_spread_decades"] >= COMPLEX_MIN_SIZE_SPREAD
          and obs["spanning_slip_fraction"] < SPANNING_COHERENT):
        state = "complex"
    elif not math.isnan(obs["spanning_slip_fraction"]) and obs["spanning_slip_fraction"] >= SPANNING_COHERENT:
        state = "spanning_ruptures"
    else:
        state = "other"
    expected = {"arrested": "steady", "steady": "steady", "periodic_pulse": "coherent", "uniform_stick_slip": "coherent",
                "spanning_ruptures": "coherent", "complex": "complex", "other": None}[state]
    cast = [v for v in vote.values() if v is not None]
    agreement = (sum(v == expected for v in cast) / len(cast)) if (cast and expected) else math.nan
    return {"state": state, "observables": obs, "votes": vote, "agreement": agreement}


def _window(record: WindowRecord, t0: float, t1: float) -> WindowRecord:
    s = (record.snapshot_time >= t0) & (record.snapshot_time <= t1)
    r = (record.series_time >= t0) & (record.series_time <= t1)
    cat = {}
    if record.catalog:
        keep = (np.asarray(record.catalog["t_start"]) >= t0) & (np.asarray(record.catalog["t_start"]) <= t1)
        cat = {k: np.asarray(v)[keep] for k, v in record.catalog.items() if k != "attrs"}
    return WindowRecord(record.v0, record.L, record.dx, record.snapshot_time[s], record.slip_rate[s],
                        record.series_time[r], record.max_slip_rate[r], cat)


def classify_record(record: WindowRecord) -> dict:
    """State of each third of the record, the final state and convergence
    (the last two thirds agree), and the coarsening length L / patches per third."""
    t_all = np.concatenate([record.snapshot_time, record.series_time])
    t0, t1 = float(t_all.min()), float(t_all.max())
    edges = np.linspace(t0, t1, 4)
    thirds = [classify_window(_window(record, edges[i], edges[i + 1])) for i in range(3)]
    states = [t["state"] for t in thirds]
    patches = [t["observables"]["median_patches"] for t in thirds]
    return {"state": states[-1], "converged": states[1] == states[2], "states_by_third": states,
            "coarsening_length_by_third": [record.L / p if p and p > 0 else math.nan for p in patches],
            "agreement": thirds[-1]["agreement"], "votes": thirds[-1]["votes"],
            "observables": thirds[-1]["observables"]}


def read_record(path, max_rows: int = 4000) -> WindowRecord:
    """The three records of a run file.  The catalog is /events if `slipstrip events`
    has run; otherwise the events are detected from /slip_sampling (into a
    temporary file: the run file is not changed).  A run with neither cannot give
    the catalog's votes: ValueError, naming the file and the cure."""
    info = analysis.read_run_info(path)
    st = analysis.read_spacetime(path, max_rows=max_rows)
    with runfile.open_h5(path) as f:
        ts_t = f["timeseries/time"][:] if "timeseries" in f else np.zeros(0)
        ts_v = f["timeseries/max_slip_rate"][:] if "timeseries" in f else np.zeros(0)
        has_events, has_sampling = "events" in f, "slip_sampling" in f
    if has_events:
        catalog = analysis.read_catalog(path)
    elif has_sampling:
        catalog = analysis.catalog_for(path)
    else:
        raise ValueError(f"{path}: no /events and no /slip_sampling to detect them from (output.delta_th = 0); "
                         "the classification needs the event catalog: rerun with output.delta_th > 0")
    if st is None:
        t, x, v = np.zeros(0), np.zeros(info.n_nodes), np.zeros((0, info.n_nodes))
    else:
        t, x, v = st
    return WindowRecord(info.v0, info.L, info.L / max(v.shape[1], 1), t, v, ts_t, ts_v, catalog)


def classify_run(path) -> dict:
    return classify_record(read_record(path))


# ---------------------------------------------------------------------------
# The map: classify every run file of one or more directories
# ---------------------------------------------------------------------------

def _run_parameters(path) -> dict:
    config = runfile.read_config(path)
    status = runfile.read_status(path) or ""
    g, fr = config["geometry"], config["friction"]
    H = g["height"]
    H = math.inf if isinstance(H, str) else float(H)
    slope = fr["a"] - fr["f0"] * fr["b"]  # d f_ss / d ln v of the paper law for v >> v*
    return {"file": str(path), "status": status, "length": float(g["length"]), "height": H,
            "nodes": int(g["nodes"]), "f0": fr["f0"], "a": fr["a"], "b": fr["b"],
            "rate_weakening": -slope, "noise_seed": int(config["initial"]["noise_seed"]),
            "duration": float(config["time"]["duration"])}


def classify_directory(paths) -> list[dict]:
    """One row per run file: parameters, state, convergence, agreement."""
    rows = []
    for path in paths:
        try:
            row = _run_parameters(path)
        except (OSError, KeyError, ValueError, TypeError) as err:  # not a run file: no parameters either
            rows.append({"file": str(path), "status": "unreadable", "state": "unreadable", "converged": False,
                         "agreement": math.nan, "error": " ".join(str(err).split())})
            continue
        try:
            result = classify_run(path)
        except (OSError, KeyError, ValueError, RuntimeError) as err:
            # RuntimeError: the HDF5 reads of the compiled event detection.  On a running run a read
            # that outlasts the writer's reader_lock_timeout sees the file change under it
            # (docs/output.md): say so rather than leave the reader to guess.
            why = " ".join(str(err).split())
            if row["status"] == "running":
                why += ("; the run is still being written and its file changed during the read: classify it "
                        "when it has stopped, or a copy of the file")
            row.update(state="unreadable", converged=False, agreement=math.nan, error=why)
        else:
            row.update(state=result["state"], converged=result["converged"], agreement=result["agreement"],
                       states_by_third="/".join(result["states_by_third"]),
                       coarsening_length_last=result["coarsening_length_by_third"][-1],
                       spanning_slip_fraction=result["observables"]["spanning_slip_fraction"],
                       size_spread_decades=result["observables"]["size_spread_decades"])
        rows.append(row)
    return rows


DEFAULT_NOISE_SEED = 1   # the seed of every map run before seeds were varied (configs/reference.toml)
MAX_SEED_COMBINATIONS = 100_000


def noise_seed(row: dict) -> int:
    """The run's `initial.noise_seed`; rows of maps written before the column
    existed come from runs that all used the default seed."""
    seed = row.get("noise_seed", DEFAULT_NOISE_SEED)
    return int(seed) if isinstance(seed, (int, float)) and math.isfinite(seed) else DEFAULT_NOISE_SEED


def _last_upward_crossing(fractions: list[float], threshold: float):
    """Index i and weight w of the last upward crossing of `threshold` between
    fractions[i] and fractions[i + 1] (fractions ordered by growing H), or None."""
    crossing = None
    for i, (lo, hi) in enumerate(zip(fractions, fractions[1:])):
        if lo < threshold <= hi:
            crossing = (i, (threshold - lo) / (hi - lo))
    return crossing


def _log_interpolate(h_lo: float, h_hi: float, w: float) -> float:
    return math.exp((1 - w) * math.log(h_lo) + w * math.log(h_hi))


def transition_heights(rows: list[dict], threshold: float = SPANNING_COHERENT) -> list[dict]:
    """Where complexity gives way to coarsening as H grows, per (friction, L):
    the last upward crossing of `threshold` by the fraction of slip carried by
    system-spanning ruptures (last third of each run), H* interpolated linearly
    in log H between the two bracketing heights.  The same observable and
    threshold as the `complex` / `spanning_ruptures` boundary of the classifier,
    but read as a continuous order parameter, so H* is located between grid points.

    Seed ensembles: runs that differ only in `initial.noise_seed` are members of
    one grid point.  H* comes from the members' mean fraction at each height; its
    spread from every way of picking one member per height (each a possible map
    had only one seed been run): `height_range` is the smallest and largest H*
    over those picks, `picks_without_crossing` how many picks have no crossing.
    With one run per height the range is H* itself.  Near H* the state depends
    on the initial noise, so the range, not the bracket, is H*'s error bar.

    Each result carries H*/L and H*/Lc(H*) (Lc interpolated the same way) with
    their brackets: a transition that scales with L has the same H*/L for every
    L; one that scales with Lc(H) has the same H*/Lc(H*)."""
    import itertools
    out = []
    groups = {}
    for r in rows:
        f = r.get("spanning_slip_fraction", math.nan)
        if math.isfinite(r["height"]) and math.isfinite(f) and r.get("state") != "unreadable":
            by_height = groups.setdefault((round(r["rate_weakening"], 6), r["length"]), {})
            by_height.setdefault(r["height"], []).append(r)
    for (slope, L), by_height in sorted(groups.items()):
        heights = sorted(by_height)
        members = [sorted(by_height[h], key=noise_seed) for h in heights]
        means = [float(np.mean([m["spanning_slip_fraction"] for m in ms])) for ms in members]
        crossing = _last_upward_crossing(means, threshold)
        if crossing is None:
            continue
        i, w = crossing
        h_star = _log_interpolate(heights[i], heights[i + 1], w)
        lc_lo, lc_hi = (float(np.mean([m.get("critical_length", math.nan) for m in members[j]])) for j in (i, i + 1))
        lc_star = (1 - w) * lc_lo + w * lc_hi
        n_picks = math.prod(len(ms) for ms in members)
        if n_picks > MAX_SEED_COMBINATIONS:
            raise ValueError(f"{n_picks} seed combinations at |df_ss/d ln v| = {slope}, L = {L} m: "
                             f"more than {MAX_SEED_COMBINATIONS} (too many seeds at too many heights)")
        picked, missing = [], 0
        for pick in itertools.product(*[[m["spanning_slip_fraction"] for m in ms] for ms in members]):
            c = _last_upward_crossing(list(pick), threshold)
            if c is None:
                missing += 1
            else:
                picked.append(_log_interpolate(heights[c[0]], heights[c[0] + 1], c[1]))
        out.append({"rate_weakening": slope, "length": L, "height": h_star,
                    "height_bracket": (heights[i], heights[i + 1]),
                    "height_range": (min(picked), max(picked)),
                    "seeds_at_bracket": (len(members[i]), len(members[i + 1])),
                    "seed_picks": n_picks, "picks_without_crossing": missing,
                    "height_over_length": h_star / L,
                    "height_over_length_bracket": (heights[i] / L, heights[i + 1] / L),
                    "critical_length": lc_star,
                    "height_over_critical_length": h_star / lc_star,
                    "height_over_critical_length_bracket": (heights[i] / lc_lo, heights[i + 1] / lc_hi)})
    return out


def transition_heights_markdown(stars: list[dict]) -> str:
    """The transition heights as a Markdown table (written by `transition --table`
    after the state grid, so the doc's numbers are regenerated with the map)."""
    if not stars:
        return "No upward crossing of the spanning-slip threshold in any (friction, L) group.\n"
    lines = ["| \\|df_ss/d ln v\\| | L | H\\* (bracket) | H\\* over seeds | seeds at the bracket | H\\*/L (bracket) | "
             "Lc(H\\*) | H\\*/Lc(H\\*) (bracket) |",
             "|---|---|---|---|---|---|---|---|"]
    for t in sorted(stars, key=lambda t: (-t["rate_weakening"], t["length"])):
        (h0, h1), (r0, r1) = t["height_bracket"], t["height_over_critical_length_bracket"]
        (s0, s1), (n0, n1) = t["height_range"], t["seeds_at_bracket"]
        spread = f"{s0:.3g}–{s1:.3g} m" + (f" ({t['picks_without_crossing']} of {t['seed_picks']} picks: no crossing)"
                                           if t["picks_without_crossing"] else "")
        lines.append(f"| {t['rate_weakening']:.4f} | {t['length']:g} m | {t['height']:.2g} m ({h0:g}–{h1:g}) | "
                     f"{spread} | {n0}, {n1} | "
                     f"{t['height_over_length']:.2g} ({h0 / t['length']:.3g}–{h1 / t['length']:.3g}) | "
                     f"{t['critical_length']:.2g} m | {t['height_over_critical_length']:.2g} ({r0:.2g}–{r1:.2g}) |")
    return "\n".join(lines) + "\n"


def plot_collapse(rows: list[dict], out_png, threshold: float = SPANNING_COHERENT) -> None:
    """The continuous order parameter (fraction of slip in system-spanning
    ruptures, last third of each run) against H/L and against H/Lc(H), one line
    per interface length L, one panel row per friction point with at least two
    L; at a height run with several noise seeds, their mean with the smallest
    and largest member as an error bar.  The abscissa on which the lines of different L fall on each other is the
    one the transition scales with."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    usable = [r for r in rows if math.isfinite(r["height"]) and math.isfinite(r.get("spanning_slip_fraction", math.nan))]
    slopes = sorted({round(r["rate_weakening"], 6) for r in usable
                     if len({q["length"] for q in usable if round(q["rate_weakening"], 6) == round(r["rate_weakening"], 6)}) >= 2},
                    reverse=True)
    if not slopes:
        return
    fig, axes = plt.subplots(len(slopes), 2, figsize=(8.4, 3.2 * len(slopes)), squeeze=False)
    for (ax_l, ax_c), slope in zip(axes, slopes):
        mine = [r for r in usable if round(r["rate_weakening"], 6) == slope]
        for L in sorted({r["length"] for r in mine}):
            # Seed ensembles: the members' mean, and their smallest and largest
            # fraction as an error bar (none where one seed ran).
            by_height = {}
            for r in mine:
                if r["length"] == L:
                    by_height.setdefault(r["height"], []).append(r)
            hs = sorted(by_height)
            f = np.array([[np.mean(v), np.min(v), np.max(v)] for v in
                          ([r["spanning_slip_fraction"] for r in by_height[h]] for h in hs)])
            lc = np.array([np.mean([r["critical_length"] for r in by_height[h]]) for h in hs])
            err = [f[:, 0] - f[:, 1], f[:, 2] - f[:, 0]]
            ax_l.errorbar(np.array(hs) / L, f[:, 0], yerr=err, fmt="o-", capsize=3, label=f"L = {L:g} m")
            ax_c.errorbar(np.array(hs) / lc, f[:, 0], yerr=err, fmt="o-", capsize=3, label=f"L = {L:g} m")
        for ax, xl in ((ax_l, "H / L"), (ax_c, "H / Lc(H)")):
            ax.axhline(threshold, color="0.5", ls=":", lw=0.8)
            ax.set(xscale="log", xlabel=xl, ylabel="slip fraction in spanning ruptures", ylim=(-0.02, 1.02),
                   title=f"|df_ss/d ln v| = {slope:.4f}")
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out_png, dpi=100)
    plt.close(fig)


MARKERS = {"arrested": ("X", "k"), "steady": ("s", "0.6"), "periodic_pulse": ("o", "tab:blue"), "uniform_stick_slip": ("^", "tab:green"),
           "spanning_ruptures": ("v", "tab:cyan"), "complex": ("*", "tab:red"), "other": ("D", "tab:purple"),
           "unreadable": ("x", "k")}


def _run_config_text(path) -> str:
    return runfile.read_config_text(path)


def add_critical_lengths(rows: list[dict]) -> None:
    """Adds Lc(H) [m] (linear stability of steady sliding, the bindings; docs/stability.md)
    and Lc(inf) to every row, from the run's own resolved config, so the map's Lc axis
    uses exactly the material and friction that ran.  NaN where it cannot be computed."""
    import slipstrip
    cache = {}
    for r in rows:
        try:
            text = _run_config_text(r["file"])
        except (OSError, KeyError) as err:
            r["critical_length"] = r["critical_length_halfspace"] = math.nan
            r.setdefault("error", str(err))
            continue
        key = (text, r["height"])
        if key not in cache:
            try:
                config = slipstrip.load_config(text)
                lc = slipstrip.critical_wavelength_vs_height(config, [r["height"], math.inf])
                cache[key] = (float(lc[0]), float(lc[1]))
            except (ValueError, RuntimeError):
                cache[key] = (math.nan, math.nan)
        r["critical_length"], r["critical_length_halfspace"] = cache[key]


def _scatter(ax, x, y, row, size=60):
    marker, colour = MARKERS[row["state"]]
    ax.scatter(x, y, marker=marker, s=size, facecolors=colour if row["converged"] else "none", edgecolors=colour)


def plot_map(rows: list[dict], out_png) -> None:
    """The state of every run (open symbols: not converged), in
    (a) the issue's plane (H/L, |df_ss/d ln v|), marker size growing with L;
    (b) (H/L, Lc(H)/H) when rows carry `critical_length` (add_critical_lengths);
    (c) one panel per interface length L in (H, |df_ss/d ln v|), with the lines
        H = L (dashed) and H = Lc(H) (dotted, from the rows' Lc): a transition that
        stays at the same H when L changes scales with Lc(H); one that moves with L
        scales with L.
    Half-spaces are drawn at 2x the largest finite abscissa."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    lengths = sorted({r["length"] for r in rows})
    has_lc = any(math.isfinite(r.get("critical_length", math.nan)) for r in rows)
    n_panels = 1 + has_lc + len(lengths)
    # A grid two panels wide, so the figure stays readable at page width
    # (840 px at the saved dpi) however many interface lengths there are.
    n_cols = min(2, n_panels)
    n_rows = -(-n_panels // n_cols)
    fig, grid = plt.subplots(n_rows, n_cols, figsize=(4.2 * n_cols, 3.6 * n_rows + 0.5), squeeze=False)
    axes = grid.ravel()
    for unused in axes[n_panels:]:
        unused.set_visible(False)
    finite_ratio = [r["height"] / r["length"] for r in rows if math.isfinite(r["height"])]
    inf_ratio = 2 * max(finite_ratio) if finite_ratio else 1.0
    size = {L: 30 + 60 * i for i, L in enumerate(lengths)}
    ax = axes[0]
    for r in rows:
        h = r["height"] / r["length"] if math.isfinite(r["height"]) else inf_ratio
        _scatter(ax, h, r["rate_weakening"], r, size[r["length"]])
    ax.set(xscale="log", xlabel="H / L (half-space at the right end)", ylabel="|d f_ss / d ln v|",
           title="all runs (marker size: L = " + ", ".join(f"{L:g}" for L in lengths) + " m)")
    if has_lc:
        ax = axes[1]
        for r in rows:
            lc = r.get("critical_length", math.nan)
            if math.isfinite(r["height"]) and math.isfinite(lc):
                _scatter(ax, r["height"] / r["length"], lc / r["height"], r, size[r["length"]])
        ax.axhline(1.0, color="0.5", ls=":", lw=0.8)
        ax.set(xscale="log", yscale="log", xlabel="H / L", ylabel="Lc(H) / H", title="finite strips")
    finite_h = [r["height"] for r in rows if math.isfinite(r["height"])]
    inf_h = 2 * max(finite_h) if finite_h else 1.0
    for ax, L in zip(axes[1 + has_lc:], lengths):
        mine = [r for r in rows if r["length"] == L]
        for r in mine:
            _scatter(ax, r["height"] if math.isfinite(r["height"]) else inf_h, r["rate_weakening"], r)
        ax.axvline(L, color="0.4", ls="--", lw=0.8, label="H = L")
        # H = Lc(H) for each friction point: the smallest finite H with Lc(H) <= H
        # (Lc grows with H and saturates at Lc(inf), so it is crossed once).
        crossing = {}
        for r in mine:
            lc = r.get("critical_length", math.nan)
            if math.isfinite(r["height"]) and math.isfinite(lc) and lc <= r["height"]:
                key = round(r["rate_weakening"], 6)
                crossing[key] = min(crossing.get(key, math.inf), r["height"])
        if crossing:
            ys = sorted(crossing)
            ax.plot([crossing[y] for y in ys], ys, color="0.4", ls=":", lw=1.0, label="first H with Lc(H) <= H")
        ax.set(xscale="log", xlabel="H [m] (half-space at the right end)", ylabel="|d f_ss / d ln v|",
               title=f"L = {L:g} m")
        ax.legend(fontsize=6, loc="lower left")
    handles = [plt.Line2D([], [], marker=m, color=c, linestyle="", label=s) for s, (m, c) in MARKERS.items()]
    fig.legend(handles=handles, fontsize=7, loc="upper center", ncol=len(MARKERS))
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.35 / fig.get_figheight()))
    fig.savefig(out_png, dpi=100)
    plt.close(fig)


STATE_SYMBOLS = {"arrested": "A", "steady": "S", "periodic_pulse": "P", "uniform_stick_slip": "U", "spanning_ruptures": "R",
                 "complex": "C", "other": "O", "unreadable": "x"}


def thin_edges(rows: list[dict]) -> list[dict]:
    """The thin-strip edge of the complexity window, per (friction, L): the
    thinnest strip height at which a run is `complex` (`height_complex`) and the
    largest height below it at which no run is (`height_not_complex`, NaN when
    no thinner strip was run, so the edge is bounded only from above).  This is
    the reverse transition of the paper's Fig. 5 discussion (complexity
    disappearing again for H << Lc(H)); groups without a complex run have no
    window and are left out.

    A bracket is read from the states, not from a threshold on a continuous
    observable (unlike `transition_heights`): on the thin side the non-complex
    states differ (spanning ruptures, creeping patches, pulses), so the state is
    the observable.  Each end carries its runs' states and whether every one of
    them is converged; an end that is not converged makes the bracket
    provisional, which the table says.

    The window need not be one interval of H: a strip between two complex ones
    may end in another state.  `inside_not_complex` lists such heights between
    the thinnest and the thickest complex strip ("H:state/state", by seed,
    separated by spaces), so that an edge read from the thinnest complex strip
    is never taken for the whole story."""
    groups = {}
    for r in rows:
        if math.isfinite(r["height"]) and r.get("state") in STATES:
            groups.setdefault((round(r["rate_weakening"], 6), r["length"]), {}).setdefault(r["height"], []).append(r)
    out = []
    for (slope, L), by_height in sorted(groups.items()):
        complex_heights = [h for h, runs in by_height.items() if any(r["state"] == "complex" for r in runs)]
        if not complex_heights:
            continue
        h_complex = min(complex_heights)
        gaps = sorted(h for h in by_height if h_complex < h < max(complex_heights) and h not in complex_heights)
        inside = " ".join(f"{h:g}:" + "/".join(r["state"] for r in sorted(by_height[h], key=noise_seed)) for h in gaps)
        below = [h for h in by_height if h < h_complex]
        h_not = max(below) if below else math.nan

        def end(h):
            runs = sorted(by_height.get(h, []), key=noise_seed)
            lc = float(np.mean([r.get("critical_length", math.nan) for r in runs])) if runs else math.nan
            return {"states": "/".join(r["state"] for r in runs),
                    "converged": bool(runs) and all(bool(r["converged"]) for r in runs),
                    "critical_length": lc, "critical_over_height": lc / h if runs else math.nan}
        hi, lo = end(h_complex), end(h_not)
        out.append({"rate_weakening": slope, "length": L, "height_complex": h_complex, "height_not_complex": h_not,
                    "states_complex": hi["states"], "states_not_complex": lo["states"],
                    "converged_complex": hi["converged"], "converged_not_complex": lo["converged"],
                    "critical_over_height_complex": hi["critical_over_height"],
                    "critical_over_height_not_complex": lo["critical_over_height"],
                    "length_over_critical_complex": L / hi["critical_length"],
                    "length_over_critical_not_complex": L / lo["critical_length"] if below else math.nan,
                    "inside_not_complex": inside})
    return out


THIN_EDGE_COLUMNS = ("rate_weakening", "length", "height_not_complex", "height_complex", "states_not_complex",
                     "states_complex", "converged_not_complex", "converged_complex",
                     "critical_over_height_not_complex", "critical_over_height_complex",
                     "length_over_critical_not_complex", "length_over_critical_complex", "inside_not_complex")


def thin_edges_markdown(edges: list[dict]) -> str:
    """The thin-strip edges as a Markdown table (bracket in H and in Lc(H)/H)."""
    if not edges:
        return "No friction point with a complex run.\n"
    lines = ["| \\|df_ss/d ln v\\| | L | edge between H (not complex) | and H (complex) | Lc(H)/H | states at the ends |",
             "|---|---|---|---|---|---|"]
    for e in sorted(edges, key=lambda e: (-e["rate_weakening"], e["length"])):
        def mark(state, converged):
            return f"`{state}`" + ("" if converged else " (not converged)")
        if math.isfinite(e["height_not_complex"]):
            low = f"{e['height_not_complex']:g} m"
            ratio = f"{e['critical_over_height_complex']:.2g}–{e['critical_over_height_not_complex']:.2g}"
            states = (mark(e["states_not_complex"], e["converged_not_complex"]) + " below, " +
                      mark(e["states_complex"], e["converged_complex"]) + " above")
        else:
            low = "— (no thinner strip run: bounded above only)"
            ratio = f"> {e['critical_over_height_complex']:.2g}"
            states = mark(e["states_complex"], e["converged_complex"]) + " at the thinnest strip run"
        if e["inside_not_complex"]:
            states += "; not complex between complex strips: " + ", ".join(
                f"H = {h} m (`{st}`)" for h, st in (item.split(":") for item in e["inside_not_complex"].split()))
        lines.append(f"| {e['rate_weakening']:.4f} | {e['length']:g} m | {low} | {e['height_complex']:g} m | "
                     f"{ratio} | {states} |")
    return "\n".join(lines) + "\n"


def plot_length_height(rows: list[dict], out_png) -> None:
    """Every finite strip's state in the (H, L) plane, one panel per friction
    point with a complex run (open symbols: not converged), with the thin edges
    (`thin_edges`) as grey bars (dashed: bounded above only), and the upper
    transition H* (`transition_heights`, with its spread over noise seeds) in
    orange: the complexity window, closed on the thick side by the upper
    transition and on the thin side by the reverse one."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    finite = [r for r in rows if math.isfinite(r["height"]) and r.get("state") in STATES]
    edges = thin_edges(finite)
    slopes = sorted({e["rate_weakening"] for e in edges}, reverse=True)
    if not slopes:
        return
    fig, axes = plt.subplots(1, len(slopes), figsize=(4.2 * len(slopes), 3.8), squeeze=False)
    for ax, slope in zip(axes[0], slopes):
        mine = [r for r in finite if round(r["rate_weakening"], 6) == slope]
        lengths = sorted({r["length"] for r in mine})
        for r in mine:
            _scatter(ax, r["height"], r["length"], r, size=45)
        for e in edges:
            if e["rate_weakening"] == slope:
                # Bounded above only: a dashed bar down to a third of the thinnest complex strip.
                closed = math.isfinite(e["height_not_complex"])
                lo = e["height_not_complex"] if closed else e["height_complex"] / 3
                ax.plot([lo, e["height_complex"]], [e["length"]] * 2, color="k", lw=2.5, alpha=0.35,
                        ls="-" if closed else "--", solid_capstyle="butt")
        for t in transition_heights(mine):
            # The upper transition: H* with its spread over noise seeds.
            lo, hi = t["height_range"]
            ax.errorbar(t["height"], t["length"], xerr=[[t["height"] - lo], [hi - t["height"]]], fmt="|",
                        color="tab:orange", ms=16, mew=2, capsize=3)
        ax.set(xscale="log", xlabel="H [m]", ylabel="L [m]", yticks=lengths, title=f"|df_ss/d ln v| = {slope:.4f}")
        ax.set_yticklabels([f"{L:g}" for L in lengths])
        ax.grid(axis="y", color="0.9")
    handles = [plt.Line2D([], [], marker=m, color=c, linestyle="", label=s) for s, (m, c) in MARKERS.items()]
    handles.append(plt.Line2D([], [], color="k", lw=2.5, alpha=0.35, label="thin edge (bracket)"))
    handles.append(plt.Line2D([], [], marker="|", color="tab:orange", ms=10, mew=2, linestyle="",
                              label="H* (spread over seeds)"))
    fig.legend(handles=handles, fontsize=7, loc="upper center", ncol=4)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.6 / fig.get_figheight()))
    fig.savefig(out_png, dpi=100)
    plt.close(fig)


def state_grid_markdown(rows: list[dict]) -> str:
    """The map as Markdown tables, one per interface length L: a row per
    friction point (|df_ss/d ln v|), a column per strip height H, each cell the
    state's letter (lower case: not converged) and Lc(H)/H.  Written by
    `transition --table`, so the doc's table is regenerated with the map."""
    def h_key(h):
        return (math.isinf(h), h)
    lines = ["States: " + ", ".join(f"{v} = `{k}`" for k, v in STATE_SYMBOLS.items()) +
             "; lower case = not converged (the last two thirds disagree); several letters: one per noise "
             "seed (`initial.noise_seed`, in increasing order); in brackets Lc(H)/H "
             "(linear stability of steady sliding with the run's own config).", ""]
    for L in sorted({r["length"] for r in rows}):
        mine = [r for r in rows if r["length"] == L]
        heights = sorted({r["height"] for r in mine}, key=h_key)
        frictions = sorted({round(r["rate_weakening"], 6) for r in mine}, reverse=True)
        lines += [f"**L = {L:g} m** (N = {mine[0]['nodes']})", "",
                  "| \\|df_ss/d ln v\\| | " + " | ".join("∞" if math.isinf(h) else f"H = {h:g} m" for h in heights) + " |",
                  "|---|" + "---|" * len(heights)]
        for fr in frictions:
            cells = []
            for h in heights:
                match = sorted((r for r in mine if r["height"] == h and round(r["rate_weakening"], 6) == fr),
                               key=noise_seed)
                if not match:
                    cells.append("")
                    continue
                letters = []
                for r in match:
                    letter = STATE_SYMBOLS.get(r["state"], "?")
                    letters.append(letter if r["converged"] else letter.lower())
                lc = match[0].get("critical_length", math.nan)
                ratio = f" ({lc / h:.2g})" if math.isfinite(h) and math.isfinite(lc) else ""
                cells.append(" ".join(letters) + ratio)
            lines.append(f"| {fr:.4f} | " + " | ".join(cells) + " |")
        lines.append("")
    return "\n".join(lines)


def _parse_csv_value(text: str):
    if text in ("True", "False"):
        return text == "True"
    try:
        return float(text)       # also "inf" and "nan"
    except ValueError:
        return text


def read_map_csv(path) -> list[dict]:
    """The rows of a map written by `--csv` (types restored: numbers, booleans, strings).

    Why: a map is a record of classifications, and run files of a few GB each do not
    outlive every machine.  Reading an earlier map back lets new runs join it without
    re-running the old ones; each row still says which run file it came from."""
    import csv
    rows = []
    with open(path, newline="") as f:
        for raw in csv.DictReader(f):
            row = {k: _parse_csv_value(v) for k, v in raw.items() if v != ""}
            row["file"] = raw["file"]
            for key in ("nodes", "noise_seed"):
                if key in row:
                    row[key] = int(row[key])
            rows.append(row)
    return rows


def _map_cell(row: dict) -> tuple:
    """What makes two rows the same run of the map: friction, L, H, mesh and noise seed."""
    return (round(row["f0"], 9), round(row["a"], 9), round(row["b"], 9), row["length"], row["height"],
            int(row["nodes"]), noise_seed(row))


def longest_run_per_cell(rows: list[dict]) -> list[dict]:
    """One row per run of the map (`_map_cell`): where a run was extended (the
    same config and seed run again for longer, which repeats the shorter run
    and continues it), the longest one, judged on its own last third; the
    shorter ones are dropped (the order of the rest is kept)."""
    best = {}
    for i, r in enumerate(rows):
        if "f0" not in r or r.get("state") == "unreadable":
            continue
        cell = _map_cell(r)
        if cell not in best or r.get("duration", 0.0) > rows[best[cell]].get("duration", 0.0):
            best[cell] = i
    keep = set(best.values())
    return [r for i, r in enumerate(rows) if i in keep or "f0" not in r or r.get("state") == "unreadable"]


def main(argv: list[str]) -> int:
    import argparse
    import csv
    import sys
    from pathlib import Path

    from .paths import OutputPathError, check_outputs, one_line
    p = argparse.ArgumentParser(prog="python3 -m slipstrip transition",
                                description="Classify the long-time state of run files (docs/transition.md).")
    p.add_argument("paths", nargs="*", help="run files or directories holding them")
    p.add_argument("--previous", action="append", default=[],
                   help="an earlier map (CSV written by --csv) whose rows join the runs classified now; a run "
                        "classified now replaces an earlier row of the same friction, L, H, N and noise seed "
                        "(repeatable)")
    p.add_argument("--csv", help="write one row per run")
    p.add_argument("--plot", help="write the state map (PNG)")
    p.add_argument("--table", help="write the map as Markdown tables (one per L)")
    p.add_argument("--collapse", help="write the order parameter against H/L and H/Lc(H) (PNG)")
    p.add_argument("--heights", help="write the transition heights H* per friction and L (CSV)")
    p.add_argument("--thin-edges", help="write the thin-strip edge of the complexity window per friction and L (CSV)")
    p.add_argument("--plane", help="write every strip's state in the (H, L) plane, one panel per friction (PNG)")
    p.add_argument("--include-unfinished", action="store_true",
                   help="also classify runs whose status is not 'completed'")
    p.add_argument("--overwrite", action="store_true",
                   help="replace existing output files (never an input: a run file or a --previous CSV)")
    args = p.parse_args(argv)
    if not args.paths and not args.previous:
        p.error("give run files, directories, or --previous CSV")
    files = []
    for entry in map(Path, args.paths):
        if entry.is_dir():
            # A scan directory also holds its strip-kernel cache (kernel_cache/) and its summary table
            # (summary.h5), not runs.
            from .scan.summary import SUMMARY_H5
            found = sorted(f for f in entry.rglob("*.h5") if "kernel_cache" not in f.relative_to(entry).parts
                           and f.name != SUMMARY_H5)
            if not found:
                print(f"transition: '{entry}' holds no run files (*.h5): give run files written by `slipstrip run` "
                      "or the directory of a `slipstrip scan`", file=sys.stderr)
                return 2
            files += found
            continue
        try:  # a path given by name must be a run file (one line saying what it is instead)
            runfile.open_h5(entry).close()
        except runfile.RunFileError as err:
            print(f"transition: {err}", file=sys.stderr)
            return 2
        files.append(entry)
    for path in files:
        try:
            runfile.require_line(path, "transition", "classifies the long-time state of a one-dimensional "
                                 "interface (the paper's states); use analyze for a 2D interface")
        except runfile.RunFileError:
            continue  # not a run file: reported below as unreadable, as before
        except ValueError as err:
            print(f"transition: {one_line(err)}", file=sys.stderr)
            return 2
    n_found = len(files)
    outputs = {"--csv": args.csv, "--plot": args.plot, "--table": args.table, "--collapse": args.collapse,
               "--heights": args.heights, "--thin-edges": args.thin_edges, "--plane": args.plane}
    try:
        check_outputs(outputs, inputs=[*files, *args.previous], overwrite=args.overwrite)
    except OutputPathError as err:
        print(f"transition: {err}", file=sys.stderr)
        return 2
    if not args.include_unfinished:
        # A running or interrupted run is a shorter record than its config says:
        # its state would be judged on the wrong window.  Listed, not classified.
        finished = []
        for path in files:
            try:
                status = _run_parameters(path)["status"]
            except (OSError, KeyError, ValueError) as err:
                status = f"unreadable ({err})"
            if status == "completed":
                finished.append(path)
            else:
                print(f"{path.name:40s} skipped: status {status} (--include-unfinished to classify it)")
        files = finished
    rows = longest_run_per_cell(classify_directory(files))
    add_critical_lengths(rows)
    fresh = {_map_cell(r) for r in rows if "f0" in r}
    previous = []
    for csv_path in args.previous:
        try:
            earlier = read_map_csv(csv_path)
        except (OSError, KeyError, ValueError) as err:
            print(f"error: --previous {one_line(f'{csv_path}: {err}')}", file=sys.stderr)
            return 2
        previous += [r for r in earlier if _map_cell(r) not in fresh]
    # Two earlier maps may hold the same run (one of them extended): keep one row per run, as for fresh runs.
    previous = longest_run_per_cell(previous)
    for r in rows:
        if r["state"] == "unreadable":
            print(f"{Path(r['file']).name:40s} not classified: {r['error']}", file=sys.stderr)
            continue
        print(f"{Path(r['file']).name:40s} seed {noise_seed(r):<3d} H/L = {r['height'] / r['length']:<8.4g} "
              f"|df/dlnv| = {r['rate_weakening']:.4f}  Lc(H) = {r['critical_length']:<7.3g} {r['state']:18s} "
              f"{'converged' if r['converged'] else 'NOT converged'}  agreement {r['agreement']:.2f}")
    if previous:
        print(f"{len(previous)} rows from {', '.join(args.previous)} (classified earlier)")
    elif not any(r["state"] != "unreadable" for r in rows):
        # Nothing to map: say why instead of writing empty tables and figures.
        unreadable = sum(r["state"] == "unreadable" for r in rows)
        print(f"transition: no run classified: of {n_found} run files, {n_found - len(rows)} are not completed "
              f"(listed above; --include-unfinished classifies them) and {unreadable} could not be read",
              file=sys.stderr)
        return 1
    rows = previous + rows
    if args.csv:
        keys = sorted({k for r in rows for k in r})
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=keys)
            w.writeheader()
            # Directory/name only: the CSV is committed next to the docs, and an
            # absolute path would name one machine's run directory.
            w.writerows({**r, "file": f"{Path(r['file']).parent.name}/{Path(r['file']).name}"} for r in rows)
    if args.plot:
        plot_map(rows, args.plot)
    stars = transition_heights(rows)
    if args.table:
        Path(args.table).write_text(state_grid_markdown(rows) + "\n**Transition heights** (last upward crossing of "
                                    f"{SPANNING_COHERENT:g} by the spanning-slip fraction as H grows, "
                                    "`transition_heights`):\n\n" + transition_heights_markdown(stars) +
                                    "\n**Thin-strip edges** (thinnest complex strip and the next thinner one run, "
                                    "`thin_edges`):\n\n" + thin_edges_markdown(thin_edges(rows)))
    if args.collapse:
        plot_collapse(rows, args.collapse)
    for t in stars:
        print(f"|df/dlnv| = {t['rate_weakening']:.4f}  L = {t['length']:g} m: H* = {t['height']:.3g} m "
              f"(between {t['height_bracket'][0]:g} and {t['height_bracket'][1]:g}; over seeds "
              f"{t['height_range'][0]:.3g}-{t['height_range'][1]:.3g}); "
              f"H*/L = {t['height_over_length']:.3g} ({t['height_over_length_bracket'][0]:.3g}-"
              f"{t['height_over_length_bracket'][1]:.3g}); H*/Lc(H*) = {t['height_over_critical_length']:.3g} "
              f"({t['height_over_critical_length_bracket'][0]:.3g}-{t['height_over_critical_length_bracket'][1]:.3g})")
    edges = thin_edges(rows)
    for e in edges:
        below = (f"not complex at H = {e['height_not_complex']:g} m ({e['states_not_complex']}"
                 f"{'' if e['converged_not_complex'] else ', not converged'})"
                 if math.isfinite(e["height_not_complex"]) else "no thinner strip run")
        print(f"|df/dlnv| = {e['rate_weakening']:.4f}  L = {e['length']:g} m: thinnest complex strip "
              f"H = {e['height_complex']:g} m (Lc/H = {e['critical_over_height_complex']:.3g}"
              f"{'' if e['converged_complex'] else ', not converged'}); {below}")
    if args.thin_edges:
        with open(args.thin_edges, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=THIN_EDGE_COLUMNS)
            w.writeheader()
            w.writerows(edges)
    if args.plane:
        plot_length_height(rows, args.plane)
    if args.heights:
        with open(args.heights, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["rate_weakening", "length", "height_star", "height_low", "height_high", "height_star_over_length",
                        "critical_length_at_height_star", "height_star_over_critical_length",
                        "height_over_critical_length_low", "height_over_critical_length_high",
                        "height_star_min_over_seeds", "height_star_max_over_seeds", "seeds_at_height_low",
                        "seeds_at_height_high", "seed_picks", "seed_picks_without_crossing"])
            for t in stars:
                w.writerow([t["rate_weakening"], t["length"], t["height"], *t["height_bracket"], t["height_over_length"],
                            t["critical_length"], t["height_over_critical_length"],
                            *t["height_over_critical_length_bracket"], *t["height_range"], *t["seeds_at_bracket"],
                            t["seed_picks"], t["picks_without_crossing"]])
    return 0
