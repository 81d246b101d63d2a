"""Restart points and run files that can no longer be destroyed or falsified
(docs/reliability.md, "Restart" and "One process per run"):

* a restart point is validated field by field before a resume (time, step,
  next output times: finite and consistent with each other and the config);
* its content carries a checksum: a flipped bit in any dataset or attribute is
  refused, a restart point without a checksum is resumed with a warning;
* a restart point that is a directory or a device is reported as such;
* one process per run and its restart point (an flock that a SIGKILL
  releases), so two `--resume` of one run cannot both write it;
* a new run never deletes a restart point it did not write, unless
  --overwrite.

Each test starts from the behaviour it reproduces (in its comment).  Tiny
runs: configs/quickstart.toml at N = 64.
"""
import os
import signal
import subprocess
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from test_restart import QUICKSTART, TINY, CASES, assert_files_identical, reference_run, run_cli, wait_for

ARGS = TINY + CASES["modal strip"]


@pytest.fixture(autouse=True)
def one_thread(monkeypatch):
    monkeypatch.setenv("OMP_NUM_THREADS", "1")


def _one_line(r):
    lines = [line for line in r.stderr.splitlines() if line.strip() and not line.startswith("slipstrip ")]
    assert len(lines) == 1, r.stderr
    return lines[0]


def _interrupted(cli, tmp_path, steps=300, args=ARGS, name="run.h5"):
    out = tmp_path / name
    r = run_cli(cli, "run", QUICKSTART, *args, "--out", out, "--quiet", "--stop-after-steps", steps)
    assert r.returncode == 143, r.stderr
    return out, Path(str(out) + ".restart")


def _edit(restart, group, attr, value):
    """Change one attribute (or one element of a dataset: attr = (name, index))
    of the restart point and delete its checksum, as in a restart point
    written before checksums, so that only the field validation stands
    between the edit and a resume."""
    with h5py.File(restart, "r+") as f:
        if isinstance(attr, tuple):
            name, index = attr
            data = f[group][name][()]
            data[index] = value
            f[group][name][...] = data
        else:
            f[group].attrs[attr] = value
        del f.attrs["checksum"]


@pytest.mark.parametrize("group, attr, value, names", [
    # Was: a restart time of -1 s was accepted; the resumed run did its remaining
    # steps, wrote no time-series rows for them and exited 0 as "completed".
    ("simulation", "time", -1.0, "time = -1"),
    ("simulation", "time", np.nan, "time = nan"),
    ("simulation", "time", 1.0, "time = 1"),                       # not step * dt
    ("simulation", "step_index", np.int64(299), "step_index = 299"),  # time is of step 300
    ("run", "next_timeseries", np.nan, "next_timeseries = nan"),
    ("run", "next_timeseries", 1e-9, "next_timeseries = 1e-09"),   # rows say otherwise
    ("run", "next_snapshot", -np.inf, "next_snapshot = -inf"),
    ("run", "next_station", 1.0, "next_station = 1"),
    ("output", "timeseries_rows", np.int64(300), "timeseries_rows = 300"),  # a row every step: 301
    ("output", "crossing_rows", np.int64(0), "crossing_rows = 0"),       # levels were reached
    ("output", "slip_recorded", np.int64(0), "slip_recorded = 0"),
    ("output", ("levels_reached", 5), np.uint64(0), "levels_reached[5] = 0"),   # its slip is past level 1
    ("output", ("next_threshold", 7), 1.0, "next_threshold[7] = 1"),
    ("output", ("rupture_front", 3), 1.0, "rupture_front[3] = 1"),      # an arrival after the time
])
def test_edited_restart_fields_are_refused_by_name(cli, tmp_path, group, attr, value, names):
    out, restart = _interrupted(cli, tmp_path)
    _edit(restart, group, attr, value)
    before = out.read_bytes(), restart.read_bytes()
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    line = _one_line(r)
    assert r.returncode == 2, r.stderr
    assert f"restart point '{restart}'" in line and names in line, line
    assert (out.read_bytes(), restart.read_bytes()) == before


@pytest.mark.parametrize("triggers", [
    # time series every 3 dt, snapshots by time and by slip at once (one count
    # for both), stations more often than dt (a row every step, its trigger
    # falling behind the time)
    ["--set", "output.timeseries_interval=2.1e-6", "--set", "output.snapshot_slip_increment=5e-8",
     "--set", "output.station_interval=1e-7"],
    # no snapshots, no stations, no slip sampling, no rupture front
    ["--set", "output.snapshot_interval=0", "--set", "output.stations=[]", "--set", "output.delta_th=0",
     "--set", "output.front_slip_rate=0"],
], ids=["mixed triggers", "records off"])
def test_genuine_restart_points_of_every_trigger_mode_pass_the_validation(cli, tmp_path, triggers):
    # The field validation must never refuse a restart point the solver wrote:
    # interrupted at two steps, resumed twice, the file is the uninterrupted one.
    args = ARGS + triggers
    reference = reference_run(cli, tmp_path, args)
    out, restart = _interrupted(cli, tmp_path, steps=333, args=args)
    r = run_cli(cli, "run", "--resume", out, "--quiet", "--stop-after-steps", 901)
    assert r.returncode == 143, r.stderr
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 0, r.stderr
    assert "warning" not in r.stderr
    assert_files_identical(reference, out)


def test_the_issue_reproducer_negative_time_with_its_checksum_is_damage(cli, tmp_path):
    # The edit of the original report (time = -1 s, nothing else touched).
    out, restart = _interrupted(cli, tmp_path)
    with h5py.File(restart, "r+") as f:
        f["simulation"].attrs["time"] = -1.0
    before = out.read_bytes()
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 2, r.stderr
    line = _one_line(r)
    assert "is damaged" in line and "checksum" in line and str(restart) in line
    assert out.read_bytes() == before and restart.exists()


def _flip_bit(restart, path, bit=12):
    with h5py.File(restart, "r+") as f:
        data = f[path][()]
        raw = data.view(np.uint64)
        raw[len(raw) // 2] ^= np.uint64(1) << np.uint64(bit)
        f[path][...] = raw.view(data.dtype)


@pytest.mark.parametrize("path", ["simulation/slip_rate", "simulation/state", "output/next_threshold"])
def test_a_flipped_bit_in_restart_data_is_refused(cli, tmp_path, path):
    # Was: HDF5 stored no checksum, so a bit flip in the data resumed silently.
    out, restart = _interrupted(cli, tmp_path)
    _flip_bit(restart, path)
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 2, r.stderr
    line = _one_line(r)
    assert "checksum" in line and "damaged" in line and str(restart) in line


def test_a_flipped_bit_in_a_history_array_or_counter_is_refused(cli, tmp_path):
    out, restart = _interrupted(cli, tmp_path)
    with h5py.File(restart, "r") as f:
        arrays = sorted(f["history/arrays"])
        counters = sorted(f["history/counters"].attrs)
    _flip_bit(restart, f"history/arrays/{arrays[0]}", bit=3)
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 2 and "checksum" in r.stderr, r.stderr
    out, restart = _interrupted(cli, tmp_path, name="run2.h5")
    if counters:
        with h5py.File(restart, "r+") as f:
            f["history/counters"].attrs[counters[0]] ^= np.int64(1)
        r = run_cli(cli, "run", "--resume", out, "--quiet")
        assert r.returncode == 2 and "checksum" in r.stderr, r.stderr


def test_a_restart_point_without_checksum_resumes_with_a_warning(cli, tmp_path):
    # Restart points written before checksums: accepted (the fields are still
    # validated), with one warning line; the result is the uninterrupted run's.
    reference = reference_run(cli, tmp_path, ARGS)
    out, restart = _interrupted(cli, tmp_path)
    with h5py.File(restart, "r+") as f:
        del f.attrs["checksum"]
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 0, r.stderr
    warnings = [line for line in r.stderr.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 1 and "no checksum" in warnings[0], r.stderr
    assert_files_identical(reference, out)


def test_python_resume_warns_of_a_missing_checksum(cli, tmp_path, slipstrip_module):
    import warnings
    reference = reference_run(cli, tmp_path, ARGS)
    out, restart = _interrupted(cli, tmp_path)
    with h5py.File(restart, "r+") as f:
        del f.attrs["checksum"]
    before = out.read_bytes(), restart.read_bytes()
    # As an error (python -W error): raised before the run file is touched.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(UserWarning, match="has no checksum"):
            slipstrip_module.resume(out)
    assert (out.read_bytes(), restart.read_bytes()) == before
    with pytest.warns(UserWarning, match="has no checksum"):
        result = slipstrip_module.resume(out)
    assert result.status == "completed"
    assert_files_identical(reference, out)


@pytest.mark.parametrize("kind", ["directory", "device"])
def test_a_restart_point_that_is_not_a_file_says_what_it_is(cli, tmp_path, kind):
    # Was: both reported as "does not exist".
    out, restart = _interrupted(cli, tmp_path)
    restart.unlink()
    if kind == "directory":
        restart.mkdir()
        expected = "is not a regular file (a directory)"
    else:
        restart.symlink_to("/dev/zero")
        expected = "is not a regular file"
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 2, r.stderr
    line = _one_line(r)
    assert expected in line and "does not exist" not in line and str(restart) in line


def test_a_new_run_keeps_a_restart_point_it_did_not_write(cli, tmp_path):
    # Was: `run --out prev.h5` (no prev.h5, no --overwrite) deleted prev.h5.restart.
    out, restart = _interrupted(cli, tmp_path, name="prev.h5")
    out.unlink()
    before = restart.read_bytes()
    r = run_cli(cli, "run", QUICKSTART, *ARGS, "--out", out, "--quiet")
    assert r.returncode == 2, r.stderr
    line = _one_line(r)
    assert f"'{restart}' already exists" in line and "--overwrite" in line
    assert restart.read_bytes() == before and not out.exists()
    r = run_cli(cli, "run", QUICKSTART, *ARGS, "--out", out, "--quiet", "--overwrite",
                "--set", "time.duration_transits=1")
    assert r.returncode == 0, r.stderr
    assert not restart.exists()


def test_dangling_symlink_out_names_its_target(cli, tmp_path):
    # Was: "cannot be written: File exists".
    link = tmp_path / "dangling.h5"
    link.symlink_to(tmp_path / "nowhere" / "target.h5")
    r = run_cli(cli, "run", QUICKSTART, *ARGS, "--out", link, "--quiet")
    assert r.returncode == 2
    line = _one_line(r)
    assert "is a symbolic link to" in line and "target.h5" in line and "does not exist" in line


def _slow_args(tmp_path):
    # ~200000 steps (tens of seconds) with restart points every 16 steps, so the
    # first process is surely still running while the second one tries.
    return ARGS + ["--set", "time.duration_transits=2000", "--set", "output.snapshot_interval=1e-3",
                   "--set", "output.checkpoint_interval=0.05"]


def _resume_in_background(cli, tmp_path):
    """An interrupted slow run, resumed by a background process that holds its
    lock on return: (run file, restart point, lock file, process, args)."""
    args = _slow_args(tmp_path)
    out, restart = _interrupted(cli, tmp_path, steps=200, args=args)
    lock = Path(str(out) + ".lock")
    first = subprocess.Popen([str(cli), "run", "--resume", str(out), "--quiet"], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    # The holder writes its pid just after taking the lock (the file exists a
    # moment before that).
    try:
        wait_for(lambda: lock.exists() and lock.read_text().strip(), 60, "the first resume's lock")
    except BaseException:
        first.kill()
        first.communicate(timeout=60)
        raise
    return out, restart, lock, first, args


def test_resume_of_a_run_another_process_writes_is_refused_by_the_lock_not_by_hdf5(cli, tmp_path, slipstrip_module):
    # Was (a race, seen once in CI): the resume read the run file before it took
    # the lock, so while the holder had RUN.h5 open for writing, HDF5's own file
    # locking refused the read ("H5Fopen ... Resource temporarily unavailable")
    # instead of the lock's "in use by another process".  Made deterministic:
    # this process holds the run's lock and has the file open for writing.
    out, restart = _interrupted(cli, tmp_path)
    lock_path = Path(str(out) + ".lock")
    with slipstrip_module.paths.lock_run(out), h5py.File(out, "a"):
        r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 2, r.stderr
    line = _one_line(r)
    assert "is in use by another process" in line and f"pid {os.getpid()}" in line and str(lock_path) in line
    assert "HDF5" not in line
    # Released: the resume goes ahead.
    r = run_cli(cli, "run", "--resume", out, "--quiet", "--stop-after-steps", 400)
    assert r.returncode == 143, r.stderr


def test_one_process_per_run_and_sigkill_leaves_no_stale_lock(cli, tmp_path):
    # Was: two `run --resume RUN.h5` at once both exited 4 ("addr overflow") and
    # left snapshots/slip unreadable ("inflate() failed"): the run was lost.
    out, restart, lock, first, args = _resume_in_background(cli, tmp_path)
    try:
        second = run_cli(cli, "run", "--resume", out, "--quiet")
        line = _one_line(second)
        assert second.returncode == 2
        assert "is in use by another process" in line and f"pid {first.pid}" in line and str(lock) in line
        # A new run of that name (even with --overwrite) and `events` into it are refused too.
        again = run_cli(cli, "run", QUICKSTART, *args, "--out", out, "--overwrite", "--quiet")
        assert again.returncode == 2 and "is in use by another process" in again.stderr, again.stderr
        events = run_cli(cli, "events", out)
        assert events.returncode == 2 and "is in use by another process" in events.stderr, events.stderr
        assert restart.exists()
        # SIGKILL: the lock file stays behind, the lock does not.
        time.sleep(0.3)
        first.kill()
        first.communicate(timeout=60)
    finally:
        if first.poll() is None:
            first.kill()
    assert first.returncode == -signal.SIGKILL
    assert lock.exists()
    # The next resume takes the lock over and continues from the last periodic
    # restart point (that a resume after SIGKILL equals the uninterrupted run
    # bit for bit is test_restart.py's SIGKILL test).
    with h5py.File(restart, "r") as c:
        at = int(c["simulation"].attrs["step_index"])
    assert at >= 200
    r = run_cli(cli, "run", "--resume", out, "--quiet", "--stop-after-steps", at + 100, timeout=600)
    assert r.returncode == 143, r.stderr
    assert f"resumed from step {at}" in r.stderr
    assert not lock.exists() and restart.exists()
    # The run file is intact: every dataset reads in full (two writers once
    # left snapshots/slip failing with "inflate() failed").
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "interrupted"
        datasets = []
        f.visititems(lambda name, obj: datasets.append(obj[()]) if isinstance(obj, h5py.Dataset) else None)
        assert len(datasets) > 5 and f["snapshots/slip"].shape[0] > 1
        assert np.isfinite(f["snapshots/slip"][()]).all()


def test_python_resume_and_run_honour_the_same_lock(cli, tmp_path, slipstrip_module):
    out, restart, lock, first, args = _resume_in_background(cli, tmp_path)
    try:
        with pytest.raises(slipstrip_module.LockHeldError, match="is in use by another process"):
            slipstrip_module.resume(out)
        # run(overwrite=True) would replace the file: refused before it touches anything.
        with pytest.raises(slipstrip_module.LockHeldError, match="is in use by another process"):
            slipstrip_module.run(QUICKSTART, out, overrides=["geometry.nodes=64"], overwrite=True)
    finally:
        first.kill()
        first.communicate(timeout=60)
    assert restart.exists()


def test_writers_into_a_run_file_take_its_lock(cli, tmp_path, slipstrip_module):
    # `slipstrip events RUN.h5` and `analyze --write-events` write into the run
    # file: not while another process holds its lock.  A catalog into another
    # file does not need it.
    from slipstrip import paths
    out = reference_run(cli, tmp_path, ARGS, name="done.h5")
    env = dict(os.environ, SLIPSTRIP_BIN=str(cli))
    with paths.lock_run(out):
        before = out.read_bytes()
        r = run_cli(cli, "events", out)
        assert r.returncode == 2 and "is in use by another process" in _one_line(r)
        r = subprocess.run([str(cli), "analyze", str(out), "--out-dir", str(tmp_path / "a"), "--write-events"],
                           capture_output=True, text=True, env=env, timeout=600)
        assert r.returncode == 2 and "is in use by another process" in _one_line(r), r.stderr
        assert out.read_bytes() == before
        r = run_cli(cli, "events", out, "--out", tmp_path / "catalog.h5")
        assert r.returncode == 0, r.stderr
    r = run_cli(cli, "events", out)
    assert r.returncode == 0, r.stderr
    with h5py.File(out, "r") as f:
        assert "events" in f
