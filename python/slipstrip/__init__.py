"""slipstrip: spectral boundary-integral solver for frictional sliding between
two elastic strips of height H with rate-and-state friction (Python API).

SI units everywhere.  See docs/python.md for an overview with examples.

    import slipstrip
    cfg = slipstrip.load_config("configs/quickstart.toml", {"geometry.nodes": 128})
    sim = slipstrip.Simulation(cfg)
    v = sim.slip_rate            # NumPy view of the solver's memory, updated in place
    sim.advance(100)
    slipstrip.run(cfg, "run.h5", progress=print)
    r = slipstrip.open_run("run.h5")
"""
from __future__ import annotations

import os
import warnings
from typing import Any, Callable, Iterable

import numpy as np

from . import _slipstrip
from ._slipstrip import (  # noqa: F401  (re-exported)
    ConfigError,
    ElasticMaterial,
    LocalSolveFailure,
    LockHeldError,
    RunResult,
    SimulationError,
    detect_events,
    detect_events_in_file,
    detect_events_into_file,
    half_space_response,
    read_event_catalog,
    read_slip_sampling_info,
    strip_response,
    strip_static_stiffness,
    waiting_time_threshold,
    write_event_catalog,
    write_event_catalog_csv,
    write_slip_sampling,
)
from .config import Config, ConfigWarning, load_config, overrides_from, to_toml_text  # noqa: F401
from .export import SeasFile, read_seas  # noqa: F401
from .paths import OutputPathError, check_outputs, run_outputs  # noqa: F401
from .runfile import RunFile, open_run  # noqa: F401

__version__ = _slipstrip.code_version
git_hash = _slipstrip.git_hash

__all__ = [
    "Config", "ConfigError", "ConfigWarning", "ElasticMaterial", "LocalSolveFailure", "LockHeldError",
    "OutputPathError", "RunFile", "RunResult",
    "Simulation", "SimulationError", "characteristic_roots", "critical_wavelength",
    "critical_wavelength_vs_height", "is_inplane_pair", "pair_critical_wavelength", "pair_stability",
    "pair_unstable_roots", "detect_events", "detect_events_in_file", "detect_events_into_file", "growth_rates",
    "half_space_response", "linearise_friction", "load_config", "most_unstable_root", "open_run",
    "quasi_static_critical_wavelength", "read_event_catalog", "read_seas", "read_slip_sampling_info", "resume",
    "run", "SeasFile",
    "solve_slip_rate", "characteristic_function",
    "strip_response", "strip_static_stiffness", "to_toml_text", "waiting_time_threshold",
    "write_event_catalog", "write_event_catalog_csv", "write_slip_sampling",
]


def __dir__() -> list[str]:
    # dir(slipstrip) lists the API, not the modules this file imports (numpy, os, typing).
    return sorted(__all__ + ["__version__", "git_hash"])


class Simulation(_slipstrip._Simulation):
    """One simulation, stepped from Python.

    Simulation(config=None, overrides=None): config is anything load_config
    accepts (Config, path, TOML text, dict).

    Fields x, slip, slip_rate, state, shear_stress are read-only NumPy arrays
    that view the solver's memory (no copy): they change in place after
    step()/advance().  Use .copy() to keep a value.
    """

    def __init__(self, config=None, overrides=None):
        cfg = load_config(config, overrides)
        super().__init__(cfg)
        self._config = cfg

    @property
    def config(self) -> Config:
        return self._config

    def fields(self, copy: bool = False) -> dict[str, np.ndarray]:
        """All interface fields as a dict (views, or copies with copy=True)."""
        names = ("x", "slip", "slip_rate", "state", "shear_stress")
        return {n: (getattr(self, n).copy() if copy else getattr(self, n)) for n in names}

    def __repr__(self) -> str:
        return (f"Simulation(N={self.config.nodes}, t={self.time!r} s, step={self.step_index}, "
                f"dt={self.time_step!r} s, max_slip_rate={self.max_slip_rate!r} m/s)")


def run(config, out_path: str | os.PathLike, progress: Callable[[dict], Any] | None = None,
        overrides=None, progress_interval: float = 0.5, overwrite: bool = False) -> RunResult:
    """Run a whole simulation and write the HDF5 run file (docs/output.md).

    The output-path rule of every command (slipstrip.paths.check_outputs):
    out_path and its restart point out_path + ".restart" must not exist unless
    overwrite=True (which replaces both), and out_path is never the config
    file; OutputPathError otherwise, before anything is computed.  One process
    per run: LockHeldError if another process is writing out_path.

    progress(p) is called about every progress_interval seconds of wall time
    and once at the end, with p a dict: time [s], duration [s], step,
    max_slip_rate [m/s], wall_seconds.

    Ctrl-C (or an exception raised by progress) stops the run cleanly: the file
    is closed with status "interrupted" and the exception is re-raised with the
    RunResult attached as exc.run_result.  A divergence is not an exception:
    it is reported in RunResult.status ("diverged: ...").
    """
    cfg = load_config(config, overrides)
    config_file = [config] if isinstance(config, (str, os.PathLike)) and os.path.isfile(config) else []
    check_outputs(run_outputs(out_path, "out_path"), inputs=config_file, overwrite=overwrite,
                  overwrite_flag="overwrite=True")
    for text in cfg.warnings():  # valid but implausible values (docs/config.md, "Warnings")
        warnings.warn(text, ConfigWarning, stacklevel=2)
    return _slipstrip._run(cfg, os.fspath(out_path), progress, progress_interval, overwrite=bool(overwrite))


def resume(run_path: str | os.PathLike, progress: Callable[[dict], Any] | None = None,
           progress_interval: float = 0.5) -> RunResult:
    """Continue an interrupted run from its restart point RUN.h5.restart, with
    the config stored in the run file, appending to it; the file ends bitwise
    as an uninterrupted run's (docs/reliability.md, "Restart").  Ctrl-C and
    progress behave as in run() (and leave a new restart point).  ValueError
    if there is nothing to resume (no or unusable restart point, a completed
    or diverged run)."""
    return _slipstrip._resume(os.fspath(run_path), progress, progress_interval)


# --- linear stability of steady sliding (stability/linear_stability.hpp) -----------
# `config` is anything load_config accepts; material, friction, loading and
# geometry.height describe the steady sliding state, as in `slipstrip stability`.

def growth_rates(config, wavelengths: Iterable[float] | float) -> dict[str, np.ndarray]:
    """For each wavelength [m]: growth_rate = Re Lambda [1/s] of the least stable
    root, frequency = |Im Lambda| [rad/s], unstable (bool)."""
    w = np.atleast_1d(np.asarray(wavelengths, dtype=float))
    return _slipstrip._growth_rates(load_config(config), w.tolist())


def most_unstable_root(config, wavelength: float) -> complex | None:
    """Lambda [1/s] with the largest real part among unstable roots; None if stable."""
    return _slipstrip._most_unstable_root(load_config(config), float(wavelength))


def characteristic_roots(config, wavelength: float) -> np.ndarray:
    """All roots with Re Lambda > 0 (complete set), by decreasing real part."""
    return np.asarray(_slipstrip._characteristic_roots(load_config(config), float(wavelength)), dtype=complex)


def critical_wavelength(config, lower: float, upper: float, relative_tolerance: float = 1e-10) -> float:
    """Lc [m] bracketed by a stable `lower` and an unstable `upper` wavelength."""
    return _slipstrip._critical_wavelength(load_config(config), lower, upper, relative_tolerance)


def critical_wavelength_vs_height(config, heights: Iterable[float] | float) -> np.ndarray:
    """Lc(H) [m] for each height H [m] (inf allowed): the height of both identical
    strips, or, for an in-plane pair of different bodies, the top body's height
    with the bottom body fixed (as `slipstrip stability --height-range`;
    pair_critical_wavelength's search range, docs/bodies.md §5)."""
    h = np.atleast_1d(np.asarray(heights, dtype=float))
    c = load_config(config)
    if is_inplane_pair(c):
        length = c.length
        return np.asarray(_slipstrip._pair_critical_wavelength_vs_top_height(c, h.tolist(), 1e-3 * length,
                                                                             1e3 * length))
    return np.asarray(_slipstrip._critical_wavelength_vs_height(c, h.tolist()))


# --- in-plane pairs of different bodies (stability/interface_stability.hpp) --------
# The generalised dispersion relation with the normal-stress coupling and the
# memory the solver uses (docs/bodies.md §5); the numbers of `slipstrip stability`.

def is_inplane_pair(config) -> bool:
    """True for an in-plane config whose bottom body is not the mirror image of the
    top one (bottom.body = "elastic" or "rigid"): the pair functions below apply."""
    d = load_config(config).as_dict()
    return d["bottom"]["body"] != "mirror" and d["material"]["plane"] != "antiplane"


def pair_unstable_roots(config, wavelength: float) -> np.ndarray:
    """The unstable roots Lambda [1/s] at one wavelength [m], fastest first (empty
    when steady sliding is stable there).  k = 2 pi / wavelength > 0: a root
    travels along x at -Im(Lambda)/k."""
    return np.asarray(_slipstrip._pair_unstable_roots(load_config(config), float(wavelength)), dtype=complex)


def pair_critical_wavelength(config, shortest: float | None = None, longest: float | None = None) -> float:
    """Lc [m]: the shortest unstable wavelength in [shortest, longest] (default
    [1e-3, 1e3] x geometry.length, as the CLI), to 1e-6 relative; NaN if none."""
    c = load_config(config)
    length = c.length
    return _slipstrip._pair_critical_wavelength(c, 1e-3 * length if shortest is None else float(shortest),
                                                1e3 * length if longest is None else float(longest))


def pair_stability(config, wavelengths: Iterable[float] | float | None = None) -> dict:
    """What `slipstrip stability CONFIG --json` prints for an in-plane pair of
    different bodies, per wavelength [m] (default geometry.length): growth_rate
    (Re Lambda of the fastest unstable root, NaN if stable) [1/s], frequency
    (|Im Lambda|) [rad/s], phase_velocity (-Im Lambda / k) [m/s], unstable_roots
    (all of them, complex), and critical_wavelength [m]."""
    c = load_config(config)
    w = np.atleast_1d(np.asarray(c.length if wavelengths is None else wavelengths, dtype=float))
    roots = [pair_unstable_roots(c, x) for x in w]
    fastest = np.array([r[0] if len(r) else complex(np.nan, np.nan) for r in roots])
    return {
        "wavelength": w,
        "growth_rate": fastest.real,
        "frequency": np.abs(fastest.imag),
        "phase_velocity": -fastest.imag * w / (2.0 * np.pi),
        "unstable_roots": roots,
        "critical_wavelength": pair_critical_wavelength(c),
    }


def quasi_static_critical_wavelength(config) -> float:
    """Lc [m] with inertia dropped (closed form for a half-space); ValueError naming
    the height when no wavelength is unstable (an antiplane strip with mu/(2H) >= the
    critical stiffness)."""
    return _slipstrip._quasi_static_critical_wavelength(load_config(config))


def linearise_friction(config) -> dict[str, float]:
    """Friction derivatives at steady sliding: state phi0 [s], strength_dv [Pa s/m],
    strength_dstate [Pa/s], state_rate_dv [s/m], state_rate_dstate [1/s]."""
    return _slipstrip._linearise_friction(load_config(config))


def characteristic_function(config, wavenumber: float, growth: complex) -> complex:
    """F(Lambda) for wavenumber k [1/m] (roots are the modes of steady sliding)."""
    return _slipstrip._characteristic_function(load_config(config), float(wavenumber), complex(growth))


def solve_slip_rate(config, tau_history: float, state: float, initial_guess: float | None = None) -> float:
    """Slip rate v [m/s] of one node: tau_history - eta v = sign(v) strength(|v|, state),
    eta = mu / (2 c_s), friction and normal stress from `config` (0 if the node sticks).
    Raises LocalSolveFailure (a RuntimeError) with all inputs in the message."""
    cfg = load_config(config)
    guess = cfg.driving_velocity if initial_guess is None else initial_guess
    return _slipstrip._solve_slip_rate(cfg, float(tau_history), float(state), float(guess))
