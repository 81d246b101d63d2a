"""slipstrip against the independent volume solver for two different bodies
(docs/benchmarks/volume_bodies.md): the strip_pulse problem with a different bottom
body, in-plane (configs/benchmarks/strip_pulse_bimaterial.toml: the normal stress
changes, Prakash-Clifton effective normal stress) and antiplane
(configs/benchmarks/strip_pulse_antiplane.toml).

slipstrip runs at N nodes (beta = 0.25) and the volume solver at nx = L/h cells
with dt = (N/nx) slipstrip's step, so every volume step is a slipstrip step.  The
differences at the stations are reported per field (max over time), with the
rms difference of log10(slip rate / v0) over the whole run:

    /usr/bin/python3 tools/volume_solver/bodies_crosscheck.py --nodes 640 --nx 160 320 640 \
        --json docs/benchmarks/volume_bodies/measured.json
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(HERE))
from volume import read_config, run_volume  # noqa: E402

CASES = {
    "bimaterial": REPO / "configs" / "benchmarks" / "strip_pulse_bimaterial.toml",
    "antiplane": REPO / "configs" / "benchmarks" / "strip_pulse_antiplane.toml",
}
STATIONS = [0.5, 0.625, 0.75, 0.875, 0.0]
FIELDS = ["slip", "slip_rate", "shear_stress", "normal_stress"]


def slipstrip_series(config, nodes: int, stations, duration: float | None = None, beta: float = 0.25) -> dict:
    """slipstrip's station series at every step (N = nodes)."""
    import slipstrip as ss

    sim = ss.Simulation(str(config), {"geometry.nodes": nodes, "time.beta": beta})
    idx = [int(round(s / sim.dx)) % nodes for s in stations]
    if duration is None:
        duration = ss.load_config(str(config)).duration
    n = int(round(duration / sim.time_step))
    inplane_pair = np.asarray(sim.normal_stress).size > 0
    sigma0 = ss.load_config(str(config)).normal_stress
    views = {"slip": lambda: sim.slip, "slip_rate": lambda: sim.slip_rate, "shear_stress": lambda: sim.shear_stress,
             "normal_stress": (lambda: sim.normal_stress) if inplane_pair else (lambda: np.full(nodes, sigma0))}
    out = {f: np.empty((n + 1, len(idx))) for f in views}
    for k in range(n + 1):
        if k:
            sim.step()
        for f, v in views.items():
            out[f][k] = np.asarray(v())[idx]
    out["time"] = np.arange(n + 1) * sim.time_step
    out["dt"] = sim.time_step
    out["nodes"] = nodes
    return out


def volume_series(config, nx: int, bim: dict, stations) -> dict:
    """The volume solver at nx cells, its step = (N/nx) slipstrip steps."""
    cfg = read_config(config)
    stride = bim["nodes"] // nx
    if stride * nx != bim["nodes"]:
        raise ValueError(f"nodes = {bim['nodes']} is not a multiple of nx = {nx}")
    dt = stride * bim["dt"]
    n_vol = (bim["time"].size - 1) // stride  # whole volume steps within slipstrip's run
    r = run_volume(cfg, nx, stations, dt=dt, duration=n_vol * dt)
    if not np.allclose(bim["time"][: n_vol * stride + 1: stride], r["time"], rtol=0, atol=1e-6 * bim["dt"]):
        raise RuntimeError("volume and slipstrip times differ")
    r["stride"] = stride
    return r


def differences(bim: dict, vol: dict, v0: float) -> dict:
    s, m = vol["stride"], vol["time"].size
    d = {f: np.abs(vol[f] - bim[f][: m * s: s]).max(axis=0).tolist() for f in FIELDS}
    lv = lambda v: np.log10(np.maximum(np.abs(v), 1e-3 * v0) / v0)  # noqa: E731  (stuck: 1e-3 v0)
    d["log10_slip_rate_rms"] = np.sqrt(np.mean((lv(vol["slip_rate"]) - lv(bim["slip_rate"][: m * s: s])) ** 2,
                                               axis=0)).tolist()
    return d


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--case", nargs="+", default=list(CASES), choices=list(CASES))
    ap.add_argument("--nodes", type=int, default=640)
    ap.add_argument("--nx", type=int, nargs="+", default=[160, 320, 640])
    ap.add_argument("--reference-nodes", type=int, default=0,
                    help="also run slipstrip at this N and report its own difference from --nodes")
    ap.add_argument("--reference-beta", type=float, default=0.125,
                    help="beta of that run (an in-plane pair at N = 1280 needs < 0.25 for its passive operators)")
    ap.add_argument("--coarse-nodes", type=int, default=0,
                    help="also run slipstrip at this N < --nodes (same beta): |N_coarse - N| / 3 estimates "
                         "slipstrip's own error at N (second order, Richardson)")
    ap.add_argument("--duration-transits", type=float, help="run length in L/c_s of the top body "
                    "(default: the config's)")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    result = {"stations": STATIONS, "nodes": a.nodes, "beta": 0.25, "nx": a.nx,
              "duration_transits": a.duration_transits, "command": " ".join(["bodies_crosscheck.py"] + argv),
              "cases": {}}
    for case in a.case:
        config = CASES[case]
        v0 = read_config(config)["driving_velocity"]
        t0 = time.perf_counter()
        cfg = read_config(config)
        duration = a.duration_transits * cfg["length"] / cfg["shear_wave_speed"] if a.duration_transits else None
        bim = slipstrip_series(config, a.nodes, STATIONS, duration)
        entry = {"config": str(config.relative_to(REPO)), "slipstrip_wall_seconds": time.perf_counter() - t0,
                 "duration": float(bim["time"][-1]),
                 "peak_slip_rate_over_v0": (bim["slip_rate"].max(axis=0) / v0).tolist(),
                 "normal_stress_range": [float(bim["normal_stress"].min()), float(bim["normal_stress"].max())],
                 "volume": {}}
        for nx in a.nx:
            vol = volume_series(config, nx, bim, STATIONS)
            entry["volume"][str(nx)] = {**differences(bim, vol, v0), "wall_seconds": vol["wall_seconds"]}
            print(case, nx, {k: np.round(np.max(v), 6) for k, v in entry["volume"][str(nx)].items()}, flush=True)
        if a.reference_nodes:
            ref = slipstrip_series(config, a.reference_nodes, STATIONS, duration, a.reference_beta)
            s = int(round(bim["dt"] / ref["dt"]))
            m = min(bim["time"].size, (ref["time"].size - 1) // s + 1)
            if not np.allclose(ref["time"][: m * s: s], bim["time"][:m], rtol=0, atol=1e-6 * ref["dt"]):
                raise RuntimeError("reference and slipstrip times differ")
            entry["slipstrip_vs_reference"] = {
                "reference_nodes": a.reference_nodes, "reference_beta": a.reference_beta,
                **{f: np.abs(ref[f][: m * s: s] - bim[f][:m]).max(axis=0).tolist() for f in FIELDS}}
            print(case, "slipstrip", a.nodes, "vs", a.reference_nodes,
                  {f: np.max(entry["slipstrip_vs_reference"][f]) for f in FIELDS}, flush=True)
        if a.coarse_nodes:
            coarse = slipstrip_series(config, a.coarse_nodes, STATIONS, duration)
            s = int(round(coarse["dt"] / bim["dt"]))
            m = min(coarse["time"].size, (bim["time"].size - 1) // s + 1)
            if not np.allclose(bim["time"][: m * s: s], coarse["time"][:m], rtol=0, atol=1e-6 * bim["dt"]):
                raise RuntimeError("coarse and slipstrip times differ")
            entry["slipstrip_vs_coarse"] = {
                "coarse_nodes": a.coarse_nodes,
                **{f: np.abs(coarse[f][:m] - bim[f][: m * s: s]).max(axis=0).tolist() for f in FIELDS}}
            print(case, "slipstrip", a.nodes, "vs", a.coarse_nodes,
                  {f: np.max(entry["slipstrip_vs_coarse"][f]) for f in FIELDS}, flush=True)
        result["cases"][case] = entry
    if a.json:
        Path(a.json).write_text(json.dumps(result, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
