"""The one output-path rule (io/output_paths.hpp; slipstrip.paths calls it
through the bindings) in every command: an output that names an input is
refused even with --overwrite, an existing output only with --overwrite, and
the refusal is one line with exit code 2 that leaves every file as it was.
docs/reliability.md, "Output paths"."""
import os
import subprocess
import sys

import pytest

QUICK = ["--set", "geometry.nodes=64", "--set", "time.duration_transits=3", "--quiet"]


def _cli(cli, *args, **kw):
    env = dict(os.environ, SLIPSTRIP_BIN=str(cli), OMP_NUM_THREADS="1")
    return subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True, env=env, timeout=600, **kw)


def _py(repo, *args, **kw):
    env = dict(os.environ, PYTHONPATH=str(repo / "python"), OMP_NUM_THREADS="1")
    return subprocess.run([sys.executable, "-m", "slipstrip", *map(str, args)], capture_output=True, text=True,
                          env=env, timeout=600, **kw)


def _refused(r, *parts):
    """Exit 2 with one message line holding every part."""
    lines = [line for line in r.stderr.splitlines() if line.strip()]
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert len(lines) == 1 and "Traceback" not in r.stderr, r.stderr
    for part in parts:
        assert part in lines[0], (part, lines[0])
    return lines[0]


@pytest.fixture(scope="module")
def run_file(cli, repo, tmp_path_factory):
    out = tmp_path_factory.mktemp("paths") / "run.h5"
    r = _cli(cli, "run", repo / "configs/quickstart.toml", *QUICK, "--out", out)
    assert r.returncode == 0, r.stderr
    return out


def test_check_outputs_api(slipstrip_module, tmp_path):
    from slipstrip import paths
    run = tmp_path / "run.h5"
    run.write_bytes(b"data")
    with pytest.raises(paths.OutputPathError, match=r"is the input .*\(even with --overwrite\)"):
        paths.check_outputs({"--csv": tmp_path / "." / "run.h5"}, inputs=[run], overwrite=True)
    with pytest.raises(ValueError, match=r"already exists: refusing to overwrite it \(give overwrite=True"):
        paths.check_outputs({"out_path": run}, overwrite_flag="overwrite=True")
    paths.check_outputs({"out_path": run}, overwrite=True)
    paths.check_outputs({"--csv": None, "--plot": tmp_path / "new.png"})   # options not given are skipped
    assert not (tmp_path / "new.png").exists()
    with pytest.raises(paths.OutputPathError, match="is also given as --csv"):
        paths.check_outputs({"--csv": tmp_path / "a", "--plot": tmp_path / "a"})
    assert run.read_bytes() == b"data"


def test_transition_csv_never_replaces_a_run_file(repo, run_file, tmp_path):
    # Was: `transition RUN.h5 --csv RUN.h5` replaced the run file with CSV and exited 0.
    before = run_file.read_bytes()
    line = _refused(_py(repo, "transition", run_file, "--csv", run_file, "--overwrite"), "--csv", "is the input")
    assert str(run_file) in line
    assert run_file.read_bytes() == before
    existing = tmp_path / "map.csv"
    existing.write_text("earlier map\n")
    _refused(_py(repo, "transition", run_file, "--plot", existing), "--plot", "already exists", "--overwrite")
    _refused(_py(repo, "transition", "--previous", existing, "--csv", existing, "--overwrite"), "is the input")
    assert existing.read_text() == "earlier map\n"


def test_analyze_keeps_an_earlier_analysis_unless_overwrite(cli, repo, run_file, tmp_path):
    out_dir = tmp_path / "analysis"
    out_dir.mkdir()
    (out_dir / "summary.json").write_text("{}")
    _refused(_py(repo, "analyze", run_file, "--out-dir", out_dir), "summary.json", "already exists")
    assert (out_dir / "summary.json").read_text() == "{}"
    not_a_dir = tmp_path / "file"
    not_a_dir.write_text("x")
    _refused(_py(repo, "analyze", run_file, "--out-dir", not_a_dir), "--out-dir", "is not a directory")


def test_plot_and_plot_stability_refuse_their_input_and_existing_files(repo, run_file, tmp_path):
    before = run_file.read_bytes()
    _refused(_py(repo, "plot", run_file, "--out", run_file, "--overwrite"), "--out", "is the input")
    png = tmp_path / "old.png"
    png.write_bytes(b"old")
    _refused(_py(repo, "plot", run_file, "--out", png), "--out", "already exists")
    table = tmp_path / "lc.csv"
    table.write_text("height_m,critical_wavelength_m\n0.1,0.3\n")
    _refused(_py(repo, "plot-stability", table, "--out", table, "--overwrite"), "is the input")
    assert run_file.read_bytes() == before and png.read_bytes() == b"old"


def test_scan_plot_durations_never_replaces_the_scan_file(repo, tmp_path):
    scan = tmp_path / "scan.toml"
    scan.write_text(f'name = "s"\nbase = "{repo / "configs/quickstart.toml"}"\noutput_dir = "out"\n'
                    '[[parameter]]\nkey = "geometry.height"\nvalues = [0.1]\n')
    before = scan.read_text()
    _refused(_py(repo, "scan", scan, "--plot-durations", scan, "--overwrite"), "--plot-durations",
             "is the input")
    assert scan.read_text() == before


def test_events_csv_or_out_never_replaces_the_run_file(cli, run_file, tmp_path):
    # Was: `slipstrip events RUN.h5 --csv RUN.h5` replaced the run file with CSV and exited 0.
    before = run_file.read_bytes()
    for option in ("--csv", "--out"):
        for extra in ([], ["--overwrite"]):
            line = _refused(_cli(cli, "events", run_file, option, run_file, *extra), option, "is the input")
            assert str(run_file) in line
    assert run_file.read_bytes() == before
    existing = tmp_path / "old.csv"
    existing.write_text("old\n")
    _refused(_cli(cli, "events", run_file, "--csv", existing), "--csv", "already exists", "--overwrite")
    assert existing.read_text() == "old\n"
    _refused(_cli(cli, "events", run_file, "--out", tmp_path / "c", "--csv", tmp_path / "c"), "is also given as")
    # With --overwrite an existing catalog is replaced (and the run file still untouched).
    r = _cli(cli, "events", run_file, "--out", tmp_path / "catalog.h5", "--csv", existing, "--overwrite")
    # (exit 1 when this short run keeps no event: the catalog is written either way)
    assert r.returncode == 0 or (r.returncode == 1 and "0 events kept" in r.stderr), r.stderr
    assert existing.read_text() != "old\n"
    assert run_file.read_bytes() == before


def test_stability_out_never_replaces_the_config_or_an_existing_table(cli, repo, tmp_path):
    config = tmp_path / "c.toml"
    config.write_text((repo / "configs/quickstart.toml").read_text())
    before = config.read_text()
    _refused(_cli(cli, "stability", config, "--out", config, "--overwrite"), "--out", "is the input")
    table = tmp_path / "lc.csv"
    table.write_text("old\n")
    _refused(_cli(cli, "stability", config, "--out", table), "--out", "already exists")
    # the figure written next to the table is an output too
    (tmp_path / "new.png").write_bytes(b"old figure")
    _refused(_cli(cli, "stability", config, "--out", tmp_path / "new.csv"), "the figure of --out", "already exists")
    assert config.read_text() == before and table.read_text() == "old\n"
    assert (tmp_path / "new.png").read_bytes() == b"old figure" and not (tmp_path / "new.csv").exists()


def test_export_never_replaces_the_run_file_or_earlier_station_files(cli, repo, tmp_path):
    run = tmp_path / "stations.h5"
    r = _cli(cli, "run", repo / "configs/quickstart.toml", *QUICK, "--set", "output.stations=[0.1]", "--out", run)
    assert r.returncode == 0, r.stderr
    before = run.read_bytes()
    _refused(_py(repo, "export", run, "--seas", run), "--seas", "is the input")
    seas = tmp_path / "seas"
    r = _py(repo, "export", run, "--seas", seas)
    assert r.returncode == 0, r.stderr
    first = {p.name: p.read_bytes() for p in seas.iterdir()}
    assert "global.txt" in first and any(name.startswith("station_x") for name in first)
    (seas / "global.txt").write_text("edited\n")
    _refused(_py(repo, "export", run, "--seas", seas), "--seas station_x", "already exists", "--overwrite")
    assert (seas / "global.txt").read_text() == "edited\n"
    r = _py(repo, "export", run, "--seas", seas, "--overwrite")
    assert r.returncode == 0, r.stderr
    assert run.read_bytes() == before


def test_run_out_refusals_are_one_line(cli, repo, tmp_path):
    config = repo / "configs/quickstart.toml"
    # Was: "cannot be written: File exists" for a symbolic link to nothing.
    link = tmp_path / "dangling.h5"
    link.symlink_to(tmp_path / "missing" / "target.h5")
    _refused(_cli(cli, "run", config, *QUICK, "--out", link), "--out", "is a symbolic link to", "target.h5",
             "does not exist")
    fifo = tmp_path / "fifo.h5"
    os.mkfifo(fifo)
    _refused(_cli(cli, "run", config, *QUICK, "--out", fifo, "--overwrite"), "--out", "is a FIFO")
    for extra in ([], ["--overwrite"]):
        _refused(_cli(cli, "run", config, *QUICK, "--out", tmp_path, *extra), "--out", "is a directory")


def test_python_run_follows_the_rule(slipstrip_module, repo, tmp_path):
    ss = slipstrip_module
    config = tmp_path / "c.toml"
    config.write_text((repo / "configs/quickstart.toml").read_text())
    small = {"geometry.nodes": 16, "time.duration_transits": 0.05}
    with pytest.raises(ss.OutputPathError, match=r"out_path .* is the input .*even with overwrite=True"):
        ss.run(config, config, overrides=small, overwrite=True)
    out = tmp_path / "run.h5"
    out.write_bytes(b"earlier")
    with pytest.raises(ss.OutputPathError, match=r"already exists: .*give overwrite=True"):
        ss.run(config, out, overrides=small)
    assert out.read_bytes() == b"earlier"
    # A restart point it did not write is kept, unless overwrite=True replaces the run.
    out.unlink()
    restart = tmp_path / "run.h5.restart"
    restart.write_bytes(b"someone else's")
    with pytest.raises(ss.OutputPathError, match=r"the restart point of out_path .*already exists"):
        ss.run(config, out, overrides=small)
    assert restart.read_bytes() == b"someone else's" and not out.exists()
    assert ss.run(config, out, overrides=small, overwrite=True).status == "completed"
    assert not restart.exists() and config.read_text() == (repo / "configs/quickstart.toml").read_text()
