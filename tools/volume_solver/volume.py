"""Python driver of the independent volume solver `slipstrip_volume`.

The solver itself is tools/volume_solver/volume_solver.cpp (a staggered-grid
finite-difference scheme of one elastic strip, or of a top and a bottom body of their
own heights and materials, or a strip on a rigid base, in-plane or antiplane; see
docs/benchmarks/volume_solver.md and docs/benchmarks/volume_bodies.md).
This module reads a slipstrip TOML config with the standard library's tomllib
(not with slipstrip's config code: the oracle shares only the friction law with
the product), turns it into the solver's key=value arguments, runs it and
returns the station time series as NumPy arrays.

    from volume import run_volume
    r = run_volume("configs/benchmarks/bp_pulse.toml", nx=320, stations=[0.5, 0.75])
    r["time"], r["slip_rate"][:, 0]          # [s], [m/s] at x = 0.5 m

For long runs it writes a run file in slipstrip's layout (docs/output.md:
/timeseries, /snapshots, the root attribute `config`), so `python3 -m slipstrip
pulse-episodes` and `trajectory-divergence` and the analysis read it unchanged:

    /usr/bin/python3 tools/volume_solver/volume.py run configs/fig5.toml --nx 1600 --out RUN.h5
    /usr/bin/python3 tools/volume_solver/volume.py convert RUN.h5     # after an interrupted run
    /usr/bin/python3 tools/volume_solver/volume.py run ... --checkpoint-interval 600   # restartable
    /usr/bin/python3 tools/volume_solver/volume.py resume RUN.h5      # after a kill: from the last checkpoint

Noise and sinusoidal initial perturbations are not re-implemented: phi(x, 0) is
taken from slipstrip's own initial-state code (the pybind11 module), which is
the same field as a slipstrip run of the same config and seed at N = nx.  The
initial condition is input data, not part of what the oracle checks.

The executable is looked up in $SLIPSTRIP_VOLUME_BIN, then
$SLIPSTRIP_BUILD_DIR/tools/volume_solver/, then <repo>/build*/tools/volume_solver/
(newest first).  Build it with `cmake --build build --target slipstrip_volume`.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import tempfile
import tomllib
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
EXE_NAME = "slipstrip_volume"
# the columns per station of the solver's station file (and of final_profile after x)
STATION_FIELDS = ("slip", "slip_rate", "shear_stress", "state", "normal_stress", "effective_normal_stress")


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


def load_table(path, overrides: dict | None = None) -> dict:
    """The TOML config at `path` as a dict, with overrides {"section.key": value} applied."""
    with open(path, "rb") as f:
        c = tomllib.load(f)
    for key, value in (overrides or {}).items():
        section, _, name = key.partition(".")
        if not name:
            raise ValueError(f"override {key!r}: give section.key")
        c.setdefault(section, {})[name] = value
    return c


def has_slipstrip_initial_state(table: dict) -> bool:
    """True if [initial] asks for noise or a sine, which the driver takes from slipstrip."""
    ini = table.get("initial", {})
    return bool(ini.get("noise_amplitude", 0.0) or ini.get("sine_amplitude", 0.0))


def read_config(path, overrides: dict | None = None, *, allow_slipstrip_initial: bool = False) -> dict:
    """The benchmark config as plain numbers (SI), resolved as docs/config.md says:
    shear_modulus from youngs_modulus if given, duration from duration_transits.
    allow_slipstrip_initial: accept noise / sine perturbations (the caller then
    supplies phi(x, 0) with initial_state_from_slipstrip)."""
    c = path if isinstance(path, dict) else load_table(path, overrides)
    g, m, lo = c.get("geometry", {}), c.get("material", {}), c.get("loading", {})
    bo, top = c.get("bottom", {}), c.get("top", {})
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
    if has_slipstrip_initial_state(c) and not allow_slipstrip_initial:
        raise ValueError("the volume solver implements [initial] local_* perturbations only "
                         "(noise and sine: volume.py run, which takes phi(x, 0) from slipstrip)")
    if it.get("load_pulse_amplitude", 0.0) and it.get("profile", "ramp") != "bump":
        raise ValueError("the volume solver implements the sin^4 'bump' load pulse only")
    H = g.get("height", 0.1)
    bottom = _bottom_body(bo, top, H, mu, nu, rho)
    return {
        "length": L, "height": H,
        "shear_modulus": mu, "poisson_ratio": nu, "density": rho,
        "plane": m.get("plane", "strain"),
        **bottom,
        "normal_stress_slip": it.get("normal_stress_slip", 0.0),
        "normal_stress_time": it.get("normal_stress_time", 0.0),
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


def _bottom_body(bo: dict, top: dict, H: float, mu: float, nu: float, rho: float) -> dict:
    """The solver's bottom_* arguments from [bottom] (docs/bodies.md section 1): a mirror
    image of the top body, another elastic strip (keys not given are the top body's), or
    rigid.  Half-spaces and clamped outer faces are refused (the grid is finite and its
    outer faces are driven)."""
    kind = bo.get("body", "mirror")
    if kind not in ("mirror", "elastic", "rigid"):
        raise ValueError(f"bottom.body = {kind!r}: allowed are mirror, elastic, rigid")
    for face in (top.get("outer_face", "driven"), bo.get("outer_face", "driven")):
        if face != "driven":
            raise ValueError(f"outer_face = {face!r}: the volume solver implements driven outer faces only")
    if kind == "rigid":
        return {"bottom": "rigid"}
    nu_b = bo.get("poisson_ratio", nu)
    mu_b = bo["shear_modulus"] if "shear_modulus" in bo else (
        bo["youngs_modulus"] / (2 * (1 + nu_b)) if "youngs_modulus" in bo else mu)
    H_b = bo.get("height", H)
    if isinstance(H_b, str) or not math.isfinite(H_b):
        raise ValueError("bottom.height = inf: the volume solver's bodies are finite strips")
    if kind == "mirror":
        return {"bottom": "mirror"}
    return {"bottom": "elastic", "bottom_height": float(H_b), "bottom_shear_modulus": float(mu_b),
            "bottom_poisson_ratio": float(nu_b), "bottom_density": float(bo.get("density", rho))}


def run_volume(config, nx: int, stations, *, dt: float | None = None, cfl: float | None = None,
               duration: float | None = None, output_every: int = 1, exe=None,
               final_profile: bool = False, threads: int | None = None) -> dict:
    """Run slipstrip_volume on `config` (a TOML path or a read_config() dict).

    nx: cells along the period (h = L/nx; H/h and H_b/h must be whole).  dt: time step [s]
    (default: cfl h / c with cfl = 0.5 and c the fastest wave speed of the grid).
    Returns a dict: time [nt], and slip, slip_rate, shear_stress, state, normal_stress,
    effective_normal_stress [nt, n_stations]; `wall_seconds`; with final_profile,
    `profile` = dict of those fields and x at the end.
    threads: OMP_NUM_THREADS of the run (default: inherited); results do not depend on it."""
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
        env = None if threads is None else {**os.environ, "OMP_NUM_THREADS": str(int(threads))}
        proc = subprocess.run(args, capture_output=True, text=True, env=env)
        wall = time.perf_counter() - t0
        if proc.returncode != 0:
            raise RuntimeError(f"{EXE_NAME} failed ({proc.returncode}): {proc.stderr.strip()}")
        header = [ln for ln in out.read_text().splitlines()[:3]]
        data = np.loadtxt(out, ndmin=2)
        result = {"time": data[:, 0],
                  **{name: data[:, 1 + k::len(STATION_FIELDS)] for k, name in enumerate(STATION_FIELDS)},
                  "stations": np.asarray(stations, float), "header": header,
                  "wall_seconds": wall}
        if final_profile:
            q = np.loadtxt(prof, ndmin=2)
            result["profile"] = {"x": q[:, 0], **{name: q[:, 1 + k] for k, name in enumerate(STATION_FIELDS)}}
    return result


# ---------------------------------------------------------------------------
# Long runs: a run file in slipstrip's layout (docs/output.md)
# ---------------------------------------------------------------------------

SNAPSHOT_FIELDS = ("slip", "slip_rate", "state", "shear_stress")  # order of the binary records
SNAPSHOT_UNITS = {"slip": "m", "slip_rate": "m/s", "state": "s", "shear_stress": "Pa"}
TIMESERIES_FIELDS = ("time", "max_slip_rate", "mean_slip", "mean_shear_stress")
TIMESERIES_UNITS = {"time": "s", "max_slip_rate": "m/s", "mean_slip": "m", "mean_shear_stress": "Pa"}
DATE_FORMAT = "%Y-%m-%dT%H:%M:%SZ"


def initial_state_from_slipstrip(config, overrides: dict | None, nx: int) -> np.ndarray:
    """phi(x, 0) at the nx interface nodes x = i L/nx, from slipstrip's initial-state
    code (the same field as `slipstrip run` of this config with geometry.nodes = nx)."""
    import slipstrip  # the pybind11 module; only for the initial field

    sim = slipstrip.Simulation(str(config), {**(overrides or {}), "geometry.nodes": int(nx)})
    return np.array(sim.state, dtype=np.float64)


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return repr(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        return repr(v) if math.isfinite(v) else ("inf" if v > 0 else "-inf")
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {v!r} as TOML")


def to_toml(table: dict) -> str:
    """A config of [section] key = scalar tables as TOML text (what tomllib.loads reads back)."""
    lines = []
    for section, values in table.items():
        lines.append(f"[{section}]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in values.items()]
        lines.append("")
    return "\n".join(lines)


def _paths(out) -> dict:
    out = Path(out)
    return {name: out.with_name(out.name + suffix) for name, suffix in (
        ("snapshots", ".snapshots.bin"), ("timeseries", ".timeseries.bin"), ("initial", ".initial_state.bin"),
        ("stations", ".stations.txt"), ("meta", ".meta.json"), ("log", ".log"),
        ("checkpoint", ".checkpoint.bin"))}


def refuse_to_replace(out, overwrite: bool) -> None:
    """A new run opens its raw records for writing, which would empty those of
    an earlier run into the same `out`: a run that finished but whose
    conversion was interrupted, or one waiting for `resume`.  So they are
    replaced only when asked (overwrite), and the message says what else to do."""
    if overwrite:
        return
    out = Path(out)
    found = [q for q in (out, out.with_name(out.name + ".partial"), *_paths(out).values()) if q.exists()]
    if found:
        names = ", ".join(q.name for q in found)
        raise FileExistsError(
            f"{out}: an earlier run's files exist ({names}); continue it with `volume.py resume {out}` "
            f"(a checkpoint exists) or `volume.py convert {out}` (its raw records), or pass --overwrite "
            f"to start again and lose them")


def _parse_value(text: str):
    """A --set value as TOML reads it (number, bool, quoted string), else the bare string."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def run_to_file(config, out, nx: int, *, overrides: dict | None = None, cfl: float | None = None,
                dt: float | None = None, duration: float | None = None, snapshot_interval: float | None = None,
                timeseries_interval: float | None = None, progress: float = 0.0, exe=None,
                keep_raw: bool = False, checkpoint_interval: float = 0.0, halt_after_steps: int = 0,
                overwrite: bool = False) -> Path:
    """Run slipstrip_volume on `config` (a TOML path; overrides {"section.key": value})
    and write the run file `out` (HDF5, slipstrip's layout).  The snapshot and
    time-series intervals default to the config's [output] values.  While it runs,
    the raw records are out.snapshots.bin and out.timeseries.bin; convert(out)
    turns them into the run file (done here at the end, or by hand after an
    interruption).  checkpoint_interval > 0: a checkpoint out.checkpoint.bin every
    that many wall seconds, from which resume_run(out) continues a killed run;
    halt_after_steps > 0: stop with a checkpoint after that step (the run file is
    then 'interrupted' until resume_run).  Refuses (FileExistsError) when the
    run file or any record of an earlier run into `out` exists, unless
    overwrite: the raw records of a long run are all it has until convert()
    has written the run file.  Returns the path of the run file."""
    import time as _time
    refuse_to_replace(out, overwrite)
    overrides = dict(overrides or {})
    table = load_table(config, overrides)
    p = read_config(table, allow_slipstrip_initial=True)
    if duration is not None:
        p["duration"] = duration
    output = table.get("output", {})
    snapshot_interval = snapshot_interval if snapshot_interval is not None else output.get("snapshot_interval", 2e-4)
    timeseries_interval = (timeseries_interval if timeseries_interval is not None
                           else output.get("timeseries_interval", 1e-5))
    exe = Path(exe) if exe else find_executable()
    if exe is None or not exe.is_file():
        raise FileNotFoundError(f"{EXE_NAME} not built: cmake --build build --target {EXE_NAME}")
    paths = _paths(out)
    p.pop("shear_wave_speed")
    if has_slipstrip_initial_state(table):
        initial_state_from_slipstrip(config, overrides, nx).tofile(paths["initial"])
        for k in ("local_amplitude", "local_center", "local_width"):  # already in slipstrip's field
            p.pop(k)
        p["initial_state"] = str(paths["initial"])
    p.update(nx=int(nx), out=str(paths["stations"]), output_every=10**12,
             snapshot_file=str(paths["snapshots"]), snapshot_interval=float(snapshot_interval),
             timeseries_file=str(paths["timeseries"]), timeseries_interval=float(timeseries_interval),
             progress=float(progress))
    if dt is not None:
        p["dt"] = float(dt)
    if cfl is not None:
        p["cfl"] = float(cfl)
    if checkpoint_interval > 0 or halt_after_steps > 0:
        p["checkpoint"] = str(paths["checkpoint"])
        if checkpoint_interval > 0:
            p["checkpoint_interval"] = float(checkpoint_interval)
    args = [str(exe)] + [f"{k}={v!r}" if isinstance(v, float) else f"{k}={v}" for k, v in p.items()]
    if halt_after_steps > 0:  # not in the saved arguments: resume_run runs to the end
        args.append(f"halt_after_steps={int(halt_after_steps)}")
    meta = {"config": str(config), "overrides": overrides, "table": table,
            "arguments": [a for a in args[1:] if not a.startswith("halt_after_steps=")],
            "nx": int(nx), "duration": p["duration"],
            "start_time": _time.strftime(DATE_FORMAT, _time.gmtime())}
    paths["meta"].write_text(json.dumps(meta, indent=1))
    return _execute(args, out, meta, keep_raw, "w")


HALTED = 3  # the solver's exit code after halt_after_steps (a checkpoint was written)


def _execute(args, out, meta: dict, keep_raw: bool, log_mode: str) -> Path:
    """Run the solver with `args`, record how it ended in the meta file and convert."""
    import time as _time
    paths = _paths(out)
    t0 = _time.perf_counter()
    with open(paths["log"], log_mode) as log:
        proc = subprocess.run(args, stdout=log, stderr=subprocess.STDOUT)
    meta.update(returncode=proc.returncode, wall_seconds=meta.get("wall_seconds", 0.0) + _time.perf_counter() - t0,
                end_time=_time.strftime(DATE_FORMAT, _time.gmtime()))
    paths["meta"].write_text(json.dumps(meta, indent=1))
    if proc.returncode not in (0, HALTED):
        raise RuntimeError(f"{EXE_NAME} failed ({proc.returncode}): {paths['log'].read_text().strip()[-2000:]}")
    if proc.returncode == HALTED:
        return convert(out, keep_raw=True)       # 'interrupted'; resume_run continues it
    if not keep_raw and paths["checkpoint"].exists():
        paths["checkpoint"].unlink()
    return convert(out, keep_raw=keep_raw)


def resume_run(out, exe=None, keep_raw: bool = False) -> Path:
    """Continue the run of `out` (started by run_to_file with a checkpoint interval, then
    killed or halted) from its last checkpoint, to the end, and write the run file.  The
    outputs are cut back to the checkpoint, so the result is the uninterrupted run's."""
    paths = _paths(out)
    meta = json.loads(paths["meta"].read_text())
    arguments = meta["arguments"]
    if not any(a.startswith("checkpoint=") for a in arguments) or not paths["checkpoint"].exists():
        raise FileNotFoundError(f"{out}: no checkpoint to resume from (run with a checkpoint interval)")
    exe = Path(exe) if exe else find_executable()
    if exe is None or not exe.is_file():
        raise FileNotFoundError(f"{EXE_NAME} not built: cmake --build build --target {EXE_NAME}")
    meta["resumed"] = meta.get("resumed", 0) + 1
    return _execute([str(exe)] + arguments + ["resume=1"], out, meta, keep_raw, "a")


def _grid_numbers(arguments: list[str]) -> dict:
    """nx, ny, h, dt, c_d dt/h, c_s, c_d of a run, from its arguments by the solver's
    formulas (the station file's header says the same, but a killed run may not
    have written it yet)."""
    a = dict(item.split("=", 1) for item in arguments)
    L, H, nx = float(a["length"]), float(a["height"]), int(a["nx"])
    plane = a.get("plane", "strain")

    def speeds(mu, nu, rho):
        lam = 2 * mu * nu / (1 - nu) if plane == "stress" else 2 * mu * nu / (1 - 2 * nu)
        return math.sqrt(mu / rho), math.sqrt((lam + 2 * mu) / rho)

    mu, nu, rho = float(a["shear_modulus"]), float(a["poisson_ratio"]), float(a["density"])
    h = L / nx
    cs, cd = speeds(mu, nu, rho)
    c_max = cs if plane == "antiplane" else cd
    if a.get("bottom", "mirror") == "elastic":
        cs_b, cd_b = speeds(float(a["bottom_shear_modulus"]), float(a["bottom_poisson_ratio"]),
                            float(a["bottom_density"]))
        c_max = max(c_max, cs_b if plane == "antiplane" else cd_b)
    dt = float(a.get("dt", 0.0))
    if dt <= 0:
        dt = float(a.get("cfl", 0.5)) * h / c_max
    t_end = float(a["duration"])
    dt = t_end / round(t_end / dt)
    ny_b = int(round(float(a["bottom_height"]) / h)) if a.get("bottom", "mirror") == "elastic" else 0
    return {"nx": nx, "ny": int(round(H / h)), "ny_bottom": ny_b, "h": h, "dt": dt, "courant_cd": cd * dt / h,
            "courant_max": c_max * dt / h, "c_s": cs, "c_d": cd}


def convert(out, keep_raw: bool = True) -> Path:
    """Write the run file `out` from the raw records of run_to_file (complete records only,
    so a run that was stopped early gives a shorter but valid file, status 'interrupted')."""
    import h5py

    out = Path(out)
    paths = _paths(out)
    meta = json.loads(paths["meta"].read_text())
    hdr = _grid_numbers(meta["arguments"])
    nx, ny, h, dt = int(hdr["nx"]), int(hdr["ny"]), hdr["h"], hdr["dt"]
    table = {k: dict(v) for k, v in meta["table"].items()}
    resolved = read_config(table, allow_slipstrip_initial=True)
    material = table.setdefault("material", {})
    material.pop("youngs_modulus", None)
    material["shear_modulus"] = resolved["shear_modulus"]
    material.setdefault("poisson_ratio", resolved["poisson_ratio"])
    material.setdefault("density", resolved["density"])
    table.setdefault("geometry", {})["nodes"] = nx
    # The time step is the volume solver's, not slipstrip's beta dx / c_s.
    table["time"] = {"duration": float(meta["duration"]), "time_step": dt}
    table["volume_solver"] = {"nx": nx, "ny": ny, "ny_bottom": hdr["ny_bottom"], "cell_size": h, "time_step": dt,
                              "courant_cd": hdr["courant_cd"], "courant_max": hdr["courant_max"],
                              "courant_cs": hdr["c_s"] * dt / h, "arguments": " ".join(meta["arguments"])}
    snaps = np.fromfile(paths["snapshots"], dtype=np.float64) if paths["snapshots"].exists() else np.empty(0)
    rec = 1 + len(SNAPSHOT_FIELDS) * nx
    snaps = snaps[: (snaps.size // rec) * rec].reshape(-1, rec)
    ts = np.fromfile(paths["timeseries"], dtype=np.float64) if paths["timeseries"].exists() else np.empty(0)
    ts = ts[: (ts.size // 4) * 4].reshape(-1, 4)
    # Completed: the solver returned 0 and the time series reached the end
    # (its last row is within one interval of the duration).
    completed = (meta.get("returncode") == 0 and ts.shape[0] > 1
                 and meta["duration"] - ts[-1, 0] <= ts[-1, 0] - ts[-2, 0] + dt)
    try:
        git_hash = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short=12", "HEAD"], capture_output=True,
                                  text=True).stdout.strip() or "unknown"
    except OSError:
        git_hash = "unknown"
    tmp = out.with_name(out.name + ".partial")
    with h5py.File(tmp, "w") as f:
        f.attrs["config"] = to_toml(table)
        f.attrs["code_version"] = "slipstrip_volume (tools/volume_solver)"
        f.attrs["git_hash"] = git_hash
        f.attrs["units"] = "SI: time s, slip m, slip_rate m/s, state s, shear_stress Pa, x m"
        f.attrs["start_time"] = meta["start_time"]
        f.attrs["end_time"] = meta.get("end_time", "")
        f.attrs["status"] = "completed" if completed else "interrupted"
        g = f.create_group("timeseries")
        for c, name in enumerate(TIMESERIES_FIELDS):
            g.create_dataset(name, data=ts[:, c]).attrs["units"] = TIMESERIES_UNITS[name]
        g = f.create_group("snapshots")
        g.attrs["trigger"] = "time"
        g.create_dataset("time", data=snaps[:, 0]).attrs["units"] = "s"
        g.create_dataset("x", data=np.arange(nx) * h).attrs["units"] = "m"
        for k, name in enumerate(SNAPSHOT_FIELDS):
            d = g.create_dataset(name, data=snaps[:, 1 + k * nx: 1 + (k + 1) * nx],
                                 chunks=(1, nx) if snaps.shape[0] else None, compression="gzip",
                                 compression_opts=4, shuffle=True)
            d.attrs["units"] = SNAPSHOT_UNITS[name]
    os.replace(tmp, out)
    if not keep_raw:
        for k in ("snapshots", "timeseries", "initial"):
            if paths[k].exists():
                paths[k].unlink()
    return out


def main(argv: list[str]) -> int:
    import argparse
    ap = argparse.ArgumentParser(description="Run the volume solver into a slipstrip run file, or convert "
                                             "the raw records of an interrupted run.")
    sub = ap.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run CONFIG into OUT (HDF5, slipstrip's run-file layout)")
    r.add_argument("config")
    r.add_argument("--out", required=True)
    r.add_argument("--nx", type=int, required=True, help="cells along L (h = L/nx; H/h must be whole)")
    r.add_argument("--set", action="append", default=[], metavar="SECTION.KEY=VALUE")
    r.add_argument("--cfl", type=float, help="c_d dt / h (default 0.5)")
    r.add_argument("--dt", type=float, help="time step [s] (instead of --cfl)")
    r.add_argument("--duration", type=float, help="[s] (default: the config's)")
    r.add_argument("--snapshot-interval", type=float)
    r.add_argument("--timeseries-interval", type=float)
    r.add_argument("--progress", type=float, default=60.0, help="seconds between progress lines in OUT.log")
    r.add_argument("--keep-raw", action="store_true")
    r.add_argument("--overwrite", action="store_true",
                   help="replace OUT and the records of an earlier run into OUT (otherwise refused)")
    r.add_argument("--checkpoint-interval", type=float, default=0.0,
                   help="wall seconds between checkpoints (OUT.checkpoint.bin; `resume OUT` continues)")
    u = sub.add_parser("resume", help="continue OUT from its last checkpoint to the end")
    u.add_argument("out")
    c = sub.add_parser("convert", help="write OUT from OUT.snapshots.bin etc. (e.g. after an interruption)")
    c.add_argument("out")
    a = ap.parse_args(argv)
    if a.command == "convert":
        print(convert(a.out))
        return 0
    if a.command == "resume":
        print(resume_run(a.out))
        return 0
    overrides = {}
    for item in a.set:
        k, sep, v = item.partition("=")
        if not sep:
            raise SystemExit(f"--set {item!r}: give SECTION.KEY=VALUE")
        overrides[k] = _parse_value(v)
    path = run_to_file(a.config, a.out, a.nx, overrides=overrides, cfl=a.cfl, dt=a.dt, duration=a.duration,
                       snapshot_interval=a.snapshot_interval, timeseries_interval=a.timeseries_interval,
                       progress=a.progress, keep_raw=a.keep_raw, checkpoint_interval=a.checkpoint_interval,
                       overwrite=a.overwrite)
    print(path)
    return 0


if __name__ == "__main__":
    import sys
    sys.exit(main(sys.argv[1:]))
