"""The fuzz corpus as a test (docs/reliability.md, "Fuzz corpus").

A seeded corpus (tests/python/fuzz_corpus.py) of > 1,000 mutated config files,
`--set` overrides, damaged run files, friction node files, output paths and
damaged restart points, each run by the CLI with a time and memory limit.
Every case must end in one of

* exit 0 (ran to its end),
* exit 1 of `events` or `analyze` with one line "0 events kept ..." saying why
  (a readable run whose damage left no event to keep),
* exit 2 with one message line naming the key, section, option or attribute
  (or, for damage that has no key such as a truncated file, the input's path),
* exit 3 with a divergence diagnostic (node, time, values),
* exit 4 (the output could not be written),

and never in a signal, a timeout, another exit code or a Python traceback;
every stderr line is printable and at most 420 bytes.  A case that must be
refused (a damaged restart point, a forbidden output path) fails if it exits
0, and a valid one (an undamaged restart point) fails unless it exits 0.

    SLIPSTRIP_BIN=$PWD/build/slipstrip SLIPSTRIP_BUILD_DIR=$PWD/build PYTHONPATH=$PWD/python \\
        OMP_NUM_THREADS=1 /usr/bin/python3 -m pytest -q tests/python/test_fuzz.py

SLIPSTRIP_FUZZ_SEED changes the seed (to explore; CI uses the fixed one),
SLIPSTRIP_FUZZ_WORKERS the number of worker processes (default 2) and
SLIPSTRIP_FUZZ_FAMILIES=restart,outpath runs only those families.
"""
import collections
import concurrent.futures
import multiprocessing
import os
import shutil
import subprocess
import time
from pathlib import Path

import h5py
import pytest

import fuzz_corpus

# Minutes long: run by scripts/test.sh --all and .ci/run, not the fast tier.
pytestmark = pytest.mark.slow

SEED = int(os.environ.get("SLIPSTRIP_FUZZ_SEED", fuzz_corpus.SEED))
WORKERS = int(os.environ.get("SLIPSTRIP_FUZZ_WORKERS", "2"))
# Comma-separated families to run (e.g. "restart,outpath"), to study a change; CI runs all.
FAMILIES = set(filter(None, os.environ.get("SLIPSTRIP_FUZZ_FAMILIES", "").split(",")))


def _layout(path):
    objects, attrs = {}, {}
    with h5py.File(path, "r") as f:
        attrs["/"] = sorted(f.attrs)

        def visit(name, obj):
            objects["/" + name] = "group" if isinstance(obj, h5py.Group) else "dataset"
            if len(obj.attrs):
                attrs["/" + name] = sorted(obj.attrs)
        f.visititems(visit)
    return {"objects": objects, "attrs": attrs, "size": path.stat().st_size}


@pytest.fixture(scope="module")
def base_runs(cli, repo, tmp_path_factory):
    """A small run file with every group (slip sampling, snapshots, stations,
    rupture front), and a copy with /events; bitwise reproducible, so the
    corpus drawn from its layout is too."""
    d = tmp_path_factory.mktemp("fuzz_base")
    plain = d / "plain.h5"
    r = subprocess.run([str(cli), "run", str(repo / "configs/quickstart.toml"), "--set", "geometry.nodes=32",
                        "--set", "time.duration_transits=12", "--set", "output.snapshot_interval=2e-5",
                        "--set", "output.stations=[0.1, 0.3]", "--set", "output.front_slip_rate=2e-2",
                        "--out", str(plain), "--quiet"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    events = d / "events.h5"
    shutil.copy(plain, events)
    r = subprocess.run([str(cli), "events", str(events)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    # An interrupted run and its restart point, for the restart family: the
    # corpus's usual 16 nodes and ~3 steps, stopped after the first.
    interrupted = d / "interrupted.h5"
    r = subprocess.run([str(cli), "run", str(repo / "configs/quickstart.toml"), *fuzz_corpus.CAP_NODES,
                        *fuzz_corpus.CAP_DURATION, "--set", "output.snapshot_interval=1e-7",
                        "--set", "output.stations=[0.1]", "--set", "output.station_interval=1e-7",
                        "--out", str(interrupted), "--quiet", "--stop-after-steps", str(fuzz_corpus.RESTART_STEP)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 143, r.stderr
    return {"plain": str(plain), "events": str(events), "interrupted": str(interrupted)}


def _restart_layout(path):
    """Datasets (non-empty) and attributes of a restart point, sorted, and the
    values of the fields the corpus edits (to know which edits change them)."""
    datasets, attrs = [], []
    with h5py.File(path, "r") as f:
        attrs += [("/", a) for a in sorted(f.attrs)]

        def visit(name, obj):
            if isinstance(obj, h5py.Dataset) and obj.size > 0:
                datasets.append("/" + name)
            attrs.extend(("/" + name, a) for a in sorted(obj.attrs))
        f.visititems(visit)
        values = {f"{group}@{attr}": f[group].attrs[attr].item() for group, attr in fuzz_corpus.RESTART_FIELDS}
    return {"datasets": sorted(datasets), "attrs": sorted(attrs), "values": values}


@pytest.fixture(scope="module")
def corpus(repo, base_runs):
    return fuzz_corpus.generate(repo, _layout(Path(base_runs["plain"])), seed=SEED,
                                restart_layout=_restart_layout(base_runs["interrupted"] + ".restart"))


def test_corpus_is_large_seeded_and_deterministic(repo, base_runs, corpus):
    assert len(corpus) >= 1000
    again = fuzz_corpus.generate(repo, _layout(Path(base_runs["plain"])), seed=SEED,
                                 restart_layout=_restart_layout(base_runs["interrupted"] + ".restart"))
    assert [(c.kind, c.argv, c.config_bytes, c.damage) for c in again] == \
           [(c.kind, c.argv, c.config_bytes, c.damage) for c in corpus]
    families = collections.Counter(c.family for c in corpus)
    assert families["config"] >= 300 and families["override"] >= 300 and families["runfile"] >= 200
    assert families["nodefile"] >= 30 and families["outpath"] >= 20 and families["restart"] >= 150
    # Every case that reaches a time loop is capped (or draws only invalid/small values for the cap's key).
    for c in corpus:
        if c.argv[0] == "run" and "--resume" not in c.argv:   # a resumed run is the capped base run
            joined = " ".join(c.argv)
            assert "geometry.nodes=16" in joined or "nodes" in c.kind or "dx" in c.kind, c.kind
            assert "duration_transits=0.05" in joined or "duration" in c.kind, c.kind


def test_fuzz_corpus(cli, repo, base_runs, corpus, tmp_path, capsys):
    if FAMILIES:
        corpus = [c for c in corpus if c.family in FAMILIES]
    t0 = time.monotonic()
    python_dir = str(repo / "python")
    ctx = multiprocessing.get_context("fork")
    with concurrent.futures.ProcessPoolExecutor(max_workers=WORKERS, mp_context=ctx) as pool:
        results = list(pool.map(fuzz_corpus.execute, corpus, [str(cli)] * len(corpus),
                                [python_dir] * len(corpus), [base_runs] * len(corpus),
                                [str(tmp_path)] * len(corpus), chunksize=4))
    wall = time.monotonic() - t0
    by_class = collections.Counter(r["class"] for r in results)
    by_family = collections.defaultdict(collections.Counter)
    for r in results:
        by_family[r["family"]][r["class"]] += 1
    slowest = max(results, key=lambda r: r["seconds"])
    runfile_errors = [r for r in results if r["family"] == "runfile" and r["class"] == "input error"]
    named = sum(r["named"] for r in runfile_errors)
    summary = (f"fuzz: {len(results)} cases (seed {SEED}) in {wall:.0f} s with {WORKERS} workers: "
               + ", ".join(f"{k} {v}" for k, v in sorted(by_class.items()))
               + "; " + "; ".join(f"{fam}: " + ", ".join(f"{k} {v}" for k, v in sorted(c.items()))
                                  for fam, c in sorted(by_family.items()))
               + f"; run-file input errors naming the damaged object or attribute (not only the file): "
                 f"{named} of {len(runfile_errors)}"
               + f"; slowest case {slowest['seconds']:.1f} s ({slowest['ident']})")
    with capsys.disabled():   # shown even under pytest -q
        print("\n" + summary)
    if os.environ.get("SLIPSTRIP_FUZZ_REPORT"):   # every result as JSON, to study a run
        import json
        Path(os.environ["SLIPSTRIP_FUZZ_REPORT"]).write_text(json.dumps(results, indent=1))
    failures = [r for r in results if not r["ok"]]
    report = "\n".join(f"{r['ident']} [{r['class']}] {r['kind']!r} exit {r['returncode']}: "
                       f"{r['stderr'].strip()[-600:]!r}" for r in failures[:40])
    assert not failures, f"{len(failures)} of {len(results)} cases failed:\n{report}"


# ---------------------------------------------------------------------------
# Regression tests of the bugs the corpus found (docs/reliability.md, "Fuzz corpus")
# ---------------------------------------------------------------------------

def _run(cli, *args, **kw):
    env = dict(os.environ, SLIPSTRIP_BIN=str(cli))
    return subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True, env=env, timeout=120, **kw)


def _one_line(stderr):
    lines = [l for l in stderr.splitlines() if l.strip()]
    assert len(lines) == 1 and "Traceback" not in stderr, stderr
    return lines[0]


def test_events_on_a_truncated_run_file_is_an_input_error(cli, base_runs, tmp_path):
    # was: exit 1, "error: HDF5 error: H5Fopen(...) failed: truncated file"
    path = tmp_path / "cut.h5"
    path.write_bytes(Path(base_runs["plain"]).read_bytes()[:-600])
    r = _run(cli, "events", path)
    assert r.returncode == 2, r.stderr
    assert str(path) in _one_line(r.stderr) and "truncated" in r.stderr


def test_analyze_on_a_damaged_run_file_exits_2(cli, base_runs, tmp_path):
    # was: exit 1 (docs/reliability.md's table says 2 for a malformed run file)
    path = tmp_path / "bad.h5"
    shutil.copy(base_runs["plain"], path)
    with h5py.File(path, "r+") as f:
        del f["slip_sampling"]
    r = _run(cli, "analyze", path, "--out-dir", tmp_path / "out")
    assert r.returncode == 2, r.stderr
    assert str(path) in _one_line(r.stderr) and "slip_sampling" in r.stderr


@pytest.mark.parametrize("damage", ["one_d", "group"])
def test_export_on_a_damaged_run_file_gives_one_line(cli, base_runs, tmp_path, damage):
    # was: a Python traceback (IndexError, TypeError) and exit 1
    path = tmp_path / "bad.h5"
    shutil.copy(base_runs["plain"], path)
    with h5py.File(path, "r+") as f:
        if damage == "one_d":
            slip = f["stations/slip"][:, 0]
            del f["stations/slip"]
            f["stations/slip"] = slip
        else:
            del f["stations/x"]
            f.create_group("stations/x")
    r = _run(cli, "export", path, "--seas", tmp_path / "seas")
    assert r.returncode == 2, r.stderr
    assert str(path) in _one_line(r.stderr)


@pytest.mark.parametrize("override, key", [
    ("geometry.nodes=16\x7f", "geometry.nodes"),                # was: exit 1, a toml++ message naming nothing
    ("state.law=slip\n[geometry]\nnodes = 9", "state.law"),     # was: a three-line message
    ("geometry.nodes\n=16", "geometry.nodes"),                  # was: a two-line message
])
def test_override_with_control_characters_is_one_line_naming_the_key(cli, repo, tmp_path, override, key):
    r = _run(cli, "run", repo / "configs/quickstart.toml", "--set", override, "--out", tmp_path / "o.h5", "--quiet")
    assert r.returncode == 2, r.stderr
    assert key in _one_line(r.stderr)


@pytest.mark.parametrize("args, name", [
    (["--max-steps", "0"], "--max-steps"),          # was: two lines, a 300-digit range
    (["--max-memory-gib", "inf"], "--max-memory-gib"),
    (["--nonsense"], "--nonsense"),                 # was: two lines ("Run with --help ...")
])
def test_usage_errors_are_one_line(cli, repo, tmp_path, args, name):
    r = _run(cli, "run", repo / "configs/quickstart.toml", *args, "--out", tmp_path / "o.h5")
    assert r.returncode == 2, r.stderr
    line = _one_line(r.stderr)
    assert name in line and len(line) < 300


def test_impossible_initial_state_names_the_key(cli, repo, tmp_path):
    # was: "reduce [initial] noise_amplitude / ..." (not the key as written in --set)
    r = _run(cli, "run", repo / "configs/quickstart.toml", "--set", "initial.noise_amplitude=1e308",
             "--set", "geometry.nodes=16", "--out", tmp_path / "o.h5", "--quiet")
    assert r.returncode == 2, r.stderr
    assert "initial.noise_amplitude" in r.stderr
