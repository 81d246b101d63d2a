"""End-to-end tests of the slipstrip CLI: the run file survives SIGKILL and
Ctrl-C, divergence is diagnosed, config errors fail fast, and the JSON
outputs of `stability` and `bench` have the documented keys."""
import json
import signal
import subprocess
import time

import h5py
import numpy as np
import pytest
from figure_checks import assert_figure

QUICK = ["--set", "geometry.nodes=128", "--set", "output.snapshot_interval=0"]


def run(cli, *args, **kw):
    return subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True, **kw)


def wait_for_rows(path, minimum, timeout=60.0):
    """Poll the file with plain h5py opens (as a user would) until it holds data."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        try:
            with h5py.File(path, "r") as f:
                if f["timeseries/time"].shape[0] >= minimum:
                    return
        except (OSError, KeyError):
            pass  # not created yet, or a flush holds the lock for a moment
        time.sleep(0.1)
    raise AssertionError(f"{path} never reached {minimum} rows")


def test_sigkill_leaves_a_readable_file(cli, repo, tmp_path):
    out = tmp_path / "killed.h5"
    proc = subprocess.Popen([str(cli), "run", str(repo / "configs/quickstart.toml"), *QUICK,
                             "--set", "output.flush_interval=0.2", "--set", "time.duration_transits=1000",
                             "--out", str(out), "--quiet"], stderr=subprocess.DEVNULL)
    try:
        wait_for_rows(out, 100)
        time.sleep(0.5)
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    assert proc.returncode == -signal.SIGKILL
    with h5py.File(out, "r") as f:
        t = f["timeseries/time"][:]
        vmax = f["timeseries/max_slip_rate"][:]
        assert t.size >= 100 and np.all(np.diff(t) > 0) and np.all(np.isfinite(vmax))
        assert f.attrs["status"] == "running"       # killed: never closed
        assert "[geometry]" in f.attrs["config"]     # self-describing even after a kill
        assert f["slip_sampling/crossing_time"].shape[1] == 128


def test_ctrl_c_closes_the_file_cleanly(cli, repo, tmp_path):
    out = tmp_path / "interrupted.h5"
    proc = subprocess.Popen([str(cli), "run", str(repo / "configs/quickstart.toml"), *QUICK,
                             "--set", "output.flush_interval=0.2", "--set", "time.duration_transits=1000",
                             "--out", str(out), "--quiet"], stderr=subprocess.PIPE, text=True)
    wait_for_rows(out, 50)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "interrupted"
        assert f.attrs["end_time"] != ""
        assert f["timeseries/time"].shape[0] >= 50


def test_divergence_stops_with_a_diagnostic_and_a_readable_file(cli, repo, tmp_path):
    # A prescribed slip so large that the stress overflows to inf.
    out = tmp_path / "diverged.h5"
    r = run(cli, "run", repo / "configs/quickstart.toml", *QUICK,
            "--set", "interface.law=prescribed_slip", "--set", "interface.slip_amplitude=1e306",
            "--set", "interface.rise_time=1e-6", "--set", "time.duration_transits=1",
            "--out", out, "--quiet", timeout=120)
    assert r.returncode == 3, r.stderr
    assert "non-finite" in r.stderr and "node" in r.stderr and "t = " in r.stderr
    with h5py.File(out, "r") as f:
        assert f.attrs["status"].startswith("diverged: non-finite")
        assert np.all(np.isfinite(f["timeseries/max_slip_rate"][:]))  # nothing non-finite was written


def test_finite_blow_up_is_diagnosed_not_recorded_forever(cli, repo, tmp_path):
    # Slip that grows huge but stays finite must not make the slip sampling
    # record ~1e300 threshold crossings (it used to exhaust memory).
    out = tmp_path / "blowup.h5"
    r = run(cli, "run", repo / "configs/quickstart.toml", "--set", "geometry.nodes=32",
            "--set", "interface.law=free", "--set", "interface.stress_amplitude=1e300",
            "--set", "interface.rise_time=1e-9", "--set", "time.duration_transits=1",
            "--out", out, "--quiet", timeout=60)
    assert r.returncode == 3, r.stderr
    assert "diverging" in r.stderr or "non-finite" in r.stderr
    with h5py.File(out, "r") as f:
        assert f.attrs["status"].startswith("diverged: ")


@pytest.mark.parametrize("override, expected", [
    ("geometry.lenght=3", "did you mean 'geometry.length'"),
    ("geometry.nodes=many", "geometry.nodes"),
    ("material.poisson_ratio=0.7", "material.poisson_ratio"),
    ("state.law=healing", "state.law"),
])
def test_config_errors_fail_fast_naming_the_key(cli, repo, tmp_path, override, expected):
    t0 = time.time()
    r = run(cli, "run", repo / "configs/quickstart.toml", "--set", override, "--out", tmp_path / "x.h5")
    assert r.returncode == 2
    assert expected in r.stderr
    assert time.time() - t0 < 10  # before any computation
    assert not (tmp_path / "x.h5").exists()


def test_stability_json(cli, repo):
    # Table S1 as printed (mu = 9 GPa), where Lc(H = 0.1 m) = 0.66 m lies between 0.5 and 0.8 m; the
    # config itself now holds the paper-as-run material (E = 9 GPa, Lc = 0.38 m; docs/stability.md).
    r = run(cli, "stability", repo / "configs/reference.toml", "--wavelength", "0.5,0.8,1.0", "--json",
            "--set", "material.shear_modulus=9e9")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert set(d) >= {"wavelengths", "growth_rate", "frequency"}
    assert d["wavelengths"] == [0.5, 0.8, 1.0]
    assert d["growth_rate"][0] < 0 < d["growth_rate"][1] < d["growth_rate"][2]
    r = run(cli, "stability", repo / "configs/reference.toml", "--height-range", "0.05:0.2:4", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["heights"] == pytest.approx([0.05, 0.1, 0.15, 0.2])
    assert np.all(np.diff(d["critical_wavelength"]) > 0)


def test_bench_json_keys(cli):
    r = run(cli, "bench", "--json", "--nodes", "256", "--steps", "5", timeout=300)
    assert r.returncode == 0, r.stderr
    rows = [json.loads(line) for line in r.stdout.splitlines()]
    assert len(rows) == 3
    for row in rows:
        assert set(row) >= {"N", "height", "length", "us_per_step", "floor_us_per_step", "rss_mib"}
        assert row["N"] == 256 and row["us_per_step"] > 0 and row["rss_mib"] > 0
    assert [row["height"] for row in rows] == [0.1, 1.0, None]


def test_stability_writes_csv_and_fig_s2_style_png(cli, repo, tmp_path):
    out = tmp_path / "lc.csv"
    r = run(cli, "stability", repo / "configs/reference.toml", "--height-range", "0.05:0.2:3",
            "--out", out, timeout=120)
    assert r.returncode == 0, r.stderr
    lines = out.read_text().splitlines()
    assert lines[0] == "height_m,critical_wavelength_m"
    assert lines[-1].startswith("inf,")                      # the H -> infinity line
    assert len(lines) == 1 + 3 + 1
    png = tmp_path / "lc.png"
    assert_figure(png)


def test_events_cli_on_a_file_holding_only_slip_sampling(cli, tmp_path):
    """Three crack-like events on nodes 10..20 of 32 (5 levels of delta_th each,
    in 50 ns), separated by long stick periods: first and last are excluded, so
    the catalog holds exactly the middle one, with L_s = 11 dx and u_mean = 5 delta_th."""
    n_nodes, delta_th, dx, v0 = 32, 1e-8, 0.01, 2e-3
    starts = [1e-3, 2e-3, 3e-3]
    crossing = np.full((15, n_nodes), np.nan)
    for e, t0 in enumerate(starts):
        for level in range(5):
            for i in range(10, 21):
                crossing[5 * e + level, i] = t0 + 1e-8 * level + 1e-10 * (i - 10)
    path = tmp_path / "sampling_only.h5"
    with h5py.File(path, "w") as f:
        g = f.create_group("slip_sampling")
        for k, v in dict(delta_th=delta_th, dx=dx, v0=v0, mu=9e9, D=5e-7, L=n_nodes * dx).items():
            g.attrs[k] = v
        g["x"] = np.arange(n_nodes) * dx
        g["crossing_time"] = crossing
    r = run(cli, "events", path, "--csv", tmp_path / "catalog.csv")
    assert r.returncode == 0, r.stderr
    with h5py.File(path, "r") as f:
        ev = f["events"]
        assert ev["t_start"][:] == pytest.approx([starts[1]])
        assert ev["L_s"][:] == pytest.approx([11 * dx])
        assert ev["u_mean"][:] == pytest.approx([5 * delta_th])
        assert ev["M0"][:] == pytest.approx([9e9 * 11 * dx * 5 * delta_th])
        assert list(ev["n_clusters"][:]) == [1]
    assert len((tmp_path / "catalog.csv").read_text().splitlines()) == 2  # header + 1 event
