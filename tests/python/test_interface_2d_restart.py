"""One process per run and restart points on a 2D interface (geometry.nodes_z
> 1, docs/3d.md): the same lock, output-path rules, restart points and
`slipstrip run --resume` as a 2D run (docs/reliability.md), tested as
tests/python/test_restart.py and test_restart_integrity.py test the 2D run.

Run: SLIPSTRIP_BUILD_DIR=$PWD/build PYTHONPATH=$PWD/python OMP_NUM_THREADS=1 \\
     /usr/bin/python3 -m pytest -q tests/python/test_interface_2d_restart.py
"""
import os
import random
import signal
from pathlib import Path

import h5py
import numpy as np
import pytest

from conftest import REPO
from test_restart import SEED, assert_files_identical, run_cli, stop_mid_run, stop_twice_and_resume

TINY_3D = REPO / "configs" / "3d" / "tiny.toml"
# 16 x 8 nodes, 0.5 transits (32 steps): a fraction of a second.
SMALL = ["--set", "geometry.nodes=16", "--set", "geometry.nodes_z=8", "--set", "time.duration_transits=0.5"]
# Every record a 2D interface has: time series every step, snapshots by time,
# slip sampling (delta_th = 1e-8 m: 0.28 delta_th per step at v0), the
# rupture front (|v| above 1.005 v0), three stations (x, z) (a node, between
# nodes) recorded every 3e-6 s (about two steps of 1.43e-6 s); 3 transits, 195 steps.
RECORDS = SMALL + ["--set", "time.duration_transits=3", "--set", "output.snapshot_interval=1e-5", "--set", "output.delta_th=1e-8",
                   "--set", "output.front_slip_rate=2.01e-3",
                   "--set", "output.stations=[0.0, 0.1, 0.0703125]", "--set", "output.stations_z=[0.0, 0.2, 0.046875]",
                   "--set", "output.station_interval=3e-6"]
CASES = {
    "strips": [],
    "half-spaces": ["--set", 'geometry.height="inf"', "--set", "time.beta=0.24"],
}


@pytest.fixture(autouse=True)
def one_thread(monkeypatch):
    monkeypatch.setenv("OMP_NUM_THREADS", "1")


def _one_line(r):
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    assert lines, r.stderr
    return lines[-1]


def test_a_2d_interface_run_is_refused_while_another_process_holds_its_lock(cli, tmp_path, slipstrip_module):
    out = tmp_path / "run.h5"
    lock_path = Path(str(out) + ".lock")
    with slipstrip_module.paths.lock_run(out):
        r = run_cli(cli, "run", TINY_3D, *SMALL, "--out", out, "--quiet")
        assert r.returncode == 2, r.stderr
        line = _one_line(r)
        # The 2D run's message (io/file_lock.hpp): who holds it and where.
        assert "is in use by another process" in line and f"pid {os.getpid()}" in line and str(lock_path) in line
        assert not out.exists()  # refused before anything is written
        # --overwrite does not get past the lock either.
        r = run_cli(cli, "run", TINY_3D, *SMALL, "--out", out, "--overwrite", "--quiet")
        assert r.returncode == 2 and "is in use by another process" in _one_line(r), r.stderr
    # Released: the run goes ahead and releases it at the end.
    r = run_cli(cli, "run", TINY_3D, *SMALL, "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    assert not lock_path.exists()
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "completed"


def test_python_run_of_a_2d_interface_honours_the_lock(tmp_path, slipstrip_module):
    out = tmp_path / "run.h5"
    config = slipstrip_module.load_config(TINY_3D, overrides=[s for s in SMALL if s != "--set"])
    with slipstrip_module.paths.lock_run(out):
        with pytest.raises(slipstrip_module.LockHeldError, match="is in use by another process"):
            slipstrip_module.run(config, out)
    assert not out.exists()


def _reference(cli, tmp_path, args):
    out = tmp_path / "reference.h5"
    r = run_cli(cli, "run", TINY_3D, *args, "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    assert not Path(str(out) + ".restart").exists()  # a completed run leaves no restart point
    return out


def _steps(path):
    with h5py.File(path, "r") as f:
        return len(f["timeseries/time"]) - 1  # a row per step plus t = 0


def _assert_identical_with_sidecar(reference, resumed):
    assert_files_identical(reference, resumed)
    # The XDMF sidecar names the file; otherwise the same text.
    a = reference.with_suffix(".xdmf").read_text().replace(reference.name, "RUN")
    b = resumed.with_suffix(".xdmf").read_text().replace(resumed.name, "RUN")
    assert a == b


@pytest.mark.parametrize("case", list(CASES))
def test_interrupted_twice_and_resumed_equals_uninterrupted(cli, tmp_path, case):
    args = RECORDS + CASES[case]
    reference = _reference(cli, tmp_path, args)
    total = _steps(reference)
    with h5py.File(reference, "r") as f:
        # The records this test is about are there and not trivial.
        assert len(f["snapshots/time"]) >= 5 and f["slip_sampling/crossing_time"].shape[0] >= 5
        assert np.isfinite(f["rupture_front/arrival_time"][:]).any()
        assert len(f["stations/time"]) >= 60 and f["stations/slip_z"].shape[1] == 3
    rng = random.Random(f"{SEED} 2D interface {case}")
    first = rng.randrange(1, total // 2)
    second = rng.randrange(first + 1, total)
    out = tmp_path / "resumed.h5"

    def after_first_stop(restart):
        with h5py.File(restart, "r") as c:
            assert c["history"].attrs["kind"] == "interface 2d"
            # The z components and |v| of the 2D interface are in the restart point.
            for name in ("slip_z", "slip_rate_z", "shear_stress_z", "speed"):
                assert c["simulation"][name].shape == (16 * 8,)

    stop_twice_and_resume(cli, TINY_3D, args, out, first, second, after_first_stop)
    print(f"{case}: {total} steps, interrupted after {first} and {second}")
    _assert_identical_with_sidecar(reference, out)


def test_sigkill_after_periodic_restart_points_resumes_identically(cli, tmp_path):
    # Restart points every 0.05 s of wall time and frequent flushes: when
    # SIGKILL lands, the file holds records written after the last restart
    # point, which the resume cuts away and writes again.  500 transits last
    # ~0.8 s on a quiet core, so the kill (0.05-0.3 s after the first restart
    # point) lands mid-run; 30 transits (0.03 s) ended before any restart point.
    args = RECORDS + ["--set", "time.duration_transits=500", "--set", "output.snapshot_interval=2e-4",
                      "--set", "output.checkpoint_interval=0.05", "--set", "output.flush_interval=0.01"]
    reference = _reference(cli, tmp_path, args)
    out = tmp_path / "resumed.h5"
    restart = Path(str(out) + ".restart")
    stop_mid_run(cli, TINY_3D, args, out, restart.exists, signal.SIGKILL, SEED + 2)
    with h5py.File(restart, "r") as c:
        at = int(c["simulation"].attrs["step_index"])
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 0, r.stderr
    print(f"SIGKILL; resumed from step {at} of {_steps(reference)}")
    _assert_identical_with_sidecar(reference, out)


def test_sigterm_writes_a_restart_point_and_the_resume_completes_identically(cli, tmp_path):
    args = RECORDS + ["--set", "time.duration_transits=500", "--set", "output.snapshot_interval=2e-4"]
    reference = _reference(cli, tmp_path, args)
    out = tmp_path / "resumed.h5"
    stop_mid_run(cli, TINY_3D, args, out, out.exists, signal.SIGTERM, SEED + 3)
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 0, r.stderr
    _assert_identical_with_sidecar(reference, out)


def _interrupted(cli, tmp_path, steps=60):
    out = tmp_path / "run.h5"
    r = run_cli(cli, "run", TINY_3D, *RECORDS, "--out", out, "--quiet", "--stop-after-steps", steps)
    assert r.returncode == 143, r.stderr
    return out, Path(str(out) + ".restart")


@pytest.mark.parametrize("field", ["slip_z", "speed", "slip_rate"])
def test_a_changed_value_of_a_2d_interface_field_is_damage(cli, tmp_path, field):
    # The checksum covers the z components and |v| as it covers the x ones.
    out, restart = _interrupted(cli, tmp_path)
    with h5py.File(restart, "r+") as c:
        data = c["simulation"][field][()]
        data[5] = np.nextafter(data[5], np.inf)
        c["simulation"][field][...] = data
    before = out.read_bytes()
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 2, r.stderr
    assert f"restart point '{restart}' is damaged" in r.stderr
    assert out.read_bytes() == before


def test_a_restart_point_of_another_grid_is_refused(cli, tmp_path):
    # A restart point whose fields do not fit this run (without a checksum, so
    # only the shape checks stand in the way): refused naming the field.
    out, restart = _interrupted(cli, tmp_path)
    with h5py.File(restart, "r+") as c:
        values = c["simulation"]["slip_z"][()]
        del c["simulation"]["slip_z"]
        c["simulation"]["slip_z"] = values[:-8]
        del c.attrs["checksum"]
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 2, r.stderr
    assert "slip_z has 120 values" in r.stderr and "128 nodes" in r.stderr


def test_stations_without_z_positions_are_refused_on_a_2d_interface(cli, tmp_path):
    r = run_cli(cli, "run", TINY_3D, *SMALL, "--set", "output.stations=[0.1]", "--out", tmp_path / "x.h5",
                "--quiet")
    assert r.returncode == 2 and "output.stations_z has 0 positions and output.stations 1" in r.stderr, r.stderr
