"""Commands that find nothing to do say why and what to change, in one line
of their own, with a non-zero exit code; no library text (h5py's errno dump,
matplotlib's legend warnings, a Python traceback) reaches the user.

Each case goes through the `slipstrip` binary, as a user types it: a
directory where a run file is expected (plot, export, analyze, events), a
path that is not there or not HDF5, `analyze` of a run with no kept events
(exit 1, no figures), and `events`/`analyze` of a run made with
output.delta_th = 0 (no slip sampling).  The originals: a directory gave
"[Errno 21] ... bytes actually read = 18446744073709551615"; analyze of an
empty catalog exited 0 with six empty figures and legend warnings; events
without slip sampling said only "group /slip_sampling is missing".

Run: /usr/bin/python3 -m pytest tests/python/test_nothing_to_do.py
"""
import subprocess

import pytest

# Text of the libraries underneath that must never reach the user.
LIBRARY_TEXT = ("Traceback", "Errno", "Unable to", "bytes actually read", "HDF5-DIAG", "UserWarning",
                "No artists with labels", "RuntimeWarning")


def slipstrip(cli, *args, cwd=None):
    r = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True, timeout=300, cwd=cwd)
    for text in LIBRARY_TEXT:
        assert text not in r.stderr and text not in r.stdout, r.stderr
    return r


def tiny_run(cli, repo, path, *overrides):
    cmd = [str(cli), "run", str(repo / "configs/quickstart.toml"), "--quiet", "--out", str(path),
           "--set", "geometry.nodes=32", "--set", "time.duration_transits=0.2"]
    for o in overrides:
        cmd += ["--set", o]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return path


@pytest.fixture(scope="module")
def runs(cli, repo, tmp_path_factory):
    d = tmp_path_factory.mktemp("runs")
    return {
        # 26 steps: a few nodal slips, all in events below the size thresholds or excluded.
        "short": tiny_run(cli, repo, d / "short.h5"),
        # delta_th above the slip of the whole run: no nodal slip at all.
        "coarse": tiny_run(cli, repo, d / "coarse.h5", "output.delta_th=1e-6"),
        "unsampled": tiny_run(cli, repo, d / "unsampled.h5", "output.delta_th=0"),
        "dir": d,
    }


@pytest.mark.parametrize("command", [["plot"], ["export", "--seas", "SEAS"], ["analyze"], ["events"]])
def test_a_directory_is_named_as_one(cli, runs, tmp_path, command):
    name, *rest = command
    rest = [str(tmp_path / "seas") if a == "SEAS" else a for a in rest]
    r = slipstrip(cli, name, runs["dir"], *rest, cwd=tmp_path)
    assert r.returncode == 2
    assert "is a directory" in r.stderr, r.stderr
    if name != "events":  # the Python commands also name the run files inside
        assert "short.h5" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize("command", ["plot", "analyze"])
def test_missing_and_foreign_files(cli, tmp_path, command):
    r = slipstrip(cli, command, tmp_path / "nope.h5", cwd=tmp_path)
    assert r.returncode == 2 and "does not exist" in r.stderr, r.stderr
    text = tmp_path / "notes.h5"
    text.write_text("not a run\n")
    r = slipstrip(cli, command, text, cwd=tmp_path)
    assert r.returncode == 2 and "is not an HDF5 file" in r.stderr, r.stderr


def test_analyze_with_no_kept_event_says_why_and_draws_nothing(cli, runs, tmp_path):
    out = tmp_path / "a"
    r = slipstrip(cli, "analyze", runs["short"], "--out-dir", out)
    assert r.returncode == 1, r.stderr
    assert "0 events kept" in r.stderr and "nothing to analyse" in r.stderr
    assert "output.delta_th" in r.stderr or "time.duration_transits" in r.stderr
    assert "nan" not in r.stdout + r.stderr
    assert not list(out.glob("*.png")) and not (out / "summary.json").exists()

    r = slipstrip(cli, "analyze", runs["coarse"], "--out-dir", tmp_path / "b")
    assert r.returncode == 1
    assert "0 nodal slips" in r.stderr and "lower output.delta_th" in r.stderr, r.stderr


@pytest.mark.parametrize("command", ["events", "analyze"])
def test_no_slip_sampling_says_to_set_delta_th(cli, runs, tmp_path, command):
    r = slipstrip(cli, command, runs["unsampled"], cwd=tmp_path)
    assert r.returncode == 2
    assert "no slip sampling" in r.stderr and "output.delta_th" in r.stderr and "delta_th > 0" in r.stderr
