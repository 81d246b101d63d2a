"""Tests of the compiled bindings and the core package (python/slipstrip).

References: closed forms (steady sliding, Eq. S1/S2 friction, static strip
stiffness, quasi-static half-space Lc), the C++ CLI as an independent entry
point to the same library (messages, growth rates), files read with plain
h5py/tomllib, and a synthetic slip-sampling history whose event catalog is
known by construction.

Run: /usr/bin/python3 -m pytest tests/python/test_bindings.py
"""
import gc
import json
import math
import os
import pickle
import signal
import subprocess
import time
import tomllib

import h5py
import numpy as np
import pytest

from conftest import REPO

QUICKSTART = REPO / "configs" / "quickstart.toml"


@pytest.fixture(scope="module")
def ss(slipstrip_module):
    return slipstrip_module


def small(ss, **extra):
    """Quickstart with 64 nodes: ~256 steps per L/c_s, a few ms per 100 steps."""
    overrides = {"geometry.nodes": 64}
    overrides.update(extra)
    return ss.load_config(QUICKSTART, overrides)


def steady_sliding_closed_form(cfg):
    """phi_ss(v0) (Eq. S2 with the sqrt(v^2 + v*^2) regularisation) and tau_0 (Eq. S1)."""
    c = cfg.as_dict()
    f, v0, sigma0 = c["friction"], c["loading"]["driving_velocity"], c["loading"]["normal_stress"]
    phi = f["characteristic_slip"] / math.hypot(v0, f["v_star"])
    tau = sigma0 * (f["f0"] * (1 + f["b"] * math.log(phi / f["phi_star"])) + f["a"] * math.log1p(v0 / f["v_star"]))
    return phi, tau


# ---------------------------------------------------------------------------
# Configuration
# ---------------------------------------------------------------------------

def test_config_from_file_with_list_overrides_matches_file_and_overrides(ss):
    cfg = ss.load_config(QUICKSTART, ["geometry.nodes=128", "state.law=slip"])
    file_values = tomllib.loads(QUICKSTART.read_text())
    d = cfg.as_dict()
    assert d["geometry"]["nodes"] == 128
    assert d["state"]["law"] == "slip"
    assert d["geometry"]["length"] == file_values["geometry"]["length"]
    assert d["friction"]["characteristic_slip"] == file_values["friction"]["characteristic_slip"]
    # duration_transits is resolved into seconds: 50 L / c_s, c_s = sqrt(mu / rho).
    # 1e-12: only the rounding of one product and one square root separates the two.
    m = file_values["material"]
    expected = file_values["time"]["duration_transits"] * file_values["geometry"]["length"] / math.sqrt(
        m["shear_modulus"] / m["density"])
    assert cfg.duration == pytest.approx(expected, rel=1e-12)
    assert d["time"]["duration"] == cfg.duration


def test_config_from_string_and_dict_overrides(ss):
    cfg = ss.load_config("[geometry]\nlength = 2.0\nheight = 0.05\n", {"geometry": {"nodes": 32}})
    assert (cfg.length, cfg.height, cfg.nodes) == (2.0, 0.05, 32)
    # Flat dict overrides with a string and an infinity.
    cfg2 = ss.Config.from_string("", {"state.law": "slip", "geometry.height": math.inf})
    assert cfg2["state"]["law"] == "slip"
    assert math.isinf(cfg2.height)
    # Empty text = defaults = Config().
    assert ss.Config() == ss.load_config("")


def test_config_from_dict_equals_config_from_file(ss):
    # The Python TOML writer + C++ parser must resolve exactly what the C++
    # parser resolves from the file itself (bit-identical TOML back).
    as_dict = tomllib.loads(QUICKSTART.read_text())
    from_dict = ss.load_config(as_dict, {"geometry.nodes": 96})
    from_file = ss.load_config(QUICKSTART, ["geometry.nodes=96"])
    assert from_dict.to_toml() == from_file.to_toml()
    # And the resolved dict reads back into the same config.
    assert ss.load_config(from_file.as_dict()) == from_file


def test_config_roundtrips_through_pickle_and_with_overrides(ss):
    cfg = small(ss)
    again = pickle.loads(pickle.dumps(cfg))
    assert again == cfg and isinstance(again, ss.Config)
    changed = cfg.with_overrides({"loading.driving_velocity": 1e-3})
    assert changed.driving_velocity == 1e-3 and cfg.driving_velocity == 2e-3


def test_toml_writer_handles_types(ss):
    text = ss.to_toml_text({"a": {"s": 'x "q"', "t": True, "i": 3, "f": 1e-7, "n": -math.inf, "l": [1, 2.5]}})
    assert tomllib.loads(text) == {"a": {"s": 'x "q"', "t": True, "i": 3, "f": 1e-7, "n": -math.inf, "l": [1, 2.5]}}


# ---------------------------------------------------------------------------
# Exceptions: same type family and same message as the C++ / the CLI
# ---------------------------------------------------------------------------

def cli_error(cli, *args):
    """Runs the CLI, expects failure, returns the message after 'error: '."""
    p = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True, timeout=60)
    assert p.returncode != 0, p.stdout
    lines = [l for l in p.stderr.splitlines() if l.startswith("error: ")]
    assert lines, p.stderr
    return lines[-1][len("error: "):]


def test_unknown_key_in_file_same_message_as_cli(ss, cli, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[geometry]\nlength = 1.0\nnodez = 64\n")
    expected = cli_error(cli, "stability", bad)
    assert "did you mean" in expected  # the suggestion text is part of what must survive
    with pytest.raises(ss.ConfigError) as info:
        ss.load_config(bad)
    assert str(info.value) == expected
    assert isinstance(info.value, ValueError)


def test_bad_override_and_bad_value_same_message_as_cli(ss, cli):
    expected = cli_error(cli, "stability", QUICKSTART, "--set", "frictoin.a=0.01")
    with pytest.raises(ss.ConfigError) as info:
        ss.load_config(QUICKSTART, ["frictoin.a=0.01"])
    assert str(info.value) == expected

    expected = cli_error(cli, "stability", QUICKSTART, "--set", "geometry.nodes=-4")
    with pytest.raises(ValueError) as info:
        ss.load_config(QUICKSTART, {"geometry.nodes": -4})
    assert str(info.value) == expected


def test_missing_file_same_message_as_cli(ss, cli, tmp_path):
    missing = tmp_path / "nope.toml"
    expected = cli_error(cli, "stability", missing)
    with pytest.raises(ss.ConfigError) as info:
        ss.load_config(missing)
    assert str(info.value) == expected


def test_invalid_argument_maps_to_value_error_with_cli_message(ss, cli, tmp_path):
    # A negative initial state is rejected by the Simulation constructor
    # (std::invalid_argument, not a ConfigError): the CLI prints the same text.
    overrides = ["geometry.nodes=64", "initial.noise_amplitude=100"]
    expected = cli_error(cli, "run", QUICKSTART, "--quiet", "--out", tmp_path / "x.h5",
                         *[a for o in overrides for a in ("--set", o)])
    with pytest.raises(ValueError) as info:
        ss.Simulation(QUICKSTART, overrides)
    assert not isinstance(info.value, ss.ConfigError)
    assert str(info.value) == expected


def test_simulation_error_same_message_as_cli_divergence(ss, cli, tmp_path):
    # An absurd imposed stress (free interface) overflows within a few steps.
    # Slip sampling off: with it, the finite-but-huge slips of the steps before
    # the overflow make the run file record ~1e300 threshold crossings (the
    # process runs out of memory; reported as a bug in solver/run_output).
    overrides = ["geometry.nodes=32", "interface.law=free", "interface.stress_amplitude=1e308",
                 "interface.rise_time=1e-9", "time.duration_transits=1", "output.delta_th=0"]
    out = tmp_path / "diverged.h5"
    p = subprocess.run([str(cli), "run", str(QUICKSTART), "--quiet", "--out", str(out),
                        *[a for o in overrides for a in ("--set", o)]], capture_output=True, text=True, timeout=60)
    assert p.returncode == 3, p.stderr
    with h5py.File(out, "r") as f:
        status = f.attrs["status"]
    assert status.startswith("diverged: ")

    sim = ss.Simulation(QUICKSTART, overrides)
    with pytest.raises(ss.SimulationError) as info:
        sim.advance(1000)
    assert isinstance(info.value, RuntimeError)
    assert str(info.value) == status[len("diverged: "):]

    # run() reports the divergence in the result, as the C++ does (not raised).
    result = ss.run(QUICKSTART, tmp_path / "py.h5", overrides=overrides)
    assert result.status == status


def test_local_solve_failure_maps_to_its_own_runtime_error(ss):
    cfg = small(ss)
    with pytest.raises(ss.LocalSolveFailure) as info:
        ss.solve_slip_rate(cfg, 3e5, -1.0)
    assert isinstance(info.value, RuntimeError)
    msg = str(info.value)
    assert msg.startswith("solve_slip_rate failed (non-finite or out-of-range input")
    assert "state = -1 s" in msg and "tau_history = 300000 Pa" in msg


def test_solve_slip_rate_satisfies_eq_s1(ss):
    # tau_history - eta v = strength(v, phi) with the paper's law, evaluated here.
    cfg = small(ss)
    c = cfg.as_dict()
    f, sigma0 = c["friction"], c["loading"]["normal_stress"]
    eta = cfg.material.shear_modulus / (2 * cfg.material.shear_wave_speed)
    phi, tau0 = steady_sliding_closed_form(cfg)
    tau_history = tau0 + eta * 2e-3 + 5e3  # 5 kPa above steady sliding: slips faster than v0
    v = ss.solve_slip_rate(cfg, tau_history, phi)
    strength = sigma0 * (f["f0"] * (1 + f["b"] * math.log(phi / f["phi_star"])) + f["a"] * math.log1p(v / f["v_star"]))
    # 1e-9 of the stress: the Newton solve converges to round-off of ~1e-16 tau
    # per operation; this leaves room for the log evaluations without hiding a
    # wrong law (which would be off by > 1e-4).
    assert v > 2e-3
    assert tau_history - eta * v == pytest.approx(strength, rel=1e-9)


# ---------------------------------------------------------------------------
# Simulation: stepping and zero-copy fields
# ---------------------------------------------------------------------------

def test_fields_are_zero_copy_read_only_views_updated_in_place(ss):
    sim = ss.Simulation(small(ss))
    v = sim.slip_rate
    again = sim.slip_rate
    assert np.shares_memory(v, again)
    assert v.__array_interface__["data"][0] == sim._field_address("slip_rate")
    assert sim.slip.__array_interface__["data"][0] == sim._field_address("slip")
    assert v.base is sim  # the array keeps the Simulation (and so the memory) alive
    assert not v.flags.writeable
    with pytest.raises(ValueError):
        v[0] = 1.0
    before = v.copy()
    slip = sim.slip
    slip_before = slip.copy()
    sim.step()
    # The same array objects now show the new step, without re-fetching.
    assert not np.array_equal(v, before)
    assert not np.array_equal(slip, slip_before)
    np.testing.assert_array_equal(v, sim.slip_rate)
    assert sim.step_index == 1 and sim.time == sim.time_step


def test_field_views_keep_simulation_alive(ss):
    x = ss.Simulation(small(ss)).x
    gc.collect()
    # x_i = i dx, dx = L / N: exact in binary for L = 0.5, N = 64.
    np.testing.assert_array_equal(x, np.arange(64) * (0.5 / 64))


def test_advance_equals_repeated_step(ss):
    cfg = small(ss)
    a, b = ss.Simulation(cfg), ss.Simulation(cfg)
    for _ in range(50):
        a.step()
    b.advance(50)
    # Same operations in the same order: bit-identical.
    assert a.step_index == b.step_index == 50
    for name in ("slip", "slip_rate", "state", "shear_stress"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))


def test_advance_releases_the_gil(ss):
    # A Python thread counts while the main thread (a) sleeps, which releases
    # the GIL, then (b) sits in one advance() call.  Released during the C++
    # loop, the counting rate in (b) is comparable to (a) (OpenMP threads may
    # compete for the cores: allow a factor 4).  Held, the counter would only
    # run for the ~5 ms switch interval at the start and end of the call,
    # i.e. < 5% of a call lasting >= 0.2 s.
    import threading
    sim = ss.Simulation(small(ss))
    count = [0]
    done = threading.Event()

    def counter():
        while not done.is_set():
            count[0] += 1

    thread = threading.Thread(target=counter)
    thread.start()
    try:
        c0, t0 = count[0], time.perf_counter()
        time.sleep(0.2)
        free_rate = (count[0] - c0) / (time.perf_counter() - t0)
        steps = 200
        while True:  # until one call lasts >= 0.2 s (the machine's speed varies)
            c0, t0 = count[0], time.perf_counter()
            sim.advance(steps)
            elapsed = time.perf_counter() - t0
            if elapsed >= 0.2:
                break
            steps *= 2
        advance_rate = (count[0] - c0) / elapsed
    finally:
        done.set()
        thread.join()
    assert advance_rate > 0.25 * free_rate, (advance_rate, free_rate)


def test_ctrl_c_interrupts_advance_at_a_whole_step(ss):
    import threading
    sim = ss.Simulation(small(ss))
    timer = threading.Timer(0.2, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sim.advance(10**9)
    finally:
        timer.cancel()
    assert 0 < sim.step_index < 10**9
    # Stopped between steps: the clock is a whole number of steps.
    assert sim.time == pytest.approx(sim.step_index * sim.time_step, rel=1e-9)
    sim.step()  # and the simulation is still usable


def test_unperturbed_steady_sliding_stays_steady(ss):
    # No initial perturbation: v = v0, phi = phi_ss(v0), tau = tau_0 for all time,
    # and slip = v0 t (the trapezoidal update is exact for constant v).
    cfg = small(ss, **{"initial.noise_amplitude": 0.0})
    sim = ss.Simulation(cfg)
    sim.advance(200)
    phi, tau0 = steady_sliding_closed_form(cfg)
    v0 = cfg.driving_velocity
    # 1e-9: the local solve is converged to round-off; the spectral history of
    # a uniform field adds ~1e-16 relative per step (200 steps).
    np.testing.assert_allclose(sim.slip_rate, v0, rtol=1e-9)
    np.testing.assert_allclose(sim.state, phi, rtol=1e-9)
    np.testing.assert_allclose(sim.shear_stress, tau0, rtol=1e-9)
    np.testing.assert_allclose(sim.slip, v0 * sim.time, rtol=1e-9)
    assert sim.reference_shear_stress == pytest.approx(tau0, rel=1e-12)
    assert sim.mean_slip == pytest.approx(v0 * sim.time, rel=1e-9)


# ---------------------------------------------------------------------------
# run(): progress callback and interruption
# ---------------------------------------------------------------------------

def test_run_calls_progress_and_writes_file(ss, tmp_path):
    cfg = small(ss, **{"time.duration_transits": 2.0, "output.snapshot_interval": 1e-5})
    calls = []
    out = tmp_path / "run.h5"
    result = ss.run(cfg, out, progress=calls.append, progress_interval=0.0)
    assert result.status == "completed"
    assert calls, "progress was never called"
    assert calls[-1]["step"] == result.steps and calls[-1]["duration"] == cfg.duration
    # round(duration / dt) steps, as the C++ driver counts them.
    assert result.steps == round(cfg.duration / result.time_step)
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "completed"
        assert len(f["timeseries/time"]) == result.steps + 1  # timeseries_interval = 0: every step + t = 0
        assert tomllib.loads(f.attrs["config"]) == cfg.as_dict()


def test_ctrl_c_interrupts_run_cleanly(ss, tmp_path):
    # Long enough (~2e5 steps) that only the interrupt can end it within the test.
    cfg = small(ss, **{"time.duration_transits": 800.0})
    out = tmp_path / "interrupted.h5"
    sent = []

    def progress(p):
        if not sent:
            sent.append(p["step"])
            os.kill(os.getpid(), signal.SIGINT)  # what Ctrl-C does

    with pytest.raises(KeyboardInterrupt) as info:
        ss.run(cfg, out, progress=progress, progress_interval=0.0)
    result = info.value.run_result
    assert result.status == "interrupted"
    assert 0 < result.steps < round(cfg.duration / result.time_step)
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "interrupted"
        assert f["timeseries/time"][-1] == pytest.approx(result.simulated_time, rel=1e-12)


def test_exception_in_progress_stops_run_and_propagates(ss, tmp_path):
    cfg = small(ss, **{"time.duration_transits": 800.0})
    out = tmp_path / "stopped.h5"

    def progress(p):
        raise ZeroDivisionError("from the callback")

    with pytest.raises(ZeroDivisionError, match="from the callback"):
        ss.run(cfg, out, progress=progress, progress_interval=0.0)
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "interrupted"


# ---------------------------------------------------------------------------
# Linear stability and strip response
# ---------------------------------------------------------------------------

def test_growth_rates_equal_cli_json(ss, cli):
    wavelengths = [0.5, 0.25, 0.1, 0.05]
    p = subprocess.run([str(cli), "stability", str(QUICKSTART), "--wavelength", ",".join(map(str, wavelengths)),
                        "--json"], capture_output=True, text=True, timeout=120, check=True)
    ref = json.loads(p.stdout)
    got = ss.growth_rates(QUICKSTART, wavelengths)
    # Same library code on the same inputs, printed with 17 significant digits:
    # anything beyond round-off (1e-12) means the binding analysed another problem.
    np.testing.assert_allclose(got["wavelength"], ref["wavelengths"], rtol=0)
    np.testing.assert_allclose(got["growth_rate"], ref["growth_rate"], rtol=1e-12)
    np.testing.assert_allclose(got["frequency"], ref["frequency"], rtol=1e-12, atol=1e-9)
    # At least one unstable and the most unstable root agrees with the table.
    assert got["unstable"][0]
    root = ss.most_unstable_root(QUICKSTART, 0.5)
    assert root.real == pytest.approx(got["growth_rate"][0], rel=1e-12)


def test_quasi_static_half_space_lc_closed_form(ss):
    # Lc = 2 pi mu (1 - c_s^2/c_d^2) / (tau_v g_phi - tau_phi g_v), with the
    # derivatives of Eq. S1/S2 at steady sliding written out here.
    cfg = ss.load_config(QUICKSTART, {"geometry.height": math.inf})
    c = cfg.as_dict()
    f, v0, sigma0 = c["friction"], c["loading"]["driving_velocity"], c["loading"]["normal_stress"]
    r = math.hypot(v0, f["v_star"])
    phi = f["characteristic_slip"] / r
    tau_v = sigma0 * f["a"] / (f["v_star"] + v0)
    tau_phi = sigma0 * f["f0"] * f["b"] / phi
    g_v = -(v0 / r) * phi / f["characteristic_slip"]
    g_phi = -r / f["characteristic_slip"]
    nu = c["material"]["poisson_ratio"]
    cs2_over_cd2 = (1 - 2 * nu) / (2 * (1 - nu))  # plane strain
    expected = 2 * math.pi * c["material"]["shear_modulus"] * (1 - cs2_over_cd2) / (tau_v * g_phi - tau_phi * g_v)
    lin = ss.linearise_friction(cfg)
    # 1e-10: analytic derivatives on both sides; only round-off differs.
    assert lin["strength_dv"] == pytest.approx(tau_v, rel=1e-10)
    assert lin["state_rate_dstate"] == pytest.approx(g_phi, rel=1e-10)
    assert ss.quasi_static_critical_wavelength(cfg) == pytest.approx(expected, rel=1e-10)


def test_strip_static_stiffness_closed_form_and_vectorised(ss):
    mat = ss.ElasticMaterial(shear_modulus=9e9, poisson_ratio=0.33, density=1200.0)
    H = 0.025
    k = np.array([1.0, 10.0, 100.0])
    got = ss.strip_static_stiffness(mat, H, k)
    expected = mat.shear_modulus * k * (1 - 1 / mat.wave_speed_ratio_squared) * (
        1 / np.tanh(k * H) - k * H / np.sinh(k * H) ** 2)
    # 1e-9: the closed form loses ~(kH)^-2 digits to cancellation at small kH.
    np.testing.assert_allclose(got, expected, rtol=1e-9)
    # s -> 0 limit of the dynamic response is the static stiffness (s = 1e-6 / s:
    # the correction is O((s/(c_s k))^2) ~ 1e-20).
    np.testing.assert_allclose(ss.strip_response(mat, H, k, 1e-6 + 0j).real, expected, rtol=1e-9)
    # Half-space: S(k, 0) = mu |k| (1 - c_s^2/c_d^2).
    hs = ss.half_space_response(mat, k, 1e-6 + 0j).real
    np.testing.assert_allclose(hs, mat.shear_modulus * k * (1 - 1 / mat.wave_speed_ratio_squared), rtol=1e-9)


# ---------------------------------------------------------------------------
# Events from a synthetic slip-sampling file
# ---------------------------------------------------------------------------

N_NODES, DX, DELTA_TH, V0, MU = 32, 1e-3, 1e-8, 2e-3, 9e9
FRONT_STEP, LEVEL_STEP = 1e-7, 2e-7  # [s] between neighbouring nodes / successive levels of a node
# (base time, first node, end node, levels per node); 1e-3 s apart, far above the
# waiting-time threshold 15 delta_th / (v0 N) = 2.3e-6 s; inside an event NS are
# at most 2e-7 s apart.
SYNTHETIC_EVENTS = [
    (1e-3, 0, 32, 2),   # first: excluded
    (2e-3, 4, 12, 3),   # kept
    (3e-3, 20, 21, 5),  # one node wide: below the 2 dx extent filter
    (4e-3, 10, 20, 2),  # kept (mean slip exactly 2 delta_th is kept)
    (5e-3, 0, 32, 1),   # last: excluded
]


def synthetic_crossing_time():
    columns = [[] for _ in range(N_NODES)]
    for t0, a, b, m in SYNTHETIC_EVENTS:
        for i in range(a, b):
            for j in range(m):
                columns[i].append(t0 + (i - a) * FRONT_STEP + j * LEVEL_STEP)
    n_levels = max(len(c) for c in columns)
    ct = np.full((n_levels, N_NODES), np.nan)
    for i, c in enumerate(columns):
        ct[:len(c), i] = c
    return ct


def expected_catalog():
    kept = [SYNTHETIC_EVENTS[1], SYNTHETIC_EVENTS[3]]
    return {
        "t_start": [t0 for t0, a, b, m in kept],
        "duration": [(b - a - 1) * FRONT_STEP + (m - 1) * LEVEL_STEP for t0, a, b, m in kept],
        "x_start": [a * DX for t0, a, b, m in kept],
        "extent": [(b - a) * DX for t0, a, b, m in kept],
        "mean_slip": [m * DELTA_TH for t0, a, b, m in kept],
        "moment": [MU * (b - a) * DX * m * DELTA_TH for t0, a, b, m in kept],
        "max_slip_rate": [DELTA_TH / LEVEL_STEP for _ in kept],
        "n_clusters": [1, 1],
    }


def check_catalog(cat):
    exp = expected_catalog()
    # 1e-9: times are sums of a few doubles ~1e-3 s; differences of them (durations,
    # min Delta t) lose up to ~1e-16 * 1e-3 / 2e-7 ~ 1e-12 relative.
    for key, values in exp.items():
        np.testing.assert_allclose(cat[key], values, rtol=1e-9, err_msg=key)
    assert cat["n_nodal_slips"] == sum((b - a) * m for t0, a, b, m in SYNTHETIC_EVENTS)
    assert cat["n_events_detected"] == 5
    assert cat["n_events_excluded_first_last"] == 2
    assert cat["n_events_below_thresholds"] == 1
    assert cat["waiting_time_threshold"] == pytest.approx(15 * DELTA_TH / (V0 * N_NODES), rel=1e-15)


def test_events_from_synthetic_file(ss, tmp_path):
    path = tmp_path / "sampling.h5"
    ct = synthetic_crossing_time()
    with h5py.File(path, "w") as f:  # written with h5py, independently of the C++ writer
        g = f.create_group("slip_sampling")
        for k, v in dict(delta_th=DELTA_TH, dx=DX, v0=V0, mu=MU, D=5e-7, L=N_NODES * DX).items():
            g.attrs[k] = v
        g["x"] = np.arange(N_NODES) * DX
        g["crossing_time"] = ct
    cat = ss.detect_events_in_file(path)
    check_catalog(cat)
    # The in-memory path gives the same catalog.
    check_catalog(ss.detect_events(ct, delta_th=DELTA_TH, dx=DX, v0=V0, mu=MU))

    # Written as /events: readable with plain h5py under the documented names,
    # and read back through the bindings unchanged.
    ss.write_event_catalog(path, cat)
    with h5py.File(path, "r") as f:
        np.testing.assert_array_equal(f["events/T"][:], cat["duration"])
        np.testing.assert_array_equal(f["events/L_s"][:], cat["extent"])
        np.testing.assert_array_equal(f["events/M0"][:], cat["moment"])
    back = ss.read_event_catalog(path)
    check_catalog(back)
    run = ss.open_run(path)
    np.testing.assert_array_equal(run.events["t_start"], cat["t_start"])


def test_event_catalog_arrays_are_numpy(ss):
    cat = ss.detect_events(synthetic_crossing_time(), delta_th=DELTA_TH, dx=DX, v0=V0, mu=MU)
    assert isinstance(cat["t_start"], np.ndarray) and cat["t_start"].dtype == np.float64
    assert cat["n_clusters"].dtype == np.int32
    # A larger alpha (threshold >= the 1e-3 s gaps) merges everything into one
    # detected event, which is then excluded as first (and last).
    merged = ss.detect_events(synthetic_crossing_time(), delta_th=DELTA_TH, dx=DX, v0=V0, mu=MU, alpha=1e4)
    assert merged["n_events_detected"] == 1 and len(merged["t_start"]) == 0


def test_resolved_config_refuses_writes_with_the_override_that_works(ss):
    # A write to a section of a resolved Config used to change a temporary copy
    # and do nothing; now it raises and names the route that validates.
    cfg = ss.load_config(None, {"geometry.nodes": 64})
    with pytest.raises(AttributeError, match=r"with_overrides\(\{'material.density': 0.0\}\)"):
        cfg.material.density = 0.0
    with pytest.raises(AttributeError, match="read-only"):
        cfg.nodes = 128
    assert cfg.material.density == ss.Config().material.density
    # The override route changes and validates.
    assert cfg.with_overrides({"material.density": 1000.0}).material.density == 1000.0
    with pytest.raises(ss.ConfigError, match="density"):
        cfg.with_overrides({"material.density": 0.0})
    # The read-only material still goes where an ElasticMaterial is expected,
    # and copy() gives a mutable one.
    s = ss.strip_response(cfg.material, 0.1, 10.0, 1000.0 + 0j)
    assert np.isfinite(s)
    m = cfg.material.copy()
    m.density = 1000.0
    assert m.density == 1000.0 and cfg.material.density != 1000.0


def test_package_lists_only_its_api(ss):
    names = dir(ss)
    for helper in ("np", "os", "Any", "Callable", "Iterable", "annotations"):
        assert helper not in names
    assert set(ss.__all__) <= set(names)
    for name in ss.__all__:
        assert hasattr(ss, name), name
