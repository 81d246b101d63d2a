"""Checkpoint/restart through the CLI (docs/reliability.md, "Restart").

Every test runs a tiny case (configs/quickstart.toml at N = 64 nodes, a few
thousand steps, well under a second each), interrupts it (--stop-after-steps at
seeded random steps, SIGTERM, or SIGKILL), continues it with `slipstrip run
--resume`, and compares the result with an uninterrupted run of the same
config: every dataset and every attribute of the two files, bit for bit,
except the wall-clock dates `start_time` and `end_time`.

Run: SLIPSTRIP_BUILD_DIR=$PWD/build PYTHONPATH=$PWD/python OMP_NUM_THREADS=1 \\
     /usr/bin/python3 -m pytest -q tests/python/test_restart.py
"""
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
QUICKSTART = REPO / "configs/quickstart.toml"
# Seeded, so a failure can be repeated; SLIPSTRIP_RESTART_SEED explores others.
SEED = int(os.environ.get("SLIPSTRIP_RESTART_SEED", "20240611"))
WALL_CLOCK_ATTRIBUTES = {"start_time", "end_time"}

# Every record the run file can hold: time series every step, snapshots by
# time, stations, rupture front; slip sampling on (delta_th = 1e-8 m: a
# crossing every ~7 steps per node) unless a case turns it off.  6 L/c_s is
# ~1540 steps of 7.1e-7 s.
TINY = ["--set", "geometry.nodes=64", "--set", "time.duration_transits=6",
        "--set", "output.snapshot_interval=2e-5", "--set", "output.stations=[0.1, 0.25]",
        "--set", "output.station_interval=5e-6", "--set", "output.front_slip_rate=2.01e-3"]
CASES = {
    "modal strip": ["--set", "time.history=modal"],
    "block strip": ["--set", "time.history=block"],
    "half-space": ["--set", 'geometry.height="inf"'],
}
NO_SAMPLING = ["--set", "output.delta_th=0", "--set", "output.snapshot_interval=0",
               "--set", "output.snapshot_slip_increment=5e-8"]


@pytest.fixture(autouse=True)
def one_thread(monkeypatch):
    monkeypatch.setenv("OMP_NUM_THREADS", "1")


def run_cli(cli, *args, timeout=120):
    return subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True, timeout=timeout)


def steps_of(path):
    with h5py.File(path, "r") as f:
        return len(f["timeseries/time"]) - 1  # one row per step plus t = 0


def assert_files_identical(reference, resumed):
    """Every group, dataset and attribute of the two files, bitwise (NaN
    fill included), except the wall-clock dates."""
    with h5py.File(reference, "r") as a, h5py.File(resumed, "r") as b:
        names_a, names_b = [], []
        a.visit(names_a.append)
        b.visit(names_b.append)
        assert names_a == names_b
        compared = 0
        for name in [""] + names_a:
            obj_a, obj_b = (a[name], b[name]) if name else (a, b)
            assert type(obj_a) is type(obj_b), name
            keys_a, keys_b = sorted(obj_a.attrs.keys()), sorted(obj_b.attrs.keys())
            assert keys_a == keys_b, name
            for key in keys_a:
                if key in WALL_CLOCK_ATTRIBUTES:
                    continue
                va, vb = obj_a.attrs[key], obj_b.attrs[key]
                if isinstance(va, (str, bytes)):
                    assert va == vb, f"{name or '/'}@{key}"
                else:
                    assert np.asarray(va).tobytes() == np.asarray(vb).tobytes(), f"{name or '/'}@{key}"
            if isinstance(obj_a, h5py.Dataset):
                assert obj_a.dtype == obj_b.dtype and obj_a.shape == obj_b.shape, name
                assert obj_a[()].tobytes() == obj_b[()].tobytes(), f"dataset {name} differs"
                compared += 1
        assert compared > 0


def reference_run(cli, tmp_path, args, name="reference.h5"):
    out = tmp_path / name
    r = run_cli(cli, "run", QUICKSTART, *args, "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    assert not Path(str(out) + ".restart").exists()  # a completed run leaves no restart point
    return out


@pytest.mark.parametrize("sampling", [True, False], ids=["slip sampling", "no slip sampling"])
@pytest.mark.parametrize("case", list(CASES))
def test_interrupted_twice_and_resumed_equals_uninterrupted(cli, tmp_path, case, sampling):
    args = TINY + CASES[case] + ([] if sampling else NO_SAMPLING)
    reference = reference_run(cli, tmp_path, args)
    total = steps_of(reference)
    rng = random.Random(f"{SEED} {case} {sampling}")
    first = rng.randrange(1, total // 2)
    second = rng.randrange(first + 1, total)
    out = tmp_path / "resumed.h5"

    def after_first_stop(restart):
        with h5py.File(out, "r") as f, h5py.File(restart, "r") as c:
            assert c.attrs["config"] == f.attrs["config"]
        if case == "modal strip" and sampling:
            # An event catalog of the interrupted file describes a shorter record:
            # the resume drops it (an uninterrupted run has none).
            r = run_cli(cli, "events", out)
            # Written either way; exit 1 if this short record keeps no event.
            assert r.returncode == 0 or (r.returncode == 1 and "0 events kept" in r.stderr), r.stderr
            with h5py.File(out, "r") as f:
                assert "events" in f

    stop_twice_and_resume(cli, QUICKSTART, args, out, first, second, after_first_stop)
    print(f"{case}, sampling={sampling}: {total} steps, interrupted after {first} and {second}")
    assert_files_identical(reference, out)


def stop_twice_and_resume(cli, config, args, out, first, second, after_first_stop=None):
    """Runs `slipstrip run config args --out out` stopped after step `first`
    (--stop-after-steps: exit 143 as SIGTERM, status "interrupted", a restart
    point at that step), calls after_first_stop(restart) if given, resumes it
    and stops it again after step `second`, then resumes it to the end, which
    removes the restart point."""
    restart = Path(str(out) + ".restart")
    r = run_cli(cli, "run", config, *args, "--out", out, "--quiet", "--stop-after-steps", first)
    assert r.returncode == 143, r.stderr  # as SIGTERM
    assert restart.is_file() and "restart point" in r.stderr
    with h5py.File(out, "r") as f, h5py.File(restart, "r") as c:
        assert f.attrs["status"] == "interrupted"
        assert c["simulation"].attrs["step_index"] == first
    if after_first_stop is not None:
        after_first_stop(restart)
    r = run_cli(cli, "run", "--resume", out, "--quiet", "--stop-after-steps", second)
    assert r.returncode == 143, r.stderr
    assert f"resumed from step {first}" in r.stderr
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 0, r.stderr
    assert f"resumed from step {second}" in r.stderr
    assert not restart.exists()


def wait_for(predicate, timeout, what, proc=None):
    """Polls predicate() until it holds; fails after `timeout` s, or as soon
    as `proc` (if given) has exited without it holding: a run that ends
    before its first restart point is reported at once, with its stderr."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return
        if proc is not None and proc.poll() is not None:
            _, err = proc.communicate()
            if proc.returncode == 0:
                pytest.skip(f"the run completed before {what} (machine too fast)")
            pytest.fail(f"the run exited with {proc.returncode} before {what}: {err}")
        time.sleep(0.01)
    pytest.fail(f"timed out waiting for {what}")


def _completed(path):
    try:
        with h5py.File(path, "r") as f:
            return f.attrs.get("status") == "completed"
    except OSError:
        return False


def stop_mid_run(cli, config, args, out, started, sig, seed):
    """Starts `slipstrip run config args --out out`, waits until started()
    and a seeded 0.05-0.3 s more, then sends `sig` (SIGTERM: exit 143;
    SIGKILL).  Skips the test if the run completed before the signal."""
    proc = subprocess.Popen([str(cli), "run", str(config), *args, "--out", str(out), "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_for(started, 60, "the run to start", proc)
    time.sleep(random.Random(seed).uniform(0.05, 0.3))
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    if proc.returncode == 0:
        pytest.skip(f"the run completed before {sig.name} arrived (machine too fast)")
    if sig == signal.SIGKILL and _completed(out):
        # The kill landed after the run had closed its file and removed its
        # restart point, before the process exited: nothing to resume.
        pytest.skip("the run completed before SIGKILL arrived (it was killed while exiting)")
    assert proc.returncode == (143 if sig == signal.SIGTERM else -sig), err


def test_sigterm_writes_a_restart_point_and_exits_143(cli, tmp_path):
    # Long enough (~20000 steps) that the signal arrives mid-run.
    args = TINY + CASES["modal strip"] + ["--set", "time.duration_transits=200",
                                          "--set", "output.snapshot_interval=1e-3"]
    reference = reference_run(cli, tmp_path, args)
    out = tmp_path / "resumed.h5"
    stop_mid_run(cli, QUICKSTART, args, out, out.exists, signal.SIGTERM, SEED)
    assert Path(str(out) + ".restart").is_file()
    with h5py.File(Path(str(out) + ".restart"), "r") as c:
        stopped_at = int(c["simulation"].attrs["step_index"])
    assert 0 < stopped_at < steps_of(reference)
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 0, r.stderr
    print(f"SIGTERM after step {stopped_at} of {steps_of(reference)}")
    assert_files_identical(reference, out)


def test_sigkill_after_periodic_restart_points_resumes_identically(cli, tmp_path):
    # Restart points every 16 steps (checkpoint_interval ~0) and frequent
    # flushes: when SIGKILL lands, the file holds rows, snapshots and slip
    # crossings written after the last restart point, which the resume must
    # cut away and write again, identically.
    args = TINY + CASES["block strip"] + ["--set", "time.duration_transits=200",
                                          "--set", "output.snapshot_interval=1e-3",
                                          "--set", "output.checkpoint_interval=0.05",
                                          "--set", "output.flush_interval=0.01"]
    reference = reference_run(cli, tmp_path, args)
    out = tmp_path / "resumed.h5"
    restart = Path(str(out) + ".restart")
    stop_mid_run(cli, QUICKSTART, args, out, restart.exists, signal.SIGKILL, SEED + 1)
    assert restart.is_file()
    with h5py.File(restart, "r") as c:
        at = int(c["simulation"].attrs["step_index"])
        cursor_rows = int(c["output"].attrs["timeseries_rows"])
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "running"
        rows_in_file = len(f["timeseries/time"])
    assert rows_in_file >= cursor_rows
    print(f"{rows_in_file - cursor_rows} time-series rows past the restart point to cut")
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 0, r.stderr
    print(f"SIGKILL; resumed from step {at} of {steps_of(reference)}")
    assert_files_identical(reference, out)


def test_resume_ignores_a_torn_temporary_restart_point(cli, tmp_path):
    # What a kill during a restart-point write leaves: a partial .tmp next to
    # the previous, complete restart point.  The resume uses the complete one.
    args = TINY + CASES["modal strip"]
    reference = reference_run(cli, tmp_path, args)
    out = tmp_path / "resumed.h5"
    r = run_cli(cli, "run", QUICKSTART, *args, "--out", out, "--quiet", "--stop-after-steps", 500)
    assert r.returncode == 143, r.stderr
    restart = Path(str(out) + ".restart")
    torn = Path(str(restart) + ".tmp")
    torn.write_bytes(restart.read_bytes()[: restart.stat().st_size // 3])
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 0, r.stderr
    assert not torn.exists() and not restart.exists()
    assert_files_identical(reference, out)


def test_resume_refusals_are_clear(cli, tmp_path):
    args = TINY + CASES["modal strip"]
    out = tmp_path / "run.h5"
    restart = Path(str(out) + ".restart")
    r = run_cli(cli, "run", QUICKSTART, *args, "--out", out, "--quiet", "--stop-after-steps", 100)
    assert r.returncode == 143, r.stderr

    # A config or --set other than the stored one: refused, nothing changed.
    before = out.read_bytes(), restart.read_bytes()
    r = run_cli(cli, "run", QUICKSTART, *args, "--set", "friction.a=0.006", "--resume", out)
    assert r.returncode == 2 and "differs from the run's stored config" in r.stderr
    assert "a = 0.006" in r.stderr
    r = run_cli(cli, "run", "--resume", out, "--set", "friction.a=0.006")
    assert r.returncode == 2 and "cannot change it" in r.stderr
    r = run_cli(cli, "run", "--resume", out, "--out", tmp_path / "other.h5")
    assert r.returncode == 2 and "--out and --overwrite do not apply" in r.stderr
    assert (out.read_bytes(), restart.read_bytes()) == before
    # A damaged restart point: exit 2 naming it.
    restart.write_bytes(b"not hdf5")
    r = run_cli(cli, "run", "--resume", out)
    assert r.returncode == 2 and f"restart point '{restart}' cannot be read" in r.stderr
    assert len(r.stderr.strip().splitlines()) <= 2
    # No restart point at all: exit 2 naming the missing file.
    restart.unlink()
    r = run_cli(cli, "run", "--resume", out)
    assert r.returncode == 2
    assert f"'{out}' has no restart point" in r.stderr and "checkpoint_interval" in r.stderr
    # Not a run file.
    r = run_cli(cli, "run", "--resume", tmp_path / "missing.h5")
    assert r.returncode == 2 and "does not exist" in r.stderr


def test_resume_with_the_same_config_and_overrides_is_accepted(cli, tmp_path):
    # The rule: a config and --set given with --resume are checked, not applied.
    args = TINY + CASES["modal strip"]
    reference = reference_run(cli, tmp_path, args)
    out = tmp_path / "run.h5"
    r = run_cli(cli, "run", QUICKSTART, *args, "--out", out, "--quiet", "--stop-after-steps", 300)
    assert r.returncode == 143, r.stderr
    r = run_cli(cli, "run", QUICKSTART, *args, "--resume", out, "--quiet")
    assert r.returncode == 0, r.stderr
    assert_files_identical(reference, out)


def test_resume_of_a_completed_run_says_so(cli, tmp_path):
    out = reference_run(cli, tmp_path, TINY + CASES["modal strip"])
    before = out.read_bytes()
    r = run_cli(cli, "run", "--resume", out)
    assert r.returncode == 0
    assert "already completed; nothing to resume" in r.stderr
    assert out.read_bytes() == before


def test_new_run_over_an_interrupted_one_drops_its_restart_point(cli, tmp_path):
    # --overwrite starts afresh: the old restart point must not survive to be
    # resumed into the new file.
    args = TINY + CASES["modal strip"]
    out = tmp_path / "run.h5"
    r = run_cli(cli, "run", QUICKSTART, *args, "--out", out, "--quiet", "--stop-after-steps", 100)
    assert r.returncode == 143
    r = run_cli(cli, "run", QUICKSTART, *args, "--out", out, "--quiet", "--overwrite",
                "--set", "time.duration_transits=1")
    assert r.returncode == 0, r.stderr
    assert not Path(str(out) + ".restart").exists()


def test_checkpoint_interval_is_validated(cli, tmp_path):
    for value in ["-1", "nan", "inf", '"often"']:
        r = run_cli(cli, "run", QUICKSTART, "--set", f"output.checkpoint_interval={value}",
                    "--out", tmp_path / "x.h5")
        assert r.returncode == 2, (value, r.stderr)
        assert "checkpoint_interval" in r.stderr, (value, r.stderr)
    r = run_cli(cli, "run", QUICKSTART, "--set", "output.checkpoint_interval=-1", "--out", tmp_path / "x.h5")
    assert "0 (restart points only on SIGTERM/SIGINT) or a finite wall-clock time > 0 [s]" in r.stderr


def _load_scan_module():
    # As tests/python/test_scan.py: the package python/slipstrip/scan/.
    import importlib
    sys.path.insert(0, str(REPO / "python"))
    return importlib.import_module("slipstrip.scan")


def test_scan_relaunch_resumes_an_interrupted_run(cli, tmp_path, capfd, monkeypatch):
    scan = _load_scan_module()
    monkeypatch.setenv("SLIPSTRIP_BIN", str(cli))
    scan_file = tmp_path / "s.toml"
    scan_file.write_text("\n".join([
        f'base = "{QUICKSTART}"', 'mode = "product"', 'output_dir = "out"', "", "[fixed]",
        '"geometry.nodes" = 64', '"time.duration_transits" = 6', '"output.snapshot_interval" = 2e-5',
        "", "[[parameter]]", 'key = "friction.a"', "values = [0.005, 0.006]", ""]))
    out = tmp_path / "out"
    spec = scan.load_scan(scan_file, output_dir=out)
    tasks = scan.expand_runs(spec)
    # Run 1 as the scan runs it, stopped after 700 steps: what a Slurm time
    # limit or Ctrl-C leaves behind.
    task = tasks[1]
    out.mkdir()
    cmd = [str(cli), "run", str(spec.base_config)]
    for o in task.overrides:
        cmd += ["--set", o]
    cmd += scan.kernel_cache_override(task.overrides, task.run_file.parent)
    r = subprocess.run(cmd + ["--out", str(task.run_file), "--quiet", "--stop-after-steps", "700"],
                       capture_output=True, text=True)
    assert r.returncode == 143, r.stderr
    # The same run uninterrupted, for comparison.
    reference = tmp_path / "reference.h5"
    r = subprocess.run(cmd + ["--out", str(reference), "--quiet"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr

    rc = scan.main([str(scan_file), "--out", str(out), "--binary", str(cli)])
    err = capfd.readouterr().err
    assert rc == 0, err
    assert "cannot be resumed" not in err
    assert not Path(str(task.run_file) + ".restart").exists()
    rows = scan.read_summary(out)
    assert [r["status"] for r in rows] == ["completed", "completed"]
    # The scan ran `slipstrip events` on its file: do the same on the reference.
    r = subprocess.run([str(cli), "events", str(reference)], capture_output=True, text=True)
    # Written either way; exit 1 if this short record keeps no event.
    assert r.returncode == 0 or (r.returncode == 1 and "0 events kept" in r.stderr), r.stderr
    assert_files_identical(reference, task.run_file)


def test_scan_reruns_an_interrupted_run_whose_overrides_changed(cli, tmp_path, capfd, monkeypatch):
    scan = _load_scan_module()
    monkeypatch.setenv("SLIPSTRIP_BIN", str(cli))
    scan_file = tmp_path / "s.toml"
    body = [f'base = "{QUICKSTART}"', 'mode = "product"', 'output_dir = "out"', "", "[fixed]",
            '"geometry.nodes" = 64', '"time.duration_transits" = 2', "", "[[parameter]]",
            'key = "friction.a"']
    scan_file.write_text("\n".join(body + ["values = [0.005]", ""]))
    out = tmp_path / "out"
    task = scan.expand_runs(scan.load_scan(scan_file, output_dir=out))[0]
    out.mkdir()
    cmd = [str(cli), "run", str(QUICKSTART)]
    for o in task.overrides:
        cmd += ["--set", o]
    cmd += scan.kernel_cache_override(task.overrides, out)
    r = subprocess.run(cmd + ["--out", str(task.run_file), "--quiet", "--stop-after-steps", "100"],
                       capture_output=True, text=True)
    assert r.returncode == 143, r.stderr
    scan_file.write_text("\n".join(body + ["values = [0.007]", ""]))  # the scan file was edited
    rc = scan.main([str(scan_file), "--out", str(out), "--binary", str(cli)])
    err = capfd.readouterr().err
    assert rc == 0, err
    assert "cannot be resumed" in err and "running it again" in err
    with h5py.File(task.run_file, "r") as f:
        assert f.attrs["status"] == "completed"
        assert "a = 0.007" in f.attrs["config"]


def test_python_resume_continues_a_cli_run(cli, tmp_path, slipstrip_module):
    args = TINY + CASES["half-space"]
    reference = reference_run(cli, tmp_path, args)
    out = tmp_path / "run.h5"
    r = run_cli(cli, "run", QUICKSTART, *args, "--out", out, "--quiet", "--stop-after-steps", 777)
    assert r.returncode == 143, r.stderr
    result = slipstrip_module.resume(out)
    assert result.status == "completed" and result.steps == steps_of(reference)
    assert not Path(str(out) + ".restart").exists()
    assert_files_identical(reference, out)
    with pytest.raises(ValueError, match="completed: nothing to resume"):
        slipstrip_module.resume(out)

