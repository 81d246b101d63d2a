"""The run file is readable with a plain h5py.File(path, "r") while the run goes
on, and after the writer is killed with SIGKILL it still holds every row up to
the last flush.

The writer is the doctest helper in tests/cpp/test_solver_run_output.cpp
("writer child ..."), run as
    test_solver_run_output -tc="writer child*" --no-skip=true
It writes a deterministic run (step k at t = k*dt, node i slipping at a constant
rate) and prints "flushed <steps>" after every flush.  The binary is taken from
$SLIPSTRIP_TEST_SOLVER_RUN_OUTPUT, else the newest build*/test_solver_run_output in
the repository.

Run: /usr/bin/python3 -m pytest tests/python/test_output_readable.py
"""
import os
import signal
import subprocess
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]

# Must match write_until_killed() in tests/cpp/test_solver_run_output.cpp.
NODES = 16
DT = 1e-3
DELTA_TH = 1e-6


def writer_rate(i):
    return (1.0 + 0.1 * i / NODES) * 1e-3  # [m/s]


def find_writer():
    explicit = os.environ.get("SLIPSTRIP_TEST_SOLVER_RUN_OUTPUT")
    if explicit:
        return Path(explicit)
    candidates = sorted(REPO.glob("build*/test_solver_run_output"), key=lambda p: p.stat().st_mtime)
    if not candidates:
        pytest.skip("test_solver_run_output not built (cmake --build <dir> --target test_solver_run_output)")
    return candidates[-1]


def wait_for_flushes(proc, count, deferred=None):
    """Reads the writer's stdout until `count` written flushes; returns the last
    flushed step count.  Deferred flushes (a reader held the file) are appended
    to the list `deferred` if given."""
    steps = None
    seen = 0
    while seen < count:
        line = proc.stdout.readline()
        assert line, "writer exited early: " + proc.stderr.read()
        if line.startswith("flushed "):
            steps = int(line.split()[1])
            seen += 1
        elif line.startswith("deferred ") and deferred is not None:
            deferred.append(int(line.split()[1]))
    return steps


def check_file(f, flushed_steps):
    """Every row up to `flushed_steps` is there, with exactly the values written."""
    t = f["timeseries/time"][:]
    n = len(t)
    assert n >= flushed_steps
    k = np.arange(1, n + 1)
    np.testing.assert_array_equal(t, k * DT)
    np.testing.assert_array_equal(f["timeseries/max_slip_rate"][:], k.astype(float))
    np.testing.assert_array_equal(f["timeseries/mean_shear_stress"][:], -k.astype(float))
    assert f["timeseries/time"].attrs["units"] == "s"
    assert f["timeseries/max_slip_rate"].attrs["units"] == "m/s"

    snap_t = f["snapshots/time"][:]
    assert len(snap_t) >= flushed_steps // 10
    ks = 10 * np.arange(1, len(snap_t) + 1)
    np.testing.assert_array_equal(snap_t, ks * DT)
    rate = f["snapshots/slip_rate"][:]
    assert rate.shape == (len(snap_t), NODES)
    np.testing.assert_array_equal(rate, ks[:, None] * 100.0 + np.arange(NODES)[None, :])
    assert f["snapshots"].attrs["trigger"] == "time"

    g = f["slip_sampling"]
    assert g.attrs["delta_th"] == DELTA_TH
    assert g["x"].shape == (NODES,)
    ct = g["crossing_time"][:]
    assert ct.shape[1] == NODES
    for i in range(NODES):
        # Levels reached by the last flushed step must all be there; slip is
        # linear in time, so the crossing of level j is at (j+1) delta / rate.
        # rtol 1e-9: rounding of k*dt products only (dt = 1e-3 s).
        reached = int(np.floor(flushed_steps * DT * writer_rate(i) / DELTA_TH * (1 - 1e-12)))
        assert ct.shape[0] >= reached
        expected = (np.arange(reached) + 1) * DELTA_TH / writer_rate(i)
        np.testing.assert_allclose(ct[:reached, i], expected, rtol=1e-9)
        # Anything beyond is either a later crossing or NaN (not reached yet).
        rest = ct[reached:, i]
        later = rest[~np.isnan(rest)]
        assert np.all(later >= flushed_steps * DT - DT)


def open_plain(path, attempts=20):
    """Plain h5py open.  The writer has the file open only for the few ms of a
    flush; an open that lands inside one may fail, so retry briefly."""
    for _ in range(attempts - 1):
        try:
            return h5py.File(path, "r")
        except OSError:
            time.sleep(0.003)
    return h5py.File(path, "r")


def test_readable_while_running_and_after_sigkill(tmp_path):
    writer = find_writer()
    path = tmp_path / "run.h5"
    env = dict(os.environ, SLIPSTRIP_WRITER_CHILD_PATH=str(path))
    proc = subprocess.Popen(
        [str(writer), "-tc=writer child*", "--no-skip=true"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        flushed = wait_for_flushes(proc, 4)
        assert proc.poll() is None
        # While the run goes on: plain open, no SWMR, no environment variables.
        with open_plain(path) as f:
            assert f.attrs["status"] == "running"
            assert f.attrs["config"] == "[geometry]\nnodes = 16\n"
            assert isinstance(f.attrs["git_hash"], str) and f.attrs["git_hash"]
            assert f.attrs["start_time"].endswith("Z")
            check_file(f, flushed)
            # Held open across the writer's flush attempts (one every ~6 ms):
            # the writer must defer rather than change the file under us, so
            # a second read sees exactly the same extents.
            lengths = {name: f[name].shape for name in
                       ("timeseries/time", "timeseries/mean_shear_stress",
                        "snapshots/slip", "slip_sampling/crossing_time")}
            time.sleep(0.3)
            for name, shape in lengths.items():
                assert f[name].shape == shape, name
            check_file(f, flushed)
        deferred = []
        flushed = wait_for_flushes(proc, 3, deferred)
        # The writer tried to flush while we held the file (~50 attempts in
        # 0.3 s) and reported the deferral; >= 1 keeps this robust under load.
        assert len(deferred) >= 1
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait()
    assert proc.returncode == -signal.SIGKILL
    # Flush reports printed before the kill count too.
    for line in proc.stdout.read().splitlines():
        if line.startswith("flushed "):
            flushed = int(line.split()[1])

    with h5py.File(path, "r") as f:
        assert f.attrs["status"] == "running"  # killed: never closed
        assert f.attrs["end_time"] == ""
        check_file(f, flushed)
