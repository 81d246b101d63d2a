"""Parameter scans (python/slipstrip/scan/, docs/scans.md).

Runs real, tiny `slipstrip run`s (configs/quickstart.toml with N = 64 nodes
for 2 L/c_s, ~0.2 s each) and checks the summary table against the run files
themselves: the parameters against each file's own resolved config, the
statuses against each file's root `status` attribute, n_events against the
/events catalog.  Tests that need the solver skip when it is not built.

Run: /usr/bin/python3 -m pytest tests/python/test_scan.py
"""
import importlib
import importlib.util
import json
import math
import os
import re
import shlex
import subprocess
import sys
import tomllib
from pathlib import Path

import h5py
import numpy as np
import pytest
from figure_checks import assert_figure

REPO = Path(__file__).resolve().parents[2]


def _load_scan_module():
    # The package (python/slipstrip/scan/): the scan detects events and analyses
    # runs in-process, so it needs the package with its bindings.
    sys.path.insert(0, str(REPO / "python"))
    return importlib.import_module("slipstrip.scan")


scan = _load_scan_module()

TINY = {  # makes a quickstart run take ~0.2 s (tests/python/test_scan.py header)
    "geometry.nodes": 64,
    "time.duration_transits": 2,
    "output.snapshot_interval": 0,
}


@pytest.fixture(autouse=True)
def one_thread_per_run(monkeypatch):
    # One OpenMP thread per run: on a loaded machine, 2 spinning threads per tiny
    # run made it ~10x slower (measured 0.44 s vs 0.04 s).  The scan keeps a
    # user's OMP_NUM_THREADS.
    monkeypatch.setenv("OMP_NUM_THREADS", "1")


@pytest.fixture(scope="module")
def binary():
    try:
        path = scan.find_binary()
    except FileNotFoundError as e:
        pytest.skip(f"slipstrip binary not built: {e}")
    if not Path(path).is_file():
        pytest.skip(f"slipstrip binary {path} not found")
    return path


def write_scan(path: Path, parameters: str, mode: str = "product", fixed: dict | None = None) -> Path:
    fixed = dict(TINY if fixed is None else fixed)
    lines = [f'base = "{REPO / "configs/quickstart.toml"}"', f'mode = "{mode}"', 'output_dir = "out"', "", "[fixed]"]
    lines += [f'"{k}" = {json.dumps(v)}' for k, v in fixed.items()]
    path.write_text("\n".join(lines) + "\n\n" + parameters)
    return path


def resolved_config(run_file: Path) -> dict:
    with h5py.File(run_file, "r") as f:
        text = f.attrs["config"]
    return tomllib.loads(text.decode() if isinstance(text, bytes) else text)


def file_status(run_file: Path) -> str:
    with h5py.File(run_file, "r") as f:
        s = f.attrs["status"]
    return s.decode() if isinstance(s, bytes) else str(s)


def read_csv(path: Path) -> list[dict]:
    import csv
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


# ------------------------------------------------------------------ scan file (no solver needed)


def test_product_zip_ranges_and_overrides(tmp_path):
    base = tmp_path / "base.toml"
    base.write_text("")
    (tmp_path / "s.toml").write_text("""
base = "base.toml"
mode = "product"
[fixed.geometry]
nodes = 64
[[parameter]]
key = "friction.a"
values = [0.004, 0.006]
[[parameter]]
key = "geometry.height"
logspace = {start = 0.01, stop = 1.0, num = 3}
[[parameter]]
key = "state.law"
values = ["aging", "slip"]
""")
    spec = scan.load_scan(tmp_path / "s.toml", output_dir=tmp_path / "o")
    assert spec.base_config == base.resolve()  # relative to the scan file, not the cwd
    runs = scan.expand_runs(spec)
    # Product: 2 x 3 x 2, last parameter fastest (itertools.product order).
    assert len(runs) == 12
    heights = [r.parameters["geometry.height"] for r in runs]
    # Log spacing between the end VALUES: 0.01, 0.1, 1 (relative 1e-12: one exp/log round trip).
    assert heights[:6:2] == pytest.approx([0.01, 0.1, 1.0], rel=1e-12)
    assert runs[0].parameters == {"friction.a": 0.004, "geometry.height": 0.01, "state.law": "aging"}
    assert runs[1].parameters["state.law"] == "slip"
    assert runs[11].parameters == {"friction.a": 0.006, "geometry.height": 1.0, "state.law": "slip"}
    # Fixed first, then the varied ones, each a TOML literal the config reader parses back.
    assert runs[1].overrides[0] == "geometry.nodes=64"
    for o in runs[7].overrides:
        key, value = o.split("=", 1)
        section, name = key.split(".")
        parsed = tomllib.loads(f"{name} = {value}")[name]
        expected = runs[7].parameters.get(key, 64)
        assert parsed == expected and type(parsed) is type(expected)
    assert runs[3].run_file == (tmp_path / "o" / "run_0003.h5")

    (tmp_path / "z.toml").write_text("""
base = "base.toml"
mode = "zip"
[[parameter]]
key = "geometry.nodes"
range = {start = 64, stop = 256, num = 3}
[[parameter]]
key = "friction.b"
values = [0.05, 0.06, 0.07]
""")
    runs = scan.expand_runs(scan.load_scan(tmp_path / "z.toml"))
    # Integer ends, whole values: integers (geometry.nodes must be a TOML integer).
    assert [r.parameters["geometry.nodes"] for r in runs] == [64, 160, 256]
    assert all(type(r.parameters["geometry.nodes"]) is int for r in runs)
    assert [r.parameters["friction.b"] for r in runs] == [0.05, 0.06, 0.07]


def test_grouped_parameters_move_together_inside_a_product(tmp_path):
    # The transition map's friction family: (f0, a, b) step together along one
    # axis while the strip height is crossed with it.
    (tmp_path / "base.toml").write_text("")
    (tmp_path / "s.toml").write_text("""
base = "base.toml"
[[parameter]]
key = "friction.f0"
values = [0.28, 0.18]
group = "friction"
[[parameter]]
key = "geometry.height"
values = [0.1, 0.2, "inf"]
[[parameter]]
key = "friction.a"
values = [0.005, 0.015]
group = "friction"
""")
    runs = scan.expand_runs(scan.load_scan(tmp_path / "s.toml", output_dir=tmp_path / "o"))
    assert len(runs) == 6  # 2 friction points x 3 heights, not 2 x 3 x 2
    pairs = {(r.parameters["friction.f0"], r.parameters["friction.a"]) for r in runs}
    assert pairs == {(0.28, 0.005), (0.18, 0.015)}
    # The group stands where its first parameter is declared: friction slowest, height fastest.
    assert [r.parameters["geometry.height"] for r in runs[:3]] == [0.1, 0.2, "inf"]
    assert runs[3].parameters == {"friction.f0": 0.18, "geometry.height": 0.1, "friction.a": 0.015}
    # Overrides keep the declaration order.
    assert [o.split("=")[0] for o in runs[0].overrides] == ["friction.f0", "geometry.height", "friction.a"]


@pytest.mark.parametrize("body, message", [
    ('mode = "zip"\n[[parameter]]\nkey = "friction.a"\nvalues = [1, 2]\n[[parameter]]\nkey = "friction.b"\nvalues = [1]\n',
     "equal length"),
    ('mode = "grid"\n', "mode = 'grid' is not allowed"),
    ('[[parameter]]\nkey = "height"\nvalues = [1]\n', "'height' is not allowed"),
    ('[[parameter]]\nkey = "friction.a"\nrange = {start = 1, stop = 2}\n', "range"),
    ('[[parameter]]\nkey = "friction.a"\nlogspace = {start = 0, stop = 2, num = 3}\n', "needs values > 0"),
    ('[[parameter]]\nkey = "friction.a"\nvalues = [1]\nrange = {start = 1, stop = 2, num = 2}\n', "exactly one"),
    ('[fixed]\n"friction.a" = 1\n[[parameter]]\nkey = "friction.a"\nvalues = [1]\n', "more than once"),
    ('outputdir = "x"\n', "unknown top-level key"),
    ('[[parameter]]\nkey = "friction.a"\nvalues = [1, 2]\ngroup = "g"\n[[parameter]]\nkey = "friction.b"\nvalues = [1]\ngroup = "g"\n',
     "group 'g' needs lists of equal length"),
    ('mode = "zip"\n[[parameter]]\nkey = "friction.a"\nvalues = [1]\ngroup = "g"\n', "only allowed with mode"),
    ('[[parameter]]\nkey = "friction.a"\nvalues = [1]\ngroup = 3\n', "group = 3 is not allowed"),
])
def test_bad_scan_files_name_the_problem(tmp_path, body, message):
    (tmp_path / "base.toml").write_text("")
    (tmp_path / "s.toml").write_text('base = "base.toml"\n' + body)
    with pytest.raises(ValueError, match=re.escape(message)):
        scan.load_scan(tmp_path / "s.toml")


def test_example_scans_match_the_paper_cases():
    h = scan.expand_runs(scan.load_scan(REPO / "configs/scans/fig3c_heights.toml"))
    assert [r.parameters["geometry.height"] for r in h] == [0.05, 0.1, 0.2]
    d = scan.expand_runs(scan.load_scan(REPO / "configs/scans/fig3d_density.toml"))
    rho = [r.parameters["material.density"] for r in d]
    assert rho == [300.0, 1200.0, 4800.0]
    # c_s = sqrt(mu/rho) doubles at 300 and halves at 4800 (Table S1 mu = 9e9 Pa, reference rho = 1200).
    c_ref = math.sqrt(9e9 / 1200.0)
    assert [math.sqrt(9e9 / r) / c_ref for r in rho] == pytest.approx([2.0, 1.0, 0.5], rel=1e-15)
    for spec in (scan.load_scan(REPO / "configs/scans/fig3c_heights.toml"),
                 scan.load_scan(REPO / "configs/scans/fig3d_density.toml")):
        assert spec.base_config == (REPO / "configs/reference.toml").resolve()


def test_example_scans_give_valid_configs(binary, tmp_path):
    """Every run of the example scans is accepted by the solver (cut down to a few steps)."""
    for name in ("fig3c_heights", "fig3d_density"):
        spec = scan.load_scan(REPO / f"configs/scans/{name}.toml", output_dir=tmp_path / name)
        spec.output_dir.mkdir()
        for task in scan.expand_runs(spec):
            cmd = [binary, "run", str(spec.base_config)]
            for o in task.overrides + ("geometry.nodes=64", "time.duration_transits=0.1"):
                cmd += ["--set", o]
            proc = subprocess.run(cmd + ["--out", str(task.run_file), "--quiet"], capture_output=True, text=True)
            assert proc.returncode == 0, proc.stderr
            cfg = resolved_config(task.run_file)
            key, value = next(iter(task.parameters.items()))
            section, k = key.split(".")
            assert cfg[section][k] == value


def test_dry_run_checks_every_runs_config(tmp_path, capsys):
    """A misspelt key (or a bad value of one run) fails `--dry-run` with the
    config reader's message, before anything runs; a good scan passes."""
    pytest.importorskip("slipstrip._slipstrip")
    scan_file = write_scan(tmp_path / "s.toml", """
[[parameter]]
key = "geometry.hieght"
values = [0.02, 0.03]
""")
    assert scan.main([str(scan_file), "--dry-run"]) == 2
    captured = capsys.readouterr()
    assert len(captured.out.splitlines()) == 2  # the runs are still listed
    errors = [l for l in captured.err.splitlines() if l.startswith("error: run ")]
    assert len(errors) == 2 and all("geometry.hieght" in l and "geometry.height" in l for l in errors)
    assert "2 of 2 runs have an invalid config" in captured.err
    assert not (tmp_path / "out").exists()  # nothing ran, nothing was written

    # One bad value among good ones: only that run is named.
    write_scan(scan_file, '[[parameter]]\nkey = "material.density"\nvalues = [1200.0, -5.0]\n')
    assert scan.main([str(scan_file), "--dry-run"]) == 2
    err = capsys.readouterr().err
    assert "run 1 (run_0001.h5)" in err and "material.density" in err and "run 0 " not in err

    write_scan(scan_file, '[[parameter]]\nkey = "geometry.height"\nvalues = [0.02, 0.03]\n')
    assert scan.main([str(scan_file), "--dry-run"]) == 0
    assert "all 2 run configs are valid" in capsys.readouterr().err


def test_analysis_failure_is_recorded_not_raised(tmp_path):
    run_file = tmp_path / "r.h5"
    with h5py.File(run_file, "w") as f:
        f.create_group("events").attrs["n_events"] = 7

    def broken(path):
        raise RuntimeError("no fit for you")

    row = scan.summarize_run_file(run_file, summarizer=broken)
    assert row["analysis_error"] == "RuntimeError: no fit for you"
    assert all(math.isnan(row[k]) for k in scan.ANALYSIS_KEYS if k != "n_events")
    assert row["n_events"] == 7  # from the catalog itself

    row = scan.summarize_run_file(run_file, summarizer=lambda p: {"small_exponent_u": np.float64(1.5),
                                                                   "periodic_pulse": np.bool_(True)})
    assert row["analysis_error"] == ""
    assert row["small_exponent_u"] == 1.5 and type(row["small_exponent_u"]) is float
    assert row["periodic_pulse"] is True


# ------------------------------------------------------------------ this machine (--jobs)


def test_scan_jobs2_summary_and_relaunch_skips(binary, tmp_path, capfd):
    scan_file = write_scan(tmp_path / "s.toml", """
[[parameter]]
key = "friction.a"
values = [0.005, 0.006]
[[parameter]]
key = "geometry.height"
values = [0.02, 0.03]
""")
    out = tmp_path / "out"
    rc = scan.main([str(scan_file), "--jobs", "2", "--out", str(out), "--binary", binary])
    err = capfd.readouterr().err
    assert rc == 0, err
    # Progress covers the whole scan: the last line says 4/4 with elapsed time and an ETA.
    progress = [l for l in err.splitlines() if l.startswith("[scan]")]
    assert len(progress) == 4 and progress[-1].startswith("[scan] 4/4 runs done")
    assert "elapsed" in progress[0] and "ETA" in progress[0]

    rows = read_csv(out / "summary.csv")
    assert len(rows) == 4
    expected = [(0.005, 0.02), (0.005, 0.03), (0.006, 0.02), (0.006, 0.03)]
    for row, (a, height) in zip(rows, expected):
        run_file = out / row["run_file"]
        cfg = resolved_config(run_file)
        # The table's parameters are the ones the solver actually used.
        assert float(row["friction.a"]) == a == cfg["friction"]["a"]
        assert float(row["geometry.height"]) == height == cfg["geometry"]["height"]
        assert cfg["geometry"]["nodes"] == 64
        assert row["status"] == "completed" == file_status(run_file)
        assert row["error"] == ""
        assert float(row["wall_time_s"]) > 0
        with h5py.File(run_file, "r") as f:
            assert "events" in f  # `slipstrip events` ran before the summary
            assert float(row["n_events"]) == f["events"].attrs["n_events"]

    with h5py.File(out / "summary.h5", "r") as f:
        g = f["summary"]
        assert list(g["friction.a"][()]) == [0.005, 0.005, 0.006, 0.006]
        assert list(g["geometry.height"][()]) == [0.02, 0.03, 0.02, 0.03]
        assert [s.decode() for s in g["status"][()]] == ["completed"] * 4
        for key in scan.ANALYSIS_KEYS:
            assert key in g and g[key].shape == (4,)

    mtimes = {p.name: p.stat().st_mtime_ns for p in out.glob("run_*")}
    assert len(mtimes) == 8  # 4 run files + 4 rows
    rc = scan.main([str(scan_file), "--jobs", "2", "--out", str(out), "--binary", binary])
    err = capfd.readouterr().err
    assert rc == 0, err
    assert err.count("skipped: already completed") == 4
    assert {p.name: p.stat().st_mtime_ns for p in out.glob("run_*")} == mtimes  # nothing re-ran
    rows2 = read_csv(out / "summary.csv")
    assert [{k: v for k, v in r.items()} for r in rows2] == rows


def test_failing_run_is_recorded_and_others_complete(binary, tmp_path, capfd):
    scan_file = write_scan(tmp_path / "s.toml", """
[[parameter]]
key = "material.density"
values = [1200.0, -5.0, 2400.0]
""")
    out = tmp_path / "out"
    rc = scan.main([str(scan_file), "--jobs", "2", "--out", str(out), "--binary", binary])
    capfd.readouterr()
    assert rc == 1  # some run failed
    rows = read_csv(out / "summary.csv")
    assert [r["status"] for r in rows] == ["completed", "failed", "completed"]
    # The solver's own message, naming the key and the value.
    assert "material.density" in rows[1]["error"] and "-5" in rows[1]["error"]
    assert "exited with code" in rows[1]["error"]
    assert not (out / rows[1]["run_file"]).exists()
    assert rows[0]["error"] == rows[2]["error"] == ""
    assert file_status(out / rows[2]["run_file"]) == "completed"

    # A re-launch retries the failed run only (the completed ones are untouched).
    before = (out / rows[0]["run_file"]).stat().st_mtime_ns
    scan.main([str(scan_file), "--out", str(out), "--binary", binary])
    err = capfd.readouterr().err
    assert err.count("skipped: already completed") == 2
    assert (out / rows[0]["run_file"]).stat().st_mtime_ns == before
    assert [r["status"] for r in read_csv(out / "summary.csv")] == ["completed", "failed", "completed"]


def test_edited_scan_reruns_changed_runs(binary, tmp_path, capfd):
    body = '[[parameter]]\nkey = "friction.a"\nvalues = [{}]\n'
    scan_file = write_scan(tmp_path / "s.toml", body.format("0.005"))
    out = tmp_path / "out"
    assert scan.main([str(scan_file), "--out", str(out), "--binary", binary]) == 0
    write_scan(tmp_path / "s.toml", body.format("0.007"))
    assert scan.main([str(scan_file), "--out", str(out), "--binary", binary]) == 0
    assert "made with other overrides" in capfd.readouterr().err
    assert resolved_config(out / "run_0000.h5")["friction"]["a"] == 0.007
    # Edited to an invalid value: the old completed file must not pass for this run's result.
    write_scan(tmp_path / "s.toml", body.format("-0.001"))
    for _ in range(2):  # and a re-launch must not take it for finished either
        assert scan.main([str(scan_file), "--out", str(out), "--binary", binary]) == 1
        rows = read_csv(out / "summary.csv")
        assert rows[0]["status"] == "failed" and "friction.a" in rows[0]["error"]
        assert not (out / "run_0000.h5").exists()


# ------------------------------------------------------------------ beyond one machine


# Slow tier: a local Dask cluster's start-up (worker processes importing
# distributed) is most of its cost, and it checks the scan's distribution, not physics.
@pytest.mark.slow
def test_dask_local_cluster(binary, tmp_path, capfd):
    distributed = pytest.importorskip("distributed")
    scan_file = write_scan(tmp_path / "s.toml", """
[[parameter]]
key = "geometry.height"
values = [0.02, 0.03]
""", mode="zip")
    out = tmp_path / "out"
    # processes=True: the run function really travels to other processes (pickled by value).
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        rc = scan.main([str(scan_file), "--dask", cluster.scheduler_address, "--out", str(out),
                        "--binary", binary])
    err = capfd.readouterr().err
    assert rc == 0, err
    rows = read_csv(out / "summary.csv")
    assert [float(r["geometry.height"]) for r in rows] == [0.02, 0.03]
    for r in rows:
        assert r["status"] == "completed" == file_status(out / r["run_file"])
        assert resolved_config(out / r["run_file"])["geometry"]["height"] == float(r["geometry.height"])


def test_emit_slurm(binary, tmp_path, capfd):
    scan_file = write_scan(tmp_path / "s.toml", """
[[parameter]]
key = "friction.a"
values = [0.005, 0.006, 0.007]
[[parameter]]
key = "geometry.height"
values = [0.02, 0.03]
""")
    out, slurm = tmp_path / "out dir", tmp_path / "slurm"  # a space: the scripts must quote paths
    assert scan.main([str(scan_file), "--emit-slurm", str(slurm), "--out", str(out), "--binary", binary]) == 0
    script = (slurm / "scan.sbatch").read_text()
    assert script.startswith("#!/bin/bash\n")
    assert re.findall(r"^#SBATCH --array=(\S+)$", script, re.M) == ["0-5"]
    assert subprocess.run(["bash", "-n", str(slurm / "scan.sbatch")]).returncode == 0  # syntax
    tasks = sorted((slurm / "tasks").glob("task_*.json"))
    assert len(tasks) == 6
    # Bash array index i (= SLURM_ARRAY_TASK_ID) -> the task file of run i.
    listed = re.search(r"^TASKS=\(\n(.*?)\n\)$", script, re.M | re.S).group(1).split("\n")
    assert [Path(shlex.split(l)[0]) for l in listed] == tasks
    spec = scan.load_scan(scan_file, output_dir=out)
    for i, (path, run) in enumerate(zip(tasks, scan.expand_runs(spec))):
        task = json.loads(path.read_text())
        assert task["index"] == i
        assert task["overrides"] == list(run.overrides)
        assert task["run_file"] == str(out / f"run_{i:04d}.h5")
        assert task["base_config"] == str(REPO / "configs/quickstart.toml")
    # Runs as Slurm would run array task 4, without Slurm.
    env = dict(os.environ, SLURM_ARRAY_TASK_ID="4", SLIPSTRIP_BIN=binary)
    proc = subprocess.run(["bash", str(slurm / "scan.sbatch")], env=env, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert sorted(p.name for p in out.glob("run_*.h5")) == ["run_0004.h5"]
    cfg = resolved_config(out / "run_0004.h5")
    assert (cfg["friction"]["a"], cfg["geometry"]["height"]) == (0.007, 0.02)
    assert file_status(out / "run_0004.h5") == "completed"
    # collect.sbatch writes the table of what is on disk: one completed, five missing.
    proc = subprocess.run(["bash", str(slurm / "collect.sbatch")], env=env, capture_output=True, text=True)
    assert proc.returncode == 1, proc.stderr  # 1: not every run completed
    rows = read_csv(out / "summary.csv")
    assert [r["status"] for r in rows] == ["missing"] * 4 + ["completed", "missing"]


# ------------------------------------------------------------------ duration plots


def test_duration_pdf_of_log_uniform_sample():
    """Durations log-uniform on [a, b] have p(T) = 1 / (T ln(b/a))."""
    rng = np.random.default_rng(3)
    a, b = 1e-6, 1e-3
    t = np.exp(rng.uniform(math.log(a), math.log(b), 200_000))
    centres, density = scan.duration_pdf(t, n_bins=12)
    expected = 1.0 / (centres * math.log(b / a))
    # ~16700 samples per bin: relative standard error ~0.8 %, plus the geometric
    # centre vs. the bin average of 1/T (~0.5 % for 12 bins over 3 decades); 5 % is > 4 sigma.
    assert density == pytest.approx(expected, rel=0.05)


def test_height_round_trip_time_from_resolved_config():
    text = 'geometry = {height = 0.1}\nmaterial = {shear_modulus = 9e9, density = 1200.0}\n'
    assert scan.height_round_trip_time(text) == pytest.approx(2 * 0.1 / math.sqrt(9e9 / 1200.0), rel=1e-15)
    assert scan.height_round_trip_time('geometry = {height = "inf"}\nmaterial = {shear_modulus = 9e9, density = 300.0}\n') \
        == math.inf


def test_plot_duration_pdfs(tmp_path):
    """The plot reads the summary and every run's /events/T (synthetic files)."""
    spec_path = tmp_path / "s.toml"
    (tmp_path / "base.toml").write_text("")
    spec_path.write_text('base = "base.toml"\n[[parameter]]\nkey = "material.density"\nvalues = [300.0, 4800.0]\n')
    spec = scan.load_scan(spec_path, output_dir=tmp_path / "o")
    spec.output_dir.mkdir()
    rng = np.random.default_rng(0)
    rows = []
    for task in scan.expand_runs(spec):
        rho = task.parameters["material.density"]
        with h5py.File(task.run_file, "w") as f:
            f.attrs["config"] = f"[geometry]\nheight = 0.1\n[material]\nshear_modulus = 9e9\ndensity = {rho}\n"
            f.attrs["status"] = "completed"
            f.create_dataset("events/T", data=rng.lognormal(math.log(1e-4), 0.5, 300))
        rows.append({"index": task.index, **task.parameters, "status": "completed", "error": "",
                     "wall_time_s": 1.0, "run_file": task.run_file.name})
    scan.write_summary(spec, rows)
    png = scan.plot_duration_pdfs(spec.output_dir, tmp_path / "p.png")
    assert_figure(png)
