"""What `slipstrip run` says before it starts (config/resource_estimate.cpp
run_header, docs/config.md "Warnings"), the plausibility warnings of the
config schema, and the help of the subcommands the CLI hands to Python.

The originals: a height in mm given as metres (H/L = 50), a driving
velocity in mm/s given as m/s (36 delta_th per step) and a normal stress of
1 Pa all ran without a word; `slipstrip export --help` listed only -h.

Run: /usr/bin/python3 -m pytest tests/python/test_run_header.py
"""
import subprocess
import warnings

import h5py
import pytest

SHORT = ["--set", "geometry.nodes=32", "--set", "time.duration_transits=0.2", "--set", "output.snapshot_interval=0"]


def run(cli, repo, tmp_path, *overrides, name="r.h5"):
    cmd = [str(cli), "run", str(repo / "configs/quickstart.toml"), "--quiet", "--out", str(tmp_path / name), *SHORT]
    for o in overrides:
        cmd += ["--set", o]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300)


def test_header_states_the_cost_before_the_run(cli, repo, tmp_path):
    r = run(cli, repo, tmp_path)
    assert r.returncode == 0, r.stderr
    lines = r.stderr.splitlines()
    head = lines[0]
    assert head.startswith("run: ") and "steps of dt = " in head and "L/c_s" in head and "wall time ~" in head
    assert "H = 0.025 m, H/L = 0.05, N = 32" in lines[1] and "history operator ~" in lines[1]
    assert "output up to ~" in lines[2] and "slip per step at v0: " in lines[2] and "delta_th" in lines[2]
    assert not any(l.startswith("warning:") for l in lines)  # the quickstart is plausible
    # The header's numbers are the run's: its dt and step count (3 significant digits).
    with h5py.File(tmp_path / "r.h5", "r") as f:
        t = f["timeseries/time"][:]
    dt = t[1] - t[0]
    assert f"dt = {dt:.3g} s" in head
    assert f"{t.size - 1:.3g} steps" in head
    assert f"= {2e-3 * dt / 1e-8:.3g} delta_th" in lines[2]  # v0 dt / delta_th of the quickstart


@pytest.mark.parametrize("override, key", [
    ("loading.normal_stress=1", "loading.normal_stress = 1 Pa"),
    ("loading.driving_velocity=2", "each time step slips v0 dt"),
    ("geometry.height=50", "geometry.height = 50 m is H/L = 100"),  # over L = 0.5 m
])
def test_implausible_values_warn_and_the_run_goes_on(cli, repo, tmp_path, override, key):
    r = run(cli, repo, tmp_path, override)
    warnings_ = [l for l in r.stderr.splitlines() if l.startswith("warning: ")]
    assert len(warnings_) == 1 and key in warnings_[0], r.stderr
    assert r.returncode == 0, r.stderr  # a warning, not an error


def test_python_run_issues_config_warnings(slipstrip_module, repo, tmp_path):
    slipstrip = slipstrip_module
    overrides = {"geometry.nodes": 32, "time.duration_transits": 0.2, "output.snapshot_interval": 0}
    cfg = slipstrip.load_config(repo / "configs/quickstart.toml", overrides)
    assert cfg.warnings() == []
    assert cfg.run_header().startswith("run: ")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a plausible run warns about nothing
        slipstrip.run(cfg, tmp_path / "ok.h5")
    with pytest.warns(slipstrip.ConfigWarning, match="loading.driving_velocity is in m/s"):
        slipstrip.run(cfg.with_overrides({"loading.driving_velocity": 2.0}), tmp_path / "fast.h5")


def test_scan_dry_run_shows_the_warnings(slipstrip_module, repo, tmp_path, capsys):
    from slipstrip import scan
    scan_file = tmp_path / "s.toml"
    scan_file.write_text(f'base = "{repo / "configs/quickstart.toml"}"\n[[parameter]]\n'
                         'key = "loading.normal_stress"\nvalues = [1e6, 1.0]\n')
    assert scan.main([str(scan_file), "--dry-run"]) == 0  # valid, so the scan may run
    err = capsys.readouterr().err
    warned = [l for l in err.splitlines() if l.startswith("warning: ")]
    assert len(warned) == 1 and warned[0].startswith("warning: run 1 (run_0001.h5): loading.normal_stress = 1 Pa")


@pytest.mark.parametrize("command, option", [("export", "--seas"), ("analyze", "--out-dir"), ("scan", "--dry-run"),
                                             ("plot", "--kind"), ("report", "--allow-missing"),
                                             ("transition", "--csv")])
def test_python_subcommands_show_their_own_help(cli, command, option):
    r = subprocess.run([str(cli), command, "--help"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert option in r.stdout and "usage:" in r.stdout
