"""Python driver of the independent volume solver `slipstrip_volume`.

The solver itself is tools/volume_solver/volume_solver.cpp (a staggered-grid
finite-difference scheme of one elastic strip; see docs/benchmarks/volume_solver.md).
This module reads a slipstrip TOML config with the standard library's tomllib
(not with slipstrip's config code: the oracle shares only the friction law with
the product), turns it into the solver's key=value arguments, runs it and
returns the station time series as NumPy arrays.

    from volume import run_volume
    r = run_volume("configs/benchmarks/bp_pulse.toml", nx=320, stations=[0.5, 0.75])
    r["time"], r["slip_rate"][:, 0]          # [s], [m/s] at x = 0.5 m

The executable is looked up in $SLIPSTRIP_VOLUME_BIN, then
$SLIPSTRIP_BUILD_DIR/tools/volume_solver/, then <repo>/build*/tools/volume_solver/
(newest first).  Build it with `cmake --build build --target slipstrip_volume`.
"""
from __future__ import annotations

import math
import os
import subprocess
import tempfile
import tomllib
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
EXE_NAME = "slipstrip_volume"


def find_executable() -> Path | None:
    explicit = os.environ.get("SLIPSTRIP_VOLUME_BIN")
    if explicit:
        return Path(explicit)
    dirs = []
    if os.environ.get("SLIPSTRIP_BUILD_DIR"):
        dirs.append(Path(os.environ["SLIPSTRIP_BUILD_DIR"]))
    dirs.append(REPO / "build")
    dirs += sorted(REPO.glob("build*/"), key=lambda d: d.stat().st_mtime, reverse=True)
    for d in dirs:
        exe = d / "tools" / "volume_solver" / EXE_NAME
        if exe.is_file():
            return exe
    return None


def read_config(path) -> dict:
    """The benchmark config as plain numbers (SI), resolved as docs/config.md says:
    shear_modulus from youngs_modulus if given, duration from duration_transits."""
    with open(path, "rb") as f:
        c = tomllib.load(f)
    g, m, lo = c.get("geometry", {}), c.get("material", {}), c.get("loading", {})
    fr, st = c.get("friction", {}), c.get("state", {})
    it, ini, tm = c.get("interface", {}), c.get("initial", {}), c.get("time", {})
    nu = m.get("poisson_ratio", 0.33)
    mu = m["shear_modulus"] if "shear_modulus" in m else (
        m["youngs_modulus"] / (2 * (1 + nu)) if "youngs_modulus" in m else 9e9)
    rho = m.get("density", 1200.0)
    L = g.get("length", 4.0)
    cs = math.sqrt(mu / rho)
    if "duration_transits" in tm:
        duration = tm["duration_transits"] * L / cs
    else:
        duration = tm.get("duration", 1e-3)
    if it.get("law", "rate_and_state") != "rate_and_state":
        raise ValueError("the volume solver implements interface.law = rate_and_state only")
    if ini.get("noise_amplitude", 0.0) or ini.get("sine_amplitude", 0.0):
        raise ValueError("the volume solver implements [initial] local_* perturbations only")
    if it.get("load_pulse_amplitude", 0.0) and it.get("profile", "ramp") != "bump":
        raise ValueError("the volume solver implements the sin^4 'bump' load pulse only")
    return {
        "length": L, "height": g.get("height", 0.1),
        "shear_modulus": mu, "poisson_ratio": nu, "density": rho,
        "plane": m.get("plane", "strain"),
        "driving_velocity": lo.get("driving_velocity", 2e-3),
        "normal_stress": lo.get("normal_stress", 1e6),
        "law": fr.get("law", "paper"), "f0": fr.get("f0", 0.28), "a": fr.get("a", 0.005),
        "b": fr.get("b", 0.075), "characteristic_slip": fr.get("characteristic_slip", 5e-7),
        "v_star": fr.get("v_star", 1e-7), "phi_star": fr.get("phi_star", 3.3e-4),
        "state_law": st.get("law", "aging"),
        "load_pulse_amplitude": it.get("load_pulse_amplitude", 0.0),
        "pulse_center": it.get("pulse_center", 0.0),
        "pulse_width": it.get("pulse_width", math.inf),
        "rise_time": it.get("rise_time", 1e-4),
        "local_amplitude": ini.get("local_amplitude", 0.0),
        "local_center": ini.get("local_center", 0.0),
        "local_width": ini.get("local_width", 0.0),
        "duration": duration,
        "shear_wave_speed": cs,
    }


def run_volume(config, nx: int, stations, *, dt: float | None = None, cfl: float | None = None,
               duration: float | None = None, output_every: int = 1, exe=None,
               final_profile: bool = False) -> dict:
    """Run slipstrip_volume on `config` (a TOML path or a read_config() dict).

    nx: cells along the period (h = L/nx; H/h must be whole).  dt: time step [s]
    (default: cfl h / c_d with cfl = 0.5).  Returns a dict: time [nt], and
    slip, slip_rate, shear_stress, state [nt, n_stations]; `wall_seconds`; with
    final_profile, `profile` = dict of x, slip, slip_rate, shear_stress, state at the end."""
    p = dict(config) if isinstance(config, dict) else read_config(config)
    if duration is not None:
        p["duration"] = duration
    exe = Path(exe) if exe else find_executable()
    if exe is None or not exe.is_file():
        raise FileNotFoundError(f"{EXE_NAME} not built: cmake --build build --target {EXE_NAME}")
    p.pop("shear_wave_speed", None)
    p["nx"] = int(nx)
    if dt is not None:
        p["dt"] = dt
    if cfl is not None:
        p["cfl"] = cfl
    p["stations"] = ",".join(repr(float(s)) for s in stations)
    p["output_every"] = int(output_every)
    import time
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "stations.txt"
        prof = Path(tmp) / "profile.txt"
        p["out"] = str(out)
        if final_profile:
            p["final_profile"] = str(prof)
        args = [str(exe)] + [f"{k}={v!r}" if isinstance(v, float) else f"{k}={v}"
                             for k, v in p.items()]
        t0 = time.perf_counter()
        proc = subprocess.run(args, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if proc.returncode != 0:
            raise RuntimeError(f"{EXE_NAME} failed ({proc.returncode}): {proc.stderr.strip()}")
        header = [ln for ln in out.read_text().splitlines()[:3]]
        data = np.loadtxt(out, ndmin=2)
        result = {"time": data[:, 0], "slip": data[:, 1::4], "slip_rate": data[:, 2::4],
                  "shear_stress": data[:, 3::4], "state": data[:, 4::4],
                  "stations": np.asarray(stations, float), "header": header,
                  "wall_seconds": wall}
        if final_profile:
            q = np.loadtxt(prof, ndmin=2)
            result["profile"] = {"x": q[:, 0], "slip": q[:, 1], "slip_rate": q[:, 2],
                                 "shear_stress": q[:, 3], "state": q[:, 4]}
    return result
