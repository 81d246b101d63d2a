"""The run files of the report: which cases (RUNS, described from their
configs by run_description), the two material readings of Table S1
(READINGS), opening a run file (Run, MissingRun) and its event catalog."""
from __future__ import annotations

import dataclasses
import datetime
import json
import math
import tomllib
from pathlib import Path

from .. import analysis as an
from .. import runfile


REPO = Path(__file__).resolve().parents[3]
# The run files (RUNDIR/<name>.h5), each made from configs/<name>.toml, and the
# part of the paper each one reproduces, as the config's header comment names
# it (tests/python/test_report_numbers.py checks the figure against it).  What
# sets each case apart (H, L, the friction, ...) is read from its config by
# run_description(), never typed here.
RUNS = {
    "reference": "Fig. 1, S6, S8, S9",
    "fig2_L2": "Fig. 2 statistics",
    "fig2_events": "Fig. 2 events",
    "fig3a": "Fig. 3a, controlled nucleation",
    "fig3b": "Fig. 3b, controlled nucleation",
    "fig3c_H005": "Fig. 3c",
    "fig3c_H02": "Fig. 3c; Figs. S4-S6 example",
    "fig3d_rho300": "Fig. 3d",
    "fig3d_rho4800": "Fig. 3d",
    "fig4_slip_law": "Fig. 4",
    "fig5": "Fig. 5",
    "fig5_H02": "Fig. 5 friction, main text 'not shown'",
    "s10_D_over_3": "Fig. S10",
    "s11_a_over_3": "Fig. S11",
    "s12": "Fig. S12",
    "noise_tiny": "the initial noise, main text 'Results'",
}
# Keys that differ between configs without describing the case: N follows from
# L at the paper's mesh size (the run list has a column N), and how often the
# time series is written and the file flushed is record keeping.
UNDESCRIBED_KEYS = ("geometry.nodes", "output.timeseries_interval", "output.flush_interval")


def _flat(table: dict, prefix: str = "") -> dict:
    out = {}
    for key, value in table.items():
        if isinstance(value, dict):
            out.update(_flat(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = value
    return out


def run_description(name: str, configs: Path = REPO / "configs") -> str:
    """The run list's description of case `name`: what it reproduces (RUNS),
    then H and L and every other key in which configs/<name>.toml differs from
    configs/reference.toml, with its value from the config."""
    try:
        config = _flat(tomllib.loads((Path(configs) / f"{name}.toml").read_text()))
        reference = _flat(tomllib.loads((Path(configs) / "reference.toml").read_text()))
    except OSError:
        return f"{RUNS[name]} (configs/{name}.toml not found)"
    parts = [f"H = {config['geometry.height']:g} m", f"L = {config['geometry.length']:g} m"]
    changed = [k for k in dict.fromkeys([*reference, *config])
               if config.get(k) != reference.get(k) and k not in UNDESCRIBED_KEYS
               and k not in ("geometry.height", "geometry.length")]
    local = [k for k in changed if k.startswith("initial.local_")]
    for key in changed:
        value = config.get(key)
        if key == "material.density":
            ratio = math.sqrt(float(reference[key]) / float(value))
            parts.append(f"rho = {value:g} kg/m^3, c_s " + (f"x {ratio:g}" if ratio >= 1 else f"/ {1 / ratio:g}"))
        elif key in ("friction.f0", "friction.a", "friction.b"):
            parts.append(f"{key.split('.')[1]} = {value:g}")
        elif key == "friction.characteristic_slip":
            parts.append(f"D = {value:g} m")
        elif key == "state.law":
            parts.append(f"{value} law")
        elif key == "initial.noise_amplitude":
            parts.append(f"initial noise {value:g} instead of the reference's {reference[key]:g}" if value
                         else "no initial noise")
        elif key in local:
            if key == local[0]:
                parts.append(f"state patch of relative amplitude {config.get('initial.local_amplitude', 0):g} at "
                             f"x = {config.get('initial.local_center', 0):g} m, width "
                             f"{config.get('initial.local_width', 0):g} m")
        elif key in ("time.duration", "time.duration_transits"):
            if value is not None:
                parts.append(f"duration {value:g} " + ("L/c_s" if key.endswith("transits") else "s"))
        elif key == "output.snapshot_interval":
            parts.append(f"snapshots every {value:g} s")
        elif value is not None:
            parts.append(f"{key} = {value}")
    return f"{RUNS[name]} ({', '.join(parts)})"


STATISTICS_RUNS = ("reference", "fig2_L2", "fig3c_H005", "fig3c_H02", "fig3d_rho300", "fig3d_rho4800", "fig4_slip_law",
                   "fig5", "fig5_H02", "s10_D_over_3", "s11_a_over_3", "s12")
FIG3_FAMILY = ("fig3c_H005", "reference", "fig3c_H02", "fig3d_rho300", "fig3d_rho4800")
# The Fig. 5 case in the independent volume solver at the paper's mesh: the
# report does not run it (hours of CPU); it reads the pulse-criterion summary
# that docs/fig5_resolution.md commits and names how it was made.
FIG5_VOLUME_SOLVER_JSON = REPO / "docs" / "figures" / "fig5_resolution" / "vol_fig5_h2.5mm_seed1.json"


def fig5_volume_solver_text(path: Path = FIG5_VOLUME_SOLVER_JSON) -> str:
    """The volume-solver sentence of the Fig. 5 verdict, from the committed
    summary of `python3 -m slipstrip pulse-episodes` (empty if it is absent)."""
    try:
        summary = json.loads(path.read_text())
    except (OSError, ValueError):
        return ""
    windows = summary["windows"]
    # The cell size: the interface nodes of the volume mesh along configs/fig5.toml's L.
    cells = ""
    if summary.get("nodes"):
        length = tomllib.loads((REPO / "configs" / "fig5.toml").read_text())["geometry"]["length"]
        cells = f", {1e3 * float(length) / summary['nodes']:g} mm cells"
    return (f"; a volume discretisation at the paper's mesh (tools/volume_solver{cells}) gives "
            f"a pulse in {summary['pulse_windows']} of {len(windows)} windows over "
            f"{summary['duration_transits']:.0f} L/c_s (fig5_resolution.md)")


@dataclasses.dataclass(frozen=True)
class Reading:
    key: str
    name: str          # column title
    description: str
    overrides: dict    # config overrides that turn the committed configs into this reading
    label: str         # material_label() of its runs (without the rho suffix)


READINGS = {
    "asrun": Reading("asrun", "paper-as-run", "E = 9 GPa, mu = 3.38 GPa (Table S1's '9 GPa' read as Young's "
                     "modulus; configs as committed)", {}, "paper-as-run (E = 9 GPa)"),
    "printed": Reading("printed", "as printed", "mu = 9 GPa (Table S1 as printed: "
                       "--set material.shear_modulus=9e9)", {"material.shear_modulus": 9e9},
                       "Table S1 as printed (mu = 9 GPa)"),
}


class MissingRun(Exception):
    """A run file that cannot be used; str() is the one-line reason."""


@dataclasses.dataclass
class Run:
    name: str
    path: Path
    status: str
    config: dict
    start_time: str
    end_time: str
    git_hash: str
    info: an.RunInfo

    @property
    def wall_seconds(self) -> float:
        try:
            t0 = datetime.datetime.strptime(self.start_time, "%Y-%m-%dT%H:%M:%SZ")
            t1 = datetime.datetime.strptime(self.end_time, "%Y-%m-%dT%H:%M:%SZ")
        except (ValueError, TypeError):
            return math.nan
        return (t1 - t0).total_seconds()

    @property
    def length_transit_time(self) -> float:
        """L / c_s [s]"""
        return self.info.L / self.info.c_s


def open_run_file(rundir: Path, name: str, allow_incomplete: bool = False) -> Run:
    """The run RUNDIR/name.h5, or MissingRun naming the file and the reason."""
    path = Path(rundir) / f"{name}.h5"
    shown = f"RUNDIR/{name}.h5"
    if not path.is_file():
        raise MissingRun(f"{shown} missing")
    try:
        attrs = {k: str(v) for k, v in runfile.read_attrs(path).items()
                 if k in ("status", "config", "start_time", "end_time", "git_hash")}
        if "config" not in attrs or not runfile.has_group(path, "timeseries"):
            raise MissingRun(f"{shown} unreadable: not a slipstrip run file (no config or /timeseries)")
        info = an.read_run_info(path)
        if info.interface_2d:
            raise MissingRun(f"{shown} is a 2D interface (geometry.nodes_z > 1): the report reproduces the paper's "
                             "claims, which are about a one-dimensional interface (2D bodies); use analyze for a "
                             "2D interface")
    except MissingRun:
        raise
    except Exception as err:  # h5py raises OSError, KeyError, ...
        raise MissingRun(f"{shown} unreadable: {str(err).splitlines()[0] if str(err) else type(err).__name__}")
    status = attrs.get("status", "")
    if status != "completed" and not allow_incomplete:
        raise MissingRun(f"{shown} incomplete (status '{status}', t = {info.duration:.4g} s)")
    return Run(name=name, path=path, status=status, config=tomllib.loads(attrs["config"]),
               start_time=attrs.get("start_time", ""), end_time=attrs.get("end_time", ""),
               git_hash=attrs.get("git_hash", ""), info=info)


def material_label(config: dict) -> str:
    """Which reading of Table S1 a run uses, from its resolved config."""
    m = config.get("material", {})
    mu, nu, rho = float(m.get("shear_modulus", math.nan)), float(m.get("poisson_ratio", math.nan)), \
        float(m.get("density", math.nan))
    e = 2 * mu * (1 + nu)
    if abs(e - 9e9) < 1e-6 * 9e9:
        reading = "paper-as-run (E = 9 GPa)"
    elif abs(mu - 9e9) < 1e-6 * 9e9:
        reading = "Table S1 as printed (mu = 9 GPa)"
    else:
        reading = f"mu = {mu / 1e9:.3g} GPa"
    return reading + ("" if rho == 1200.0 else f", rho = {rho:g}")


def catalog_of(run: Run, alpha: float, workdir: Path) -> dict:
    """/events of the run file if made with this alpha, else a fresh detection
    into workdir (the run file is never written)."""
    with runfile.open_h5(run.path) as f:
        stored = float(f["events"].attrs["alpha"]) if "events" in f else None
    if stored is not None and stored == float(alpha) and run.status == "completed":
        return an.read_catalog(run.path)
    out = Path(workdir) / f"{run.name}_events_alpha{alpha:g}.h5"
    if not out.exists():
        an.run_event_detection(run.path, alpha, out)
    return an.read_catalog(out)
