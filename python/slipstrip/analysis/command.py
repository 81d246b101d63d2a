"""`python3 -m slipstrip analyze`: statistics, criteria and figures of one run
file, written into an output directory with summary.json; and the headline
numbers of one run for the parameter scan (summarize_run)."""
from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import sys
from pathlib import Path

import h5py
import numpy as np

from ..paths import OutputPathError, check_outputs, one_line
from ..runfile import open_h5, unreadable_reason
from .criteria import group_nodal_slips, periodic_pulse_of_run
from .figures import (plot_event_fields, plot_event_map, plot_event_maps, plot_hypocentres, plot_pdf_comparison,
                      plot_pdfs, plot_space_slip, plot_space_time, plot_space_time_2d)
from .reading import DEFAULT_ALPHA, RunInfo, _read_crossing_time, catalog_file_name, catalog_for, read_run_info
from .statistics import _public, catalog_statistics, stationarity, stationary_part


SENSITIVITY_ALPHAS = (8.0, 15.0, 30.0, 60.0)


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
            sensitivity_alphas=SENSITIVITY_ALPHAS, seed: int = 0, write_events: bool = False,
            min_slip_rate_v0: float = 0.0) -> dict:
    """Everything: statistics, stationarity, threshold sensitivity, figures, summary.json.
    min_slip_rate_v0 > 0 ignores the nodal slips slower than that many v0 in
    every catalog (the sensitivity's too), as `slipstrip events --min-slip-rate`."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    info = read_run_info(path)
    catalog = catalog_for(path, alpha, workdir=out_dir, write_into_run=write_events,
                          min_slip_rate_v0=min_slip_rate_v0)
    if len(catalog["t_start"]) == 0:
        raise EmptyCatalog(f"{path}: {empty_catalog_reason(catalog['attrs'], info, alpha)}")
    st = catalog_statistics(catalog, info, seed=seed)
    plane = info.interface_2d
    # A line's moment is per unit width (M0 = mu L_s u_mean [N/m]); a 2D
    # interface's is a moment (M0 = mu A u_mean [N m]) and A an area [m^2].
    normalisation = ({"u": "u_mean/D", "T": "T*v0/D", "M0": "M0/(mu*D*L*W)", "A": "A/(L*W)"} if plane
                     else {"u": "u_mean/D", "T": "T*v0/D", "M0": "M0/(mu*D*L)"})
    summary = {"run": str(path), "alpha": float(alpha), "min_slip_rate_v0": float(min_slip_rate_v0),
               "interface": "2d" if plane else "line",
               "normalisation": normalisation,
               "moment_units": "N m (mu A u_mean)" if plane else "N/m (mu L_s u_mean, per unit width)",
               "scales": dataclasses.asdict(info)}
    summary.update(_public(st))
    summary["catalog_counts"] = {k: catalog["attrs"].get(k) for k in (
        "n_nodal_slips", "n_nodal_slips_below_min_slip_rate", "n_events_detected", "n_events_excluded_first_last", "n_events_below_thresholds",
        "n_events")}
    with open_h5(path) as f:
        has_snap = "snapshots" in f and f["snapshots/time"].shape[0] > 0
        has_ss = "slip_sampling" in f
    if plane:
        summary.update({"periodic_pulse": None, "periodic_pulse_basis": "not applicable: the paper's pulse "
                        "criteria (docs/analysis.md) are those of a one-dimensional interface"})
    else:
        summary.update(periodic_pulse_of_run(path, catalog, info))
    summary["stationarity"] = stationarity(catalog, info)
    kept = stationary_part(catalog, info)
    summary["transient_cut"] = kept["cut"]
    summary["stationarity_after_cut"] = dict(kept["stationarity"], stationary=kept["stationary"])

    sens = {}
    catalogs_by_alpha = {}
    for a in sensitivity_alphas:
        cat_a = (catalog if float(a) == float(alpha)
                 else catalog_for(path, a, workdir=out_dir, min_slip_rate_v0=min_slip_rate_v0))
        catalogs_by_alpha[f"alpha={a:g}"] = cat_a
        st_a = catalog_statistics(cat_a, info, n_bootstrap=0)
        sens[f"{a:g}"] = {k: st_a[k] for k in ("n_events", "small_exponent_u", "small_exponent_u_err",
                                                "small_exponent_T", "small_exponent_M0")}
    summary["threshold_sensitivity"] = sens

    figures = []
    if plane:
        figures += plot_hypocentres(catalog, info, out_dir, pdf)
    if has_snap and plane:
        figures += plot_space_time_2d(path, info, out_dir, pdf)
    if has_snap and not plane:
        figures += plot_space_time(path, info, out_dir, pdf)
    if has_ss and not plane:
        ct, x = _read_crossing_time(path)
        figures += plot_space_slip(ct, x, info, out_dir, pdf)
        groups = group_nodal_slips(ct, info.delta_th, info.v0, alpha,
                                   catalog["attrs"].get("min_extent_dx", 2.0),
                                   catalog["attrs"].get("min_mean_slip_dth", 2.0),
                                   bool(catalog["attrs"].get("exclude_first_last", 1)),
                                   float(catalog["attrs"].get("min_slip_rate_v0", 0.0)))
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
        paths, times = (plot_event_maps if plane else plot_event_fields)(path, catalog, index, info, out_dir, pdf)
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
    from .. import _slipstrip
    counts = dict(attrs)
    counts.setdefault("alpha", float(alpha))
    counts.setdefault("delta_th", info.delta_th)
    counts.setdefault("v0", info.v0)
    return _slipstrip.empty_catalog_reason(counts, run_duration=info.duration) + "; nothing to analyse"


def format_summary(s: dict) -> str:
    def f(v, fmt=".3g"):
        return "nan" if v is None else format(v, fmt)
    # The moment's normalisation: per unit width on a line, per area on a 2D interface.
    moment = s.get("normalisation", {}).get("M0", "M0/(mu*D*L)").replace("*", " ")
    lines = [
        f"run: {s['run']}  (alpha = {s['alpha']:g}"
        + (f", nodal slips slower than {s['min_slip_rate_v0']:g} v0 ignored" if s.get("min_slip_rate_v0") else "")
        + ")",
        f"events: {s['n_events']} ({s['n_events_small']} small u<D, {s['n_events_large']} large)",
        f"small-event exponent p(u/D) ~ x^-a: a = {f(s['small_exponent_u'])} +- {f(s['small_exponent_u_err'])}"
        f" (bootstrap {f(s.get('small_exponent_u_bootstrap_err'))}, xmin = {f(s['small_exponent_u_xmin'])},"
        f" n = {s['small_exponent_u_n']})",
        f"  T v0/D: a = {f(s['small_exponent_T'])} +- {f(s['small_exponent_T_err'])};"
        f"  {moment}: a = {f(s['small_exponent_M0'])} +- {f(s['small_exponent_M0_err'])}"
        + (f";  A/(L W): a = {f(s['small_exponent_A'])} +- {f(s['small_exponent_A_err'])}" if "small_exponent_A" in s
           else ""),
        f"large events, log-normal of T v0/D: mu = {f(s['lognormal_mu'])}, sigma = {f(s['lognormal_sigma'])},"
        f" KS = {f(s['lognormal_ks'])}, p = {f(s['lognormal_ks_pvalue'])} (naive {f(s['lognormal_ks_pvalue_naive'])})",
        f"slip fraction: small events {f(s['slip_fraction_small'])}, system-spanning {f(s['slip_fraction_spanning'])}",
        f"periodic pulse: {s['periodic_pulse'] if s['periodic_pulse'] is not None else s['periodic_pulse_basis']}",
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
FIGURE_NAMES = ("space_time", "space_slip", "event_map", "pdfs", "stationarity", "threshold_sensitivity",
                "hypocentres")


def analysis_outputs(out_dir, alpha: float = DEFAULT_ALPHA, pdf: bool = False,
                     sensitivity_alphas=SENSITIVITY_ALPHAS, min_slip_rate_v0: float = 0.0) -> dict[str, Path]:
    """The files analyze() writes into out_dir under fixed names, as
    {"--out-dir NAME": path}, for the output-path check (slipstrip.paths)."""
    out_dir = Path(out_dir)
    names = ["summary.json"] + [f"{n}.png" for n in FIGURE_NAMES] + ([f"{n}.pdf" for n in FIGURE_NAMES] if pdf else [])
    names += [catalog_file_name(a, min_slip_rate_v0) for a in dict.fromkeys([alpha, *sensitivity_alphas])]
    return {f"--out-dir {name}": out_dir / name for name in names}


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="slipstrip analyze",
                                     description="Slip-event statistics and figures of one run file")
    parser.add_argument("run", help="run file (HDF5, docs/output.md)")
    parser.add_argument("--out-dir", default=None, help="output directory (default: <run>_analysis)")
    parser.add_argument("--pdf", action="store_true", help="also write PDF figures")
    parser.add_argument("--alpha", type=float, default=DEFAULT_ALPHA, help="waiting-time threshold factor")
    parser.add_argument("--min-slip-rate", type=float, default=0.0, dest="min_slip_rate",
                        help="ignore nodal slips slower than this many v0 (creep); 0 keeps all (docs/events.md)")
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
    if not (math.isfinite(args.min_slip_rate) and args.min_slip_rate >= 0):
        print(f"analyze: --min-slip-rate {args.min_slip_rate} is invalid: must be a finite number >= 0 "
              "(nodal slip rate in units of v0; 0 keeps every nodal slip)", file=sys.stderr)
        return 2
    if not (Path(args.run).is_file() and h5py.is_hdf5(args.run)):
        print(f"analyze: {unreadable_reason(args.run)}", file=sys.stderr)
        return 2
    out_dir = args.out_dir or str(Path(args.run).with_suffix("")) + "_analysis"
    try:
        check_outputs(analysis_outputs(out_dir, args.alpha, args.pdf, min_slip_rate_v0=args.min_slip_rate),
                      directories={"--out-dir": out_dir},
                      inputs=[args.run], overwrite=args.overwrite)
    except OutputPathError as err:
        print(f"analyze: {err}", file=sys.stderr)
        return 2
    try:
        summary = analyze(args.run, out_dir, pdf=args.pdf, alpha=args.alpha, event=args.event,
                          write_events=args.write_events, min_slip_rate_v0=args.min_slip_rate)
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
