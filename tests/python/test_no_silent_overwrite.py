"""Nothing is overwritten without being told: slipstrip.run() refuses an
existing file as `slipstrip run --out` does, and `export --seas DIR` refuses
files of its names already in DIR; both replace them when told (overwrite=True,
--overwrite), and neither ever writes over its own input.  The rule is
slipstrip.paths.check_outputs, in one place.

The originals: slipstrip.run(cfg, "old.h5") replaced an existing file
silently, and a second `export --seas DIR` replaced the station files of an
earlier export in DIR.

Run: /usr/bin/python3 -m pytest tests/python/test_no_silent_overwrite.py
"""
import os
import subprocess

import pytest

TINY = {"geometry.nodes": 32, "time.duration_transits": 0.2}


@pytest.fixture
def slipstrip(slipstrip_module):
    return slipstrip_module


def test_python_run_refuses_an_existing_file(slipstrip, repo, tmp_path):
    out = tmp_path / "old.h5"
    out.write_bytes(b"an earlier result\n")
    with pytest.raises(slipstrip.OutputPathError) as err:
        slipstrip.run(repo / "configs/quickstart.toml", out, overrides=TINY)
    message = str(err.value)
    assert "already exists" in message and "overwrite=True" in message and str(out) in message
    assert isinstance(err.value, ValueError)
    assert out.read_bytes() == b"an earlier result\n"  # untouched

    result = slipstrip.run(repo / "configs/quickstart.toml", out, overrides=TINY, overwrite=True)
    assert result.status == "completed"
    assert slipstrip.open_run(out).status == "completed"


def test_python_run_never_writes_over_its_config(slipstrip, repo, tmp_path):
    config = tmp_path / "c.toml"
    config.write_text((repo / "configs/quickstart.toml").read_text())
    before = config.read_text()
    for overwrite in (False, True):
        with pytest.raises(slipstrip.OutputPathError, match="is the input"):
            slipstrip.run(config, tmp_path / "." / "c.toml", overrides=TINY, overwrite=overwrite)
    assert config.read_text() == before


def test_python_run_finds_an_unusable_directory_before_the_setup(slipstrip, repo, tmp_path):
    with pytest.raises(slipstrip.OutputPathError, match="is not usable .No such file or directory"):
        slipstrip.run(repo / "configs/quickstart.toml", tmp_path / "missing" / "r.h5", overrides=TINY)
    with pytest.raises(slipstrip.OutputPathError, match="is a directory"):
        slipstrip.run(repo / "configs/quickstart.toml", tmp_path, overrides=TINY, overwrite=True)


def test_python_run_over_a_file_drops_its_old_restart_point(slipstrip_module, repo, tmp_path):
    """A restart point left by an earlier, interrupted run of the same name
    must not be taken for the new run's (as `slipstrip run --overwrite`): the
    new run, killed before it writes a restart point of its own, leaves none."""
    out = tmp_path / "r.h5"
    out.write_bytes(b"an interrupted run\n")
    stale = tmp_path / "r.h5.restart"
    stale.write_bytes(b"its restart point\n")
    # os._exit at the first progress report: a kill after the first step, long
    # before the first restart point (output.checkpoint_interval of wall time).
    script = ("import os, slipstrip\n"
              f"slipstrip.run({str(repo / 'configs/quickstart.toml')!r}, {str(out)!r}, overwrite=True,\n"
              f"              overrides={TINY!r}, progress=lambda p: os._exit(9), progress_interval=0.0)\n")
    r = subprocess.run(["/usr/bin/python3", "-c", script], capture_output=True, text=True, timeout=300,
                       env={**os.environ, "PYTHONPATH": str(repo / "python")})
    assert r.returncode == 9, r.stderr
    assert not stale.exists()


@pytest.fixture(scope="module")
def station_run(cli, repo, tmp_path_factory):
    path = tmp_path_factory.mktemp("export") / "stations.h5"
    r = subprocess.run([str(cli), "run", str(repo / "configs/quickstart.toml"), "--quiet", "--out", str(path),
                        "--set", "geometry.nodes=32", "--set", "time.duration_transits=0.2",
                        "--set", "output.stations=[0.1, 0.3]"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return path


def export(cli, *args):
    return subprocess.run([str(cli), "export", *map(str, args)], capture_output=True, text=True, timeout=300)


def test_export_refuses_files_it_would_replace(cli, station_run, tmp_path):
    seas = tmp_path / "seas"
    r = export(cli, station_run, "--seas", seas)  # a new directory: created
    assert r.returncode == 0, r.stderr
    written = sorted(p.name for p in seas.iterdir())
    assert written == ["global.txt", "station_x+0.1000.txt", "station_x+0.3000.txt"]

    marked = seas / "global.txt"
    marked.write_text("kept\n")
    r = export(cli, station_run, "--seas", seas)
    assert r.returncode == 2
    assert "already exists" in r.stderr and "--overwrite" in r.stderr and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    assert marked.read_text() == "kept\n"  # nothing written, not even the station files before it

    r = export(cli, station_run, "--seas", seas, "--overwrite")
    assert r.returncode == 0, r.stderr
    assert marked.read_text().startswith("# problem:")

    # Other files in the directory are no concern of the export.
    (seas / "notes.txt").write_text("mine\n")
    other = tmp_path / "other"
    other.mkdir()
    (other / "notes.txt").write_text("mine\n")
    assert export(cli, station_run, "--seas", other).returncode == 0
    assert (other / "notes.txt").read_text() == "mine\n"


def test_export_never_writes_over_its_input_or_into_a_file(cli, station_run, tmp_path):
    r = export(cli, station_run, "--seas", station_run, "--overwrite")
    assert r.returncode == 2 and "is the input" in r.stderr, r.stderr
    plain = tmp_path / "plain"
    plain.write_text("a file\n")
    r = export(cli, station_run, "--seas", plain)
    assert r.returncode == 2 and "is not a directory" in r.stderr, r.stderr
    assert plain.read_text() == "a file\n"


def test_check_outputs_rule(slipstrip_module, tmp_path):
    from slipstrip.paths import OutputPathError, check_outputs
    a = tmp_path / "a.txt"
    a.write_text("x")
    check_outputs({"--out": tmp_path / "new.txt"}, inputs=[a])  # a new file: fine, and not left behind
    assert not (tmp_path / "new.txt").exists()
    check_outputs({"--out": None, "--csv": ""})  # options not given
    with pytest.raises(OutputPathError, match="already exists"):
        check_outputs({"--out": a})
    check_outputs({"--out": a}, overwrite=True)
    os.symlink(a, tmp_path / "link.txt")
    with pytest.raises(OutputPathError, match="is the input"):
        check_outputs({"--out": tmp_path / "link.txt"}, inputs=[a], overwrite=True)
    with pytest.raises(OutputPathError, match="is also given as --csv"):
        check_outputs({"--csv": tmp_path / "b.csv", "--table": tmp_path / "." / "b.csv"})
    os.symlink(tmp_path / "nowhere", tmp_path / "dangling")
    with pytest.raises(OutputPathError, match="is a symbolic link to .*which does not exist"):
        check_outputs({"--out": tmp_path / "dangling"}, overwrite=True)
    if os.geteuid() != 0:  # root writes into a read-only directory
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(0o500)
        try:
            with pytest.raises(OutputPathError, match="cannot be written"):
                check_outputs({"--out": ro / "x.txt"})
        finally:
            ro.chmod(0o700)
