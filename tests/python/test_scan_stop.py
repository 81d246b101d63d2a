"""Stopping a scan (python/slipstrip/scan/stopping.py, docs/scans.md "Stopping a scan").

Each test starts a real scan as its own process, the way a user or a script
does, signals it while its solvers run, and checks what is left: the
scan's exit code, the summary rows, every solver gone (no orphan), every
run file "interrupted" with its restart point; then that a relaunch
resumes them.  The original failures these reproduce: a scan started with
SIGINT ignored (a script's background job) ran on after `kill -INT -<pgid>`
and exited 1; SIGTERM ended the scan at once and left its solver running;
a relaunch ran a second writer on the orphan's file; a Dask scan left its
workers' solvers running.

Runs: configs/quickstart.toml at N = 64 for 1500 L/c_s (3 s of wall time on
a quiet core: 1000 L/c_s took 2.05 s), long enough to be signalled mid-run.
A Dask task sees the stop only after its worker has connected a client to
the scheduler, which can take a second, so the Dask test's runs are four
times longer; it stops them, so their length costs nothing when it passes.

Run: /usr/bin/python3 -m pytest tests/python/test_scan_stop.py
"""
import csv
import importlib
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "python"))
scan = importlib.import_module("slipstrip.scan")
runfile = importlib.import_module("slipstrip.runfile")

LONG = {"geometry.nodes": 64, "time.duration_transits": 1500, "output.snapshot_interval": 0}
WAIT_SECONDS = 120  # upper bound on anything here; a loaded machine is slow, a hung scan fails the test


@pytest.fixture(scope="module")
def binary(cli):
    return str(cli)  # conftest.py: the CLI of this build


@pytest.fixture(autouse=True)
def one_thread(monkeypatch):
    monkeypatch.setenv("OMP_NUM_THREADS", "1")


def write_scan(path: Path, n_runs: int, duration_factor: int = 1) -> Path:
    fixed = dict(LONG, **{"time.duration_transits": LONG["time.duration_transits"] * duration_factor})
    lines = [f'base = "{REPO / "configs/quickstart.toml"}"', "", "[fixed]"]
    lines += [f'"{k}" = {json.dumps(v)}' for k, v in fixed.items()]
    seeds = ", ".join(str(s) for s in range(1, n_runs + 1))
    path.write_text("\n".join(lines) + f'\n\n[[parameter]]\nkey = "initial.noise_seed"\nvalues = [{seeds}]\n')
    return path


def start_scan(scan_file: Path, out: Path, binary: str, *extra: str, ignore_sigint: bool = False):
    env = dict(os.environ, PYTHONPATH=str(REPO / "python"), OMP_NUM_THREADS="1")

    def child_setup():
        if ignore_sigint:
            # What a non-interactive shell does to a background job (`scan ... &` in a script).
            signal.signal(signal.SIGINT, signal.SIG_IGN)

    return subprocess.Popen([sys.executable, "-m", "slipstrip", "scan", str(scan_file), "--out", str(out),
                             "--binary", binary, *extra], env=env, stderr=subprocess.PIPE, text=True,
                            preexec_fn=child_setup, start_new_session=True)


def solver_pids(out: Path, n: int) -> dict[str, int]:
    """Waits until n runs have a solver past its set-up (run file status
    "running") and returns {run file name: solver pid}, found by their
    command lines (`slipstrip run ... --out|--resume <out>/run_<i>.h5`)."""
    deadline = time.monotonic() + WAIT_SECONDS
    while time.monotonic() < deadline:
        pids = {}
        for proc in Path("/proc").iterdir():
            try:
                argv = (proc / "cmdline").read_bytes().decode(errors="replace").split("\0")
            except OSError:  # not a process, or gone meanwhile
                continue
            for flag in ("--out", "--resume"):
                if "run" in argv and flag in argv[:-1]:
                    run = Path(argv[argv.index(flag) + 1])
                    if run.parent == out and runfile.read_status(run) == "running":
                        pids[run.name] = int(proc.name)
        if len(pids) >= n:
            return pids
        time.sleep(0.1)
    raise AssertionError(f"no {n} running solvers after {WAIT_SECONDS} s")


def alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except FileNotFoundError:
        return False
    return state != "Z"


def read_csv(path: Path) -> list[dict]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def check_interrupted(out: Path, rows: list[dict], pids: dict[str, int], code: int) -> None:
    for row in rows:
        run = out / row["run_file"]
        assert row["status"] == "interrupted", row
        assert f"exited with code {code}" in row["error"], row["error"]
        assert runfile.read_status(run) == "interrupted"
        assert scan.restart_point(run).is_file()
    for name, pid in pids.items():
        assert not alive(pid), f"the solver of {name} (pid {pid}) still runs"


# Slow tier for its cost (three 3-s runs, two of them twice): it checks the
# scan's process control; test_sigterm_to_the_scan_alone_reaches_its_solver
# keeps a stop that reaches the solver in the fast tier.
@pytest.mark.slow
def test_sigint_to_the_group_stops_a_scan_that_ignored_sigint(binary, tmp_path, capfd):
    out = tmp_path / "out"
    proc = start_scan(write_scan(tmp_path / "s.toml", 3), out, binary, "--jobs", "2", ignore_sigint=True)
    pids = solver_pids(out, 2)
    os.killpg(proc.pid, signal.SIGINT)  # docs/scans.md: the whole process group, as Ctrl-C does
    _, err = proc.communicate(timeout=WAIT_SECONDS)
    assert proc.returncode == 130, err
    rows = read_csv(out / "summary.csv")
    # The third run never started: the scan stopped instead of running on.
    assert [r["run_file"] for r in rows] == sorted(pids)
    assert not (out / "run_0002.h5").exists()
    check_interrupted(out, rows, pids, 130)
    assert "1 not started" in err

    # A relaunch resumes both and runs the third; the resumed rows count both parts' wall time.
    part1 = {r["run_file"]: float(r["wall_time_s"]) for r in rows}
    assert scan.main([str(tmp_path / "s.toml"), "--out", str(out), "--binary", binary, "--jobs", "2"]) == 0
    err = capfd.readouterr().err
    rows = read_csv(out / "summary.csv")
    assert [r["status"] for r in rows] == ["completed"] * 3
    for r in rows:
        resumed = r["run_file"] in part1
        assert r["resumed"] == str(resumed)
        assert (f"run {r['index']} completed (resumed from its restart point)" in err) == resumed
        if resumed:  # the first part's time plus this part's (> 0)
            assert float(r["wall_time_s"]) > part1[r["run_file"]]


def test_sigterm_to_the_scan_alone_reaches_its_solver(binary, tmp_path):
    out = tmp_path / "out"
    proc = start_scan(write_scan(tmp_path / "s.toml", 2), out, binary)
    pids = solver_pids(out, 1)
    proc.send_signal(signal.SIGTERM)  # the scan's pid only, as a batch system or `kill PID` does
    _, err = proc.communicate(timeout=WAIT_SECONDS)
    assert proc.returncode == 143, err
    rows = read_csv(out / "summary.csv")
    assert len(rows) == 1
    check_interrupted(out, rows, pids, 143)
    assert "SIGTERM" in err


def test_relaunch_leaves_alone_a_run_whose_solver_outlived_its_scan(binary, tmp_path, capfd):
    scan_file = write_scan(tmp_path / "s.toml", 1)
    out = tmp_path / "out"
    proc = start_scan(scan_file, out, binary)
    pids = solver_pids(out, 1)
    proc.kill()  # SIGKILL: nothing can be forwarded; the solver runs on as an orphan
    proc.communicate(timeout=WAIT_SECONDS)
    (name, pid), = pids.items()
    assert alive(pid)
    rc = scan.main([str(scan_file), "--out", str(out), "--binary", binary])
    err = capfd.readouterr().err
    assert rc == 1 and "run 0 busy" in err
    row, = read_csv(out / "summary.csv")
    assert row["status"] == "busy"
    assert f"held by process {pid}" in row["error"] and "kill -TERM" in row["error"]
    # Not a second writer: the orphan's file is still its own, and it finishes it.
    deadline = time.monotonic() + WAIT_SECONDS
    while alive(pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert runfile.read_status(out / name) == "completed"
    assert scan.main([str(scan_file), "--out", str(out), "--binary", binary]) == 0
    row, = read_csv(out / "summary.csv")
    assert row["status"] == "completed"


# Slow tier: a local Dask cluster's start-up (worker processes importing
# distributed) is most of its cost, and it checks the scan's distribution, not physics.
@pytest.mark.slow
def test_dask_scan_stop_reaches_the_workers_solvers(binary, tmp_path):
    distributed = pytest.importorskip("distributed")
    out = tmp_path / "out"
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        proc = start_scan(write_scan(tmp_path / "s.toml", 3, duration_factor=4), out, binary, "--dask",
                          cluster.scheduler_address)
        pids = solver_pids(out, 2)
        # The scan (the Dask client) alone: its workers are this test's processes, not its children.
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=WAIT_SECONDS)
    assert proc.returncode == 130, err
    rows = read_csv(out / "summary.csv")
    assert [r["run_file"] for r in rows] == sorted(pids)
    check_interrupted(out, rows, pids, 130)
