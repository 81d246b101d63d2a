"""Commands that find nothing to do say why and what to change, in one line
of their own, with a non-zero exit code; no library text (h5py's errno dump,
matplotlib's legend warnings, a Python traceback) reaches the user.

Each case goes through the `slipstrip` binary, as a user types it: a
directory where a run file is expected (plot, export, analyze, events), a
path that is not there or not HDF5 (plot, analyze, export, events,
transition), `analyze` and `events` of a run with no kept events (exit 1;
analyze draws no figures), `events`/`analyze` of a run made with
output.delta_th = 0 (no slip sampling), and `transition` of a directory with
no run file in it.  The originals: a directory gave "[Errno 21] ... bytes
actually read = 18446744073709551615"; analyze of an empty catalog exited 0
with six empty figures and legend warnings; events of an empty catalog exited
0 without a word; events without slip sampling said only "group
/slip_sampling is missing"; transition --include-unfinished of a non-HDF5
file printed a traceback, and of an empty directory exited 0 silently.

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


@pytest.mark.parametrize("command", [["plot"], ["analyze"], ["export", "--seas", "seas"], ["events"],
                                     ["transition"], ["transition", "--include-unfinished"]])
def test_missing_and_foreign_files(cli, tmp_path, command):
    name, *rest = command
    r = slipstrip(cli, name, tmp_path / "nope.h5", *rest, cwd=tmp_path)
    assert r.returncode == 2 and "does not exist" in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    text = tmp_path / "notes.h5"
    text.write_text("not a run\n")
    r = slipstrip(cli, name, text, *rest, cwd=tmp_path)
    assert r.returncode == 2 and "not an HDF5 file" in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "seas").exists()


def test_transition_with_nothing_to_classify(cli, tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    r = slipstrip(cli, "transition", empty, "--csv", tmp_path / "map.csv")
    assert r.returncode == 2 and "holds no run files" in r.stderr, r.stderr
    # A directory whose only .h5 is not a run file: listed as skipped, then
    # one line saying that nothing was classified; no empty table written.
    (empty / "notes.h5").write_text("not a run\n")
    r = slipstrip(cli, "transition", empty, "--csv", tmp_path / "map.csv")
    assert r.returncode == 1, r.stderr
    assert "no run classified" in r.stderr and "1 could not be read" not in r.stderr
    assert "--include-unfinished" in r.stderr
    assert not (tmp_path / "map.csv").exists()
    r = slipstrip(cli, "transition", empty, "--include-unfinished", "--csv", tmp_path / "map.csv")
    assert r.returncode == 1 and "1 could not be read" in r.stderr, r.stderr
    assert "not an HDF5 file" in r.stderr
    assert not (tmp_path / "map.csv").exists()


def test_events_with_no_kept_event_says_why(cli, runs, tmp_path):
    """The catalog is still written (its counts are the answer), but the exit
    code is 1 and one line says why nothing was kept and what to change."""
    out = tmp_path / "short_events.h5"
    r = slipstrip(cli, "events", runs["short"], "--out", out)
    assert r.returncode == 1, r.stderr
    assert "0 kept" in r.stdout
    # 7 events detected: the first and the last excluded, the other 5 too small.
    assert "0 events kept" in r.stderr and "below the size thresholds" in r.stderr
    assert "lower output.delta_th" in r.stderr and "run longer" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    assert out.exists()  # the catalog, with its counts

    r = slipstrip(cli, "events", runs["coarse"], "--out", tmp_path / "coarse_events.h5")
    assert r.returncode == 1, r.stderr
    assert "0 nodal slips" in r.stderr and "lower output.delta_th" in r.stderr, r.stderr


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


def test_commands_import_no_fitting_or_plotting_library_before_they_work(repo):
    """Every `python3 -m slipstrip` command module imports scipy and matplotlib
    only inside the functions that fit, test or draw: importing them is most
    of a command's start-up (about 1 s of CPU against 0.4 s without), paid by
    every refusal above and by every test that checks one."""
    import os
    import sys
    modules = ["slipstrip.__main__", "slipstrip.analysis", "slipstrip.scan", "slipstrip.report",
               "slipstrip.transition", "slipstrip.export", "slipstrip.episodes", "slipstrip.divergence",
               "slipstrip.fronts"]
    code = ("import importlib, sys\n"
            f"for m in {modules!r}:\n"
            "    importlib.import_module(m)\n"
            "print(' '.join(sorted({m.split('.')[0] for m in sys.modules} & {'scipy', 'matplotlib'})))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                       env=dict(os.environ, PYTHONPATH=str(repo / "python")))
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "", f"imported at start-up: {r.stdout.strip()}"
