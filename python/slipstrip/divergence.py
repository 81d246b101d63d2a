"""`python3 -m slipstrip trajectory-divergence`: how long two runs of the same
case stay on the same trajectory.

    python3 -m slipstrip trajectory-divergence A.h5 B.h5 [A2.h5 B2.h5 ...] [--json OUT.json] [--plot OUT.png]

For a refinement study (docs/fig5_resolution.md): A and B differ in mesh (N_B a
multiple of N_A, or the other way round) or time step, and start from the same
field (band-limited noise, `[initial] noise_modes`).  Per common snapshot time
it gives the rms over the coarse nodes of log10(v_A/v_B) (slip rates floored at
1e-3 v0, as in the space-time plots), and the first times that rms exceeds
0.01, 0.1 and 0.3 (2 %, 26 % and a factor of 2 in slip rate).  Before the
first, the two discretisations compute the same solution; after the last, the
runs are different trajectories of a chaotic system and can be compared only
statistically.
"""
from __future__ import annotations

import argparse
import json
import os
import sys

import numpy as np

from . import analysis as an
from . import runfile
from .paths import OutputPathError, check_outputs, one_line

THRESHOLDS = (0.01, 0.1, 0.3)
SAMPLE_TRANSITS = (10.0, 20.0, 30.0, 40.0)  # times [L/c_s] at which the rms is also reported
JSON_SERIES_POINTS = 500


def log_rate_divergence(t_a, v_a, t_b, v_b, v0: float) -> tuple[np.ndarray, np.ndarray]:
    """(times, rms log10 ratio) at the snapshot times the two records share.

    v_a, v_b are [snapshots, nodes]; the finer record is sampled at the coarse
    nodes (node i of N sits at node r i of r N).  Times match when they differ
    by less than a quarter of the smaller snapshot spacing."""
    t_a, t_b = np.asarray(t_a, float), np.asarray(t_b, float)
    v_a, v_b = np.abs(np.asarray(v_a, float)), np.abs(np.asarray(v_b, float))
    n_a, n_b = v_a.shape[1], v_b.shape[1]
    if max(n_a, n_b) % min(n_a, n_b):
        raise ValueError(f"node counts {n_a} and {n_b}: one must be a multiple of the other")
    if n_a > n_b:
        v_a = v_a[:, :: n_a // n_b]
    else:
        v_b = v_b[:, :: n_b // n_a]
    if t_a.size < 2 or t_b.size < 2:
        raise ValueError("each record needs at least two snapshots")
    spacing = min(np.min(np.diff(t_a)), np.min(np.diff(t_b)))
    j = np.searchsorted(t_b, t_a).clip(1, t_b.size - 1)  # t_b[j - 1] <= t_a < t_b[j], at the ends clipped
    j = np.where(t_a - t_b[j - 1] <= t_b[j] - t_a, j - 1, j)  # the nearer neighbour
    match = np.abs(t_b[j] - t_a) < 0.25 * spacing
    floor = 1e-3 * v0
    za = np.log10(np.maximum(v_a[match], floor))
    zb = np.log10(np.maximum(v_b[j[match]], floor))
    return t_a[match], np.sqrt(np.mean((za - zb) ** 2, axis=1))


def first_exceedance(times: np.ndarray, rms: np.ndarray, threshold: float) -> float | None:
    above = np.nonzero(rms > threshold)[0]
    return float(times[above[0]]) if above.size else None


def divergence_summary(path_a: str, path_b: str) -> dict:
    info = an.read_run_info(path_a)
    records = [an.read_spacetime(p) for p in (path_a, path_b)]
    for p, r in zip((path_a, path_b), records):
        if r is None:
            raise ValueError(f"{p}: no snapshots, nothing to compare")
    (t_a, _, v_a), (t_b, _, v_b) = records
    times, rms = log_rate_divergence(t_a, v_a, t_b, v_b, info.v0)
    transit = info.L / info.c_s
    firsts = {f"{thr:g}": first_exceedance(times, rms, thr) for thr in THRESHOLDS}
    return {
        "runs": [os.path.basename(path_a), os.path.basename(path_b)],  # no machine paths
        "nodes": [int(v_a.shape[1]), int(v_b.shape[1])],
        "common_snapshots": int(times.size),
        "first_exceedance_transits": {k: (None if v is None else v / transit) for k, v in firsts.items()},
        # Before the chaotic growth takes over, this is the size of the discretisation difference.
        "rms_at_transits": {f"{at:g}": float(rms[np.argmin(np.abs(times / transit - at))])
                            for at in SAMPLE_TRANSITS if times.size and times[-1] / transit >= at},
        "time_transits": (times / transit).tolist(),
        "rms_log10_ratio": rms.tolist(),
    }


def _rms_samples(summary: dict) -> str:
    """The rms at the sample times the pair reaches; a pair shorter than the
    first sample time reports its last common snapshot instead of nothing."""
    at = summary["rms_at_transits"]
    if at:
        return f"; rms at t = {', '.join(at)} L/c_s: " + ", ".join(f"{v:.1e}" for v in at.values())
    if not summary["time_transits"]:
        return ""
    return (f"; rms at the last common snapshot, t = {summary['time_transits'][-1]:.2f} L/c_s: "
            f"{summary['rms_log10_ratio'][-1]:.1e}")


def plot(summaries: list[dict], out: str) -> None:
    from .plots import plt
    fig, ax = plt.subplots(figsize=(5.2, 3.4))
    try:
        for s in summaries:
            ax.semilogy(s["time_transits"], np.maximum(s["rms_log10_ratio"], 1e-17),
                        label=f"{s['runs'][0]} vs {s['runs'][1]}", lw=1)
        for thr in THRESHOLDS:
            ax.axhline(thr, color="0.6", lw=0.6, ls=":")
        ax.set_xlabel(r"$t c_s / L$")
        ax.set_ylabel(r"rms $\log_{10}(v_A / v_B)$")
        ax.legend(fontsize=6)
        fig.tight_layout()
        fig.savefig(out, dpi=110)
    finally:
        plt.close(fig)


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(prog="python3 -m slipstrip trajectory-divergence",
                                description=__doc__.split("\n\n", 2)[2].strip(),
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("runs", nargs="+", help="pairs of run files: A1 B1 [A2 B2 ...]")
    p.add_argument("--json", help="one JSON file (a list, one entry per pair)")
    p.add_argument("--plot", help="rms log10(v_A/v_B) against time, one line per pair (PNG)")
    p.add_argument("--overwrite", action="store_true", help="replace existing --json / --plot files")
    a = p.parse_args(argv)
    if len(a.runs) % 2:
        p.error("give the run files in pairs: A1 B1 [A2 B2 ...]")
    outputs = {k: v for k, v in (("--json", a.json), ("--plot", a.plot)) if v}
    try:
        check_outputs(outputs, inputs=list(a.runs), overwrite=a.overwrite)
    except OutputPathError as err:
        print(f"trajectory-divergence: {err}", file=sys.stderr)
        return 2
    try:
        for run in a.runs:
            runfile.require_line(run, "trajectory-divergence", "compares the space-time fields of "
                                 "one-dimensional interfaces only")
        summaries = [divergence_summary(x, y) for x, y in zip(a.runs[::2], a.runs[1::2])]
    except (ValueError, OSError, KeyError) as err:
        print(f"trajectory-divergence: {one_line(err)}", file=sys.stderr)
        return 2
    for s in summaries:
        f = s["first_exceedance_transits"]
        print(f"{s['runs'][0]} (N = {s['nodes'][0]}) vs {s['runs'][1]} (N = {s['nodes'][1]}): "
              f"{s['common_snapshots']} common snapshots; rms log10 ratio first above "
              + ", ".join(f"{k} at {'never' if v is None else f'{v:.1f} L/c_s'}" for k, v in f.items())
              + _rms_samples(s))
    if a.json:
        # The series are thinned to <= JSON_SERIES_POINTS points (evenly strided): the
        # JSON is a record for the docs; the plot uses every common snapshot.
        thinned = []
        for s in summaries:
            stride = max(1, -(-len(s["time_transits"]) // JSON_SERIES_POINTS))
            thinned.append({**s, "series_stride": stride, "time_transits": s["time_transits"][::stride],
                            "rms_log10_ratio": s["rms_log10_ratio"][::stride]})
        with open(a.json, "w") as fh:
            json.dump(thinned, fh, indent=1)
            fh.write("\n")
    if a.plot:
        plot(summaries, a.plot)
    return 0

