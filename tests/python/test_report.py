"""Tests of the reproduction report (python/slipstrip/report/) and of the two
rules it relies on in slipstrip.analysis: the automatic transient cut and the
space-time periodic-pulse criterion.

Synthetic catalogs and space-time fields test the rules; tiny real runs
(N = 64, a few L/c_s) test that every table row is computed from the run
files, and the missing-file behaviour.  Needs the CLI binary for the real
runs (skipped without it).

Run: /usr/bin/python3 -m pytest tests/python/test_report.py
"""
import io
import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from figure_checks import assert_figure

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "python"))
from slipstrip import analysis  # noqa: E402
from slipstrip import divergence  # noqa: E402
from slipstrip import episodes as episodes_command  # noqa: E402
from slipstrip import report  # noqa: E402
from slipstrip.runfile import read_config  # noqa: E402

# ---------------------------------------------------------------------------
# Transient cut on synthetic catalogs
# ---------------------------------------------------------------------------


def synthetic_catalog(seed, t_end=1.0, rate=2000.0, t_transient=0.0, transient_rate=6000.0, slip_shift=0.5):
    """Poisson events with power-law-like slips u/D (log10 u = -1.7 + Exp(0.35));
    during [0, t_transient] extra events at rate transient_rate - rate with
    slips larger by 10**slip_shift."""
    rng = np.random.default_rng(seed)
    n = rng.poisson(rate * t_end)
    t = rng.uniform(0, t_end, n)
    logu = -1.7 + rng.exponential(0.35, n)
    if t_transient > 0:
        m = rng.poisson((transient_rate - rate) * t_transient)
        t = np.concatenate([t, rng.uniform(0, t_transient, m)])
        logu = np.concatenate([logu, -1.7 + slip_shift + rng.exponential(0.35, m)])
    o = np.argsort(t)
    return t[o], 10 ** logu[o]


def test_transient_cut_finds_a_transient():
    cuts = [analysis.transient_cut(*synthetic_catalog(seed, t_transient=0.3), t_end=1.0)["t_cut"]
            for seed in range(10)]
    # The batches are 1/40 of the run: the rule cuts at the end of the transient or a little later.
    assert all(0.275 <= c <= 0.5 for c in cuts), cuts
    assert abs(np.median(cuts) - 0.3) <= 0.05, cuts


def test_transient_cut_of_a_weak_transient():
    cuts = [analysis.transient_cut(*synthetic_catalog(seed, t_transient=0.2, transient_rate=3000.0,
                                                       slip_shift=0.2), t_end=1.0)["t_cut"] for seed in range(10)]
    assert abs(np.median(cuts) - 0.2) <= 0.05, cuts
    assert all(c >= 0.15 for c in cuts), cuts


def test_transient_cut_of_a_stationary_catalog_is_small():
    cuts = [analysis.transient_cut(*synthetic_catalog(seed), t_end=1.0)["t_cut"] for seed in range(10)]
    assert np.median(cuts) <= 0.05, cuts
    assert max(cuts) <= 0.25, cuts  # MSER's rare spurious cut only drops data, it does not bias


def test_mser_truncation_basics():
    assert analysis.mser_truncation(np.r_[np.full(10, 5.0), np.zeros(30)] + 0.01 * np.arange(40) % 0.03) == 10
    assert analysis.mser_truncation(np.ones(20)) == 0
    # Never more than half of the series.
    assert analysis.mser_truncation(np.r_[np.full(30, 5.0), np.zeros(10)]) <= 20


def _info(duration=1.0):
    return analysis.RunInfo(D=1.0, L=1.0, H=0.1, v0=1.0, mu=1.0, c_s=1.0, sigma0=1.0, delta_th=0.01,
                            n_nodes=100, duration=duration)


def test_stationary_part_cuts_then_passes_the_ks_tests():
    t, u = synthetic_catalog(3, t_transient=0.3)
    rng = np.random.default_rng(4)
    cat = {"t_start": t, "u_mean": u, "T": u * rng.lognormal(0, 0.3, u.size), "L_s": np.full(u.size, 0.1),
           "M0": u * 0.1, "attrs": {}}
    whole = analysis.stationarity(cat, _info())
    assert min(whole[k]["pvalue"] for k in ("u", "T", "M0")) < 0.05  # the transient is visible
    part = analysis.stationary_part(cat, _info())
    assert 0.275 <= part["cut"]["t_cut"] <= 0.5
    assert part["stationary"], part["stationarity"]
    assert np.all(part["catalog"]["t_start"] >= part["cut"]["t_cut"])
    st = part["stationarity"]
    assert st["t_begin"] == part["cut"]["t_cut"] and st["n_first"] > 100 and st["n_last"] > 100


# ---------------------------------------------------------------------------
# Periodic travelling pulse on synthetic space-time fields
# ---------------------------------------------------------------------------

N, LEN, V0 = 256, 1.0, 1e-3
X = np.arange(N) * LEN / N
TIME = np.linspace(0.0, 1.0, 200)


def pulse_field(position, amplitude=50.0, width=0.03):
    d = (X[None, :] - np.asarray(position)[:, None] + LEN / 2) % LEN - LEN / 2
    return V0 * (0.01 + amplitude * np.exp(-d ** 2 / (2 * width ** 2)))


def noisy(v, seed, sigma=0.2):
    return v * np.random.default_rng(seed).lognormal(0.0, sigma, v.shape)


def random_bursts(seed, n_bursts=150, floor=0.01):
    rng = np.random.default_rng(seed)
    v = np.full((TIME.size, N), floor * V0)
    for _ in range(n_bursts):
        i0, dur = rng.integers(0, TIME.size), rng.integers(1, 6)
        d = (X - rng.uniform(0, LEN) + LEN / 2) % LEN - LEN / 2
        v[i0:i0 + dur] += V0 * 10 ** rng.uniform(0.5, 2) * np.exp(-d ** 2 / (2 * rng.uniform(0.01, 0.2) ** 2))
    return noisy(v, seed + 1)


def pulse(v):
    return analysis.periodic_pulse_from_spacetime(TIME, v, V0, LEN / N)


def test_pulse_criterion_recognises_travelling_pulses():
    steady = pulse(noisy(pulse_field(0.2 + 5.0 * TIME), 1))
    assert steady["flag"] and steady["determined"]
    assert steady["speed_median"] == pytest.approx(5.0, rel=0.03)  # sub-node shift: speed in L per unit time
    assert steady["travelled_periods"] == pytest.approx(2.5, rel=0.05)
    # Accelerating pulse (speed 3 -> 9): speed changes are allowed.
    accel = pulse(noisy(pulse_field(0.2 + 3.0 * TIME + 3.0 * TIME ** 2), 2))
    assert accel["flag"] and accel["speed_max"] > 1.3 * accel["speed_min"]
    # Slow pulse (< 2 nodes per snapshot): a longer lag measures it.
    slow = pulse(noisy(pulse_field(0.2 + 1.2 * TIME), 3))
    assert slow["flag"] and slow["lag"] > 1 and slow["speed_median"] == pytest.approx(1.2, rel=0.1)
    # Backwards travel is the same.
    assert pulse(noisy(pulse_field(0.7 - 4.0 * TIME), 4))["flag"]


def test_pulse_after_a_coarsening_transient_and_its_onset():
    v = random_bursts(5)
    late = TIME > 0.3
    v[late] = noisy(pulse_field(0.1 + 5.0 * TIME[late]), 6)
    r = pulse(v)
    assert r["flag"]
    assert abs(r["onset_time"] - 0.3) <= 0.03


def test_pulse_criterion_rejects_complex_and_uniform_states():
    bursts = pulse(random_bursts(7))
    assert bursts["determined"] and not bursts["flag"]
    # Bursts dense enough that something always slips fast: still no pulse (shape and direction).
    dense = random_bursts(8, n_bursts=2000, floor=5.0)
    r = pulse(dense)
    assert r["min_max_slip_rate_v0"] > analysis.PULSE_MIN_RATE and not r["flag"]
    assert r["moving_fraction"] < analysis.PULSE_MIN_MOVING_FRACTION
    # Uniform stick-slip of the k = 0 mode (whole interface at once, every 0.1).
    k0 = np.where((TIME * 10) % 1 < 0.1, 50.0, 0.01)
    r = pulse(noisy(V0 * k0[:, None] * np.ones((1, N)), 9, 0.05))
    assert not r["flag"] and r["median_width_fraction"] > 0.9
    # Uniform fast sliding, and a standing localised oscillation: no pulse either.
    assert not pulse(noisy(np.full((TIME.size, N), 20 * V0), 10, 0.05))["flag"]
    standing = pulse(noisy(pulse_field(np.full(TIME.size, 0.5)) * (1.5 + np.sin(30 * TIME))[:, None], 11))
    assert not standing["flag"] and standing["moving_fraction"] < 0.5
    # The catalog criterion alone would take regular k = 0 stick-slip for a pulse;
    # with snapshots the decision is the space-time one.
    flag, basis = analysis.periodic_pulse_decision({"flag": True}, {"flag": False}, r)
    assert basis == "spacetime" and flag is False
    flag, basis = analysis.periodic_pulse_decision({"flag": True}, {"flag": False}, None)
    assert basis == "events_or_timeseries" and flag is True


def test_pulse_criterion_needs_enough_snapshots():
    r = analysis.periodic_pulse_from_spacetime(TIME[:12], pulse_field(5.0 * TIME[:12]), V0, LEN / N)
    assert not r["determined"] and not r["flag"]


# ---------------------------------------------------------------------------
# Fig. 3a/b measurement on a synthetic nucleation
# ---------------------------------------------------------------------------

def test_nucleation_event_measures_two_pulses():
    # Bilateral rupture from x0 = 0.5 at speed c = 2, the centre stops at t = 0.1,
    # then two pulses of width 0.05 run on to the antipode.
    t = np.linspace(0, 0.3, 301)
    c, w, x0 = 2.0, 0.05, 0.5
    d = np.abs(X - x0)[None, :]
    front = c * t[:, None]
    inside = d <= front
    centre_stopped = t[:, None] > 0.1
    v = np.where(inside & ~(centre_stopped & (d < front - w)), 100 * V0, 0.01 * V0)
    ev = report.nucleation_event(t, X, v, V0, x0, LEN, c_d=3.0)
    assert ev["found"] and ev["end_reason"] == "traversal"
    assert ev["front_speed"] == pytest.approx(c, rel=0.03)
    assert ev["center_duration"] == pytest.approx(0.1, abs=2e-3)
    assert ev["n_pulses"] == 2
    assert ev["pulse_width"] == pytest.approx(w, abs=2 * LEN / N)
    # Arrest instead: everything stops at t = 0.12.
    v2 = np.where(inside & (t[:, None] <= 0.12), 100 * V0, 0.01 * V0)
    ev2 = report.nucleation_event(t, X, v2, V0, x0, LEN, c_d=3.0)
    assert ev2["end_reason"] == "arrest" and ev2["max_extent"] < 0.6 * LEN


# ---------------------------------------------------------------------------
# The report on tiny real runs
# ---------------------------------------------------------------------------

TINY = ["--set", "geometry.nodes=64", "--set", "output.snapshot_interval=2e-5", "--quiet"]


@pytest.fixture(scope="module")
def binary():
    exe = os.environ.get("SLIPSTRIP_BIN")
    if exe and os.access(exe, os.X_OK):
        return exe
    for cand in (shutil.which("slipstrip"), REPO / "build" / "slipstrip"):
        if cand and os.access(cand, os.X_OK):
            return str(cand)
    pytest.skip("slipstrip binary not found (set SLIPSTRIP_BIN)")


def _tiny_set(binary, d, extra=()):
    """One tiny run (N = 64, reference config, 3 L/c_s), with /events, copied to
    every name of report.RUNS (the report only needs files of the right kind)."""
    src = d / "source.h5"
    subprocess.run([binary, "run", str(REPO / "configs" / "reference.toml"), *TINY, *extra,
                    "--set", "time.duration_transits=3", "--out", str(src)], check=True, timeout=300)
    # A run this short may keep no event: `events` then still writes the
    # catalog (all the report needs) and exits 1 saying why.
    r = subprocess.run([binary, "events", str(src)], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0 or (r.returncode == 1 and "0 events kept" in r.stderr), r.stderr
    for name in report.RUNS:
        shutil.copy(src, d / f"{name}.h5")
    src.unlink()
    return d


@pytest.fixture(scope="module")
def tiny_rundir(binary, tmp_path_factory):
    """The paper-as-run set (configs as committed)."""
    return _tiny_set(binary, tmp_path_factory.mktemp("runs"))


@pytest.fixture(scope="module")
def tiny_printed(binary, tmp_path_factory):
    """The same with Table S1 as printed (mu = 9 GPa)."""
    return _tiny_set(binary, tmp_path_factory.mktemp("printed"), ("--set", "material.shear_modulus=9e9"))


def _report(rundir, tmp_path, *extra, env_bin=None, printed=None):
    out = tmp_path / "doc" / "reproduction.md"
    figs = tmp_path / "doc" / "figures"
    env = dict(os.environ, PYTHONPATH=str(REPO / "python"), OMP_NUM_THREADS="1")
    if env_bin:
        env["SLIPSTRIP_BIN"] = env_bin
    more = ["--printed", str(printed)] if printed is not None else []
    r = subprocess.run([sys.executable, "-m", "slipstrip", "report", str(rundir), *more, "--out", str(out),
                        "--figures", str(figs), "--bootstrap", "20", "--quiet", *extra],
                       capture_output=True, text=True, env=env, timeout=900)
    return r, out, figs


def _row(text, cid):
    """The table row of claim `cid` (rows start with the id in backticks), or of a run file."""
    start = f"| `{cid}` |" if not cid.startswith("RUNDIR") and not cid.startswith("PRINTED") else f"| {cid}"
    rows = [line for line in text.splitlines() if line.startswith(start)]
    assert rows, cid
    return rows[0]


def _cells(row):
    return [c.strip() for c in row.strip().strip("|").split(" | ")]


def test_missing_run_fails_loudly(tiny_rundir, tiny_printed, tmp_path, binary):
    d = tmp_path / "runs"
    shutil.copytree(tiny_rundir, d)
    (d / "fig3c_H02.h5").unlink()
    r, out, _ = _report(d, tmp_path, env_bin=binary, printed=tiny_printed)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "RUNDIR/fig3c_H02.h5 missing" in lines[0], r.stderr
    assert not out.exists()
    # Unreadable is as loud.
    (d / "fig3c_H02.h5").write_bytes(b"not an HDF5 file")
    r, out, _ = _report(d, tmp_path, env_bin=binary, printed=tiny_printed)
    assert r.returncode == 2 and "RUNDIR/fig3c_H02.h5 unreadable" in r.stderr and not out.exists()
    # No printed set: refused unless --allow-missing.
    r, out, _ = _report(tiny_rundir, tmp_path, env_bin=binary)
    assert r.returncode == 2 and "--printed" in r.stderr and not out.exists()
    # A run of the other reading in a directory is refused, naming the file and both readings.
    r, out, _ = _report(tiny_rundir, tmp_path, env_bin=binary, printed=tiny_rundir)
    assert r.returncode == 2 and "PRINTED/reference.h5 is paper-as-run (E = 9 GPa), not the as printed reading" \
        in r.stderr, r.stderr
    assert not out.exists()


# Every checkable claim of the paper, by id (python/slipstrip/claims.py).  Written out
# here so that a claim dropped from claims.py (or from the report's table) fails this
# test instead of disappearing from docs/reproduction.md.
CLAIM_IDS = [
    # Fig. 1
    "fig1b_space_slip", "fig1c_exp_u", "fig1d_exp_T", "fig1e_exp_M0", "fig1c_split_at_D", "fig1d_lognormal_T",
    "fig1e_lognormal_M0", "small_nonpropagating", "small_slip_fraction", "reference_complex",
    # Fig. 2
    "fig2_event1_bilateral", "fig2_event1_vmax", "fig2_event1_duration", "fig2_event1_crack",
    "fig2_event1_arrest_minima", "fig2_event1_aging", "fig2_event1_stress_peaks", "fig2_events23_crack",
    "fig2_event4_from_arrest", "fig2_event5_bilateral_stage", "fig2_event5_pulses",
    # Fig. 3a/b
    "fig3a_duration", "fig3b_center_stop", "fig3b_pulses", "fig3b_speed", "fig3b_width",
    # Figs. 3c/d, S7
    "fig3c_shift", "fig3d_shift", "fig3_collapse", "fig3_small", "s7_shift_H", "s7_shift_cs",
    # Figs. 4, S10-S12
    "fig4_complex", "fig4_exponents", "fig4_lognormal_T", "fig4_larger", "fig4_Lc_same",
    "s10_complex", "s10_exponents", "s10_lognormal_T", "s10_Lc_smaller", "s10_min_propagating",
    "s11_complex", "s11_exponents", "s11_lognormal_T", "s11_Lc_smaller",
    "s12_complex", "s12_exponents", "s12_lognormal_T", "s12_Lc_smaller", "s12_fss",
    # Fig. 5 and friction
    "fig5_pulse", "fig5_H02", "reference_no_pulse", "fss_slopes", "fig5_fss",
    # Lc(H), mesh, process zone
    "Lc_01", "Lc_over_H_01", "Lc_ratio_005", "Lc_ratio_01", "Lc_ratio_02", "Lc5_01", "Lc5_02", "Lc_over_dx",
    "pz_formula", "pz_resolved",
    # event identification and statistics procedure (Figs. S4-S9)
    "ns_and_events", "first_event_spans", "s5_event", "noise_transient", "stationary", "s9_power_law",
    "s9_crossover", "s9_lognormal", "s9_max_size", "clusters",
]
MEASUREMENT_IDS = ["fig3_peak_position", "fig3_peak_fit", "s7_peak_position", "lognormal_u", "k0_mode"]


def test_the_claim_list_is_complete():
    from slipstrip import claims
    assert [c.id for c in claims.CLAIMS] == CLAIM_IDS
    assert [c.id for c in claims.MEASUREMENTS] == MEASUREMENT_IDS
    for c in claims.CLAIMS:
        assert c.where and len(c.words) > 20, c.id  # a place and the paper's own words


# Slow tier for its cost (the whole report at both readings, 11 s of CPU, half
# of it drawing figures): it checks the report's assembly, not physics; the
# claims' criteria and numbers are checked in the fast tier by the tests above
# and by test_report_numbers.py.
@pytest.mark.slow
def test_report_has_a_row_for_every_claim_at_both_readings(tiny_rundir, tiny_printed, tmp_path, binary):
    r, out, figs = _report(tiny_rundir, tmp_path, env_bin=binary, printed=tiny_printed)
    assert r.returncode == 0, r.stderr
    text = out.read_text()
    for cid in CLAIM_IDS + MEASUREMENT_IDS:
        cells = _cells(_row(text, cid))
        assert len(cells) == 7, (cid, cells)
        # Both readings have a value and a verdict; no section failed silently.
        assert cells[3] and cells[5] and cells[4] and cells[6], (cid, cells)
        assert "no row computed" not in cells[3] + cells[5], (cid, cells)
        assert "not checkable (error)" not in cells[4] + cells[6], (cid, cells)
    # The headline counts add up to the number of claims, for each reading.
    for name in ("paper-as-run", "as printed"):
        head = next(line for line in text.splitlines() if line.startswith(f"| {name} |"))
        c = _cells(head)
        assert int(c[2]) + int(c[3]) + int(c[4]) == int(c[5]) == len(CLAIM_IDS), head
    assert "### Which reading the evidence supports" in text
    conclusion = text.split("### Which reading the evidence supports")[1].split("## How to read")[0]
    assert "**The evidence supports" in conclusion
    # Lc at each reading from the bindings: 0.382 m (E = 9 GPa) and 0.658 m (mu = 9 GPa), docs/stability.md.
    lc = _cells(_row(text, "Lc_01"))
    assert lc[3].startswith("0.3821 m") and lc[5].startswith("0.6581 m"), lc
    assert lc[4].startswith("agrees") and lc[6].startswith("differs"), lc
    # The process-zone formula: 0.0337 m at mu = 3.38 GPa, 0.0896 m at mu = 9 GPa (paper: 0.095 m).
    pz = _cells(_row(text, "pz_formula"))
    assert "0.0337 m" in pz[3] and "0.0896 m" in pz[5] and pz[6].startswith("agrees") and pz[4].startswith("differs")
    assert (figs / "asrun").is_dir() and (figs / "printed").is_dir()


# Slow tier for its cost (the whole report built twice, minutes of CPU).
@pytest.mark.slow
def test_report_rows_come_from_the_run_files(tiny_rundir, tiny_printed, tmp_path, binary):
    d = tmp_path / "runs"
    shutil.copytree(tiny_rundir, d)
    (d / "fig3c_H02.h5").unlink()
    r, out, figs = _report(d, tmp_path, "--allow-missing", env_bin=binary, printed=tiny_printed)
    assert r.returncode == 0, r.stderr
    text = out.read_text()
    # The missing run: "not run", no number, in its rows (one reading only) and in the run list.
    row = _cells(_row(text, "fig3c_shift"))
    assert "not run (RUNDIR/fig3c_H02.h5 missing)" in row[3] and row[4].startswith("not checkable")
    assert "T_peak" not in row[3] and "not run" not in row[5]
    assert "Incomplete (paper-as-run)" in text
    assert "fig3c_H02: not run" in _row(text, "fig3_peak_position")
    assert "Fig. 1c caption" in text and "paper-as-run (E = 9 GPa)" in text and "Table S1 as printed (mu = 9 GPa)" in text
    assert str(tmp_path) not in text and str(REPO) not in text  # no machine paths in the doc
    assert "| RUNDIR/reference.h5 |" in text and "| PRINTED/reference.h5 |" in text and "nproc" in text
    # Every figure the document shows exists and has something drawn in it.
    import re
    shown = re.findall(r"^!\[[^\]]*\]\(([^)]+)\)$", text, flags=re.M)
    assert any(p.endswith("fig5_spacetime.png") for p in shown), shown
    for rel in shown:
        assert_figure(out.parent / rel)

    # Change one file: the run list reflects it (wall time from its own attributes).
    with h5py.File(d / "fig3a.h5", "r+") as f:
        f.attrs["start_time"] = "2026-01-01T00:00:00Z"
        f.attrs["end_time"] = "2026-01-01T01:02:03Z"
    # ... and a rescaled catalog changes a Fig. 1 number (u_mean and M0 doubled).
    with h5py.File(d / "reference.h5", "r+") as f:
        for k in ("u_mean", "M0"):
            data = f["events"][k][:]
            f["events"][k][...] = 2 * data
    # The earlier report is an existing output: kept unless --overwrite.
    refused, _, _ = _report(d, tmp_path, "--allow-missing", env_bin=binary, printed=tiny_printed)
    assert refused.returncode == 2 and "already exists" in refused.stderr and out.read_text() == text
    r2, out2, _ = _report(d, tmp_path, "--allow-missing", "--overwrite", env_bin=binary, printed=tiny_printed)
    assert r2.returncode == 0, r2.stderr
    text2 = out2.read_text()
    assert "1:02:03 (3723 s)" in _row(text2, "RUNDIR/fig3a.h5")
    assert "1:02:03" not in _row(text, "RUNDIR/fig3a.h5")
    assert _cells(_row(text, "lognormal_u"))[3] != _cells(_row(text2, "lognormal_u"))[3]
    assert _cells(_row(text, "lognormal_u"))[5] == _cells(_row(text2, "lognormal_u"))[5]  # the other reading's file
    # The whole report is regenerated: a stale figure is removed.
    stale = figs / "asrun" / "stale.png"
    stale.write_bytes(b"x")
    r3, _, _ = _report(d, tmp_path, "--allow-missing", "--overwrite", env_bin=binary, printed=tiny_printed)
    assert r3.returncode == 0 and not stale.exists()


def test_incomplete_run_is_refused_unless_allowed(tiny_rundir, tiny_printed, tmp_path, binary):
    d = tmp_path / "runs"
    shutil.copytree(tiny_rundir, d)
    with h5py.File(d / "fig5.h5", "r+") as f:
        f.attrs["status"] = "running"
    r, out, _ = _report(d, tmp_path, env_bin=binary, printed=tiny_printed)
    assert r.returncode == 2 and "RUNDIR/fig5.h5 incomplete" in r.stderr and not out.exists()


def test_xmin_sweep_verdict_uses_the_range_widened_by_the_errors():
    sweep = [{"xmin_factor": 0.5, "xmin": 0.01, "exponent": 2.30, "stderr": 0.02, "n": 900},
             {"xmin_factor": 1.0, "xmin": 0.02, "exponent": 2.40, "stderr": 0.03, "n": 500},
             {"xmin_factor": 2.0, "xmin": 0.04, "exponent": 2.60, "stderr": 0.05, "n": 200}]
    assert report.verdict_xmin_sweep(sweep, 2.45).startswith("agrees")
    assert report.verdict_xmin_sweep(sweep, 2.27).startswith("agrees")   # 2.30 - 2 * 0.02 = 2.26
    assert report.verdict_xmin_sweep(sweep, 2.25).startswith("differs")
    assert report.verdict_xmin_sweep(sweep, 2.71).startswith("differs")  # 2.60 + 2 * 0.05 = 2.70
    assert report.verdict_xmin_sweep([], 2.45) == "no value"
    cell = report.xmin_sweep_cell(sweep)
    assert "x_min = 0.5 x_opt: 2.3 ± 0.02 (n = 900)" in cell and "range 2.3-2.6" in cell


def test_verdicts_print_on_the_side_of_their_rule():
    # 2.04 sigma differs under the 2 sigma rule and must not print as "2.0 σ"; exactly 2 sigma agrees.
    v = report.verdict_sigma(2.04, 1.0, 0.0)
    assert v.startswith("differs") and "(2.04 σ)" in v, v
    v = report.verdict_sigma(2.0, 1.0, 0.0)
    assert v.startswith("agrees") and "(2.0 σ)" in v, v
    assert report.verdict_sigma(1.0, 0.5, 0.0).startswith("agrees")   # 2 sigma exactly
    assert report.verdict_relative(1.104, 1.0) == "differs by +10.4%"
    assert report.verdict_relative(1.1, 1.0) == "agrees (+10%)"
    assert report.verdict_relative(0.91, 1.0) == "agrees (-9%)"
    assert report.verdict_factor(2.04) == "differs (ratio 2.04)"
    assert report.verdict_factor(2.0).startswith("agrees") and report.verdict_factor(0.5).startswith("agrees")
    assert report.verdict_factor(0.495).startswith("differs")
    assert report.verdict_order(3.1).startswith("agrees") and report.verdict_order(3.2).startswith("differs")
    assert report.verdict_order(1 / 3.1).startswith("agrees")
    for v, cls in (("agrees (1.0 σ)", "agree"), ("differs by +3%", "differ"), ("no value", "not checkable"),
                   ("not checkable (run missing)", "not checkable"), ("—", "not checkable")):
        assert report.verdict_class(v) == cls
    assert report.verdict_majority(3, 5, "x").startswith("agrees")
    assert report.verdict_majority(2, 4, "x").startswith("differs")  # half is not "more than half"
    assert report.verdict_majority(0, 0, "x").startswith("no value")
    # 8 of 20 against a chance rate of 10 %: z = (0.4 - 0.1) / sqrt(0.09 / 20) = 4.5; 3 of 20: z = 0.75.
    assert report.verdict_beats_chance(8, 20, 0.1, "x").startswith("agrees")
    assert report.verdict_beats_chance(3, 20, 0.1, "x").startswith("differs")


def test_reading_conclusion_counts_one_computation_once():
    """Seven Lc claims favouring one reading are one piece of evidence; two run
    outcomes favouring the other outweigh them."""
    from types import SimpleNamespace
    from slipstrip import claims

    def fake(verdicts):
        rows = {c.id: report.Row(c.id, "", verdicts.get(c.id, "no value"), "") for c in claims.CLAIMS}
        return SimpleNamespace(rows=rows, missing={})
    lc = [c.id for c in claims.CLAIMS if c.group == "Lc"]
    asrun = {i: "agrees" for i in lc}
    printed = {i: "differs" for i in lc}
    asrun.update({"fig3b_pulses": "differs", "fig5_H02": "differs"})
    printed.update({"fig3b_pulses": "agrees", "fig5_H02": "agrees"})
    text = "\n".join(report.reading_conclusion({"asrun": fake(asrun), "printed": fake(printed)}))
    assert f"Claims whose verdict changes with the reading: {len(lc) + 2}." in text
    assert "favour paper-as-run 1 times (Lc (8 claims))" in text and "as printed 2 times" in text
    assert "**The evidence supports Table S1 as printed**" in text
    # A tie supports neither.
    printed["fig5_H02"] = asrun["fig5_H02"] = "agrees"
    text = "\n".join(report.reading_conclusion({"asrun": fake(asrun), "printed": fake(printed)}))
    assert "**The evidence supports neither reading**: 1 independent pieces each way." in text


def test_guide_to_the_eye_verdict_adds_the_ks_optimal_distance():
    sweep = [{"xmin_factor": 1.0, "xmin": 0.02, "exponent": 2.40, "stderr": 0.03, "n": 500},
             {"xmin_factor": 2.0, "xmin": 0.04, "exponent": 2.60, "stderr": 0.05, "n": 200}]
    v = report.verdict_guide(2.40, 0.03, sweep, 2.45)
    assert v.startswith("agrees within the fit-range systematic") and "KS-optimal fit alone: 1.7 σ" in v
    assert report.verdict_guide(2.40, 0.03, sweep, 2.9).startswith("differs")
    assert report.verdict_guide(2.40, 0.03, [], 2.45) == "no value"


def test_friction_steady_state_slope_is_the_derivative_of_f_ss():
    # d f_ss / d ln v from the closed form against a centred difference of f_ss(v)
    # (Eqs. S1-S2); step 1e-4 in ln v: truncation error ~1e-9, far below the 1e-6 asked.
    fr = {"f0": 0.28, "a": 0.005, "b": 0.075, "characteristic_slip": 5e-7, "v_star": 1e-7, "phi_star": 3.3e-4}
    for v0 in (2e-3, 1e-6, 3e-7):
        h = 1e-4
        fd = (report.friction_steady_state(fr, v0 * math.exp(h))["f_ss"]
              - report.friction_steady_state(fr, v0 * math.exp(-h))["f_ss"]) / (2 * h)
        assert report.friction_steady_state(fr, v0)["slope"] == pytest.approx(fd, abs=1e-6)
    # f_ss(v0) by hand for Table S1: 0.28 (1 + 0.075 ln(2.5e-4 / 3.3e-4)) + 0.005 ln(1 + 2e4).
    by_hand = 0.28 * (1 + 0.075 * math.log(5e-7 / math.hypot(2e-3, 1e-7) / 3.3e-4)) + 0.005 * math.log1p(2e4)
    assert report.friction_steady_state(fr, 2e-3)["f_ss"] == pytest.approx(by_hand, rel=1e-12)


def test_peak_of_pT_of_a_lognormal_is_its_density_mode():
    # p(T) (per unit T) of a log-normal peaks at exp(mu - sigma^2); with 20 000
    # samples the kernel estimate's mode is within ~5 % of it (bandwidth bias
    # ~ sigma^2 h^2 / 2 plus sampling noise, both far below that here).
    rng = np.random.default_rng(3)
    mu, sigma = math.log(2e-4), 0.4
    T = rng.lognormal(mu, sigma, 20000)
    assert report.peak_of_pT(T) == pytest.approx(math.exp(mu - sigma**2), rel=0.05)
    peaks = report.local_peaks_of_pT(T)
    assert len(peaks) == 1 and peaks[0][1] == 1.0


def test_local_peaks_of_pT_show_both_modes_of_a_bimodal_sample():
    # Short bursts (0.3 tau) plus events of ~1.5 tau, as in the H = 0.2 m run:
    # both modes must be reported, the higher one first, each near its
    # component's density mode (components a factor 5 apart, so they are resolved).
    rng = np.random.default_rng(4)
    tau = 2.4e-4
    short = rng.lognormal(math.log(0.3 * tau), 0.25, 3000)
    long_ = rng.lognormal(math.log(1.5 * tau), 0.25, 3000)
    peaks = report.local_peaks_of_pT(np.concatenate([short, long_]))
    assert len(peaks) == 2
    assert peaks[0][1] == 1.0 and 0.1 <= peaks[1][1] < 1.0
    found = sorted(p[0] / tau for p in peaks)
    assert found[0] == pytest.approx(0.3 * math.exp(-0.25**2), rel=0.1)
    assert found[1] == pytest.approx(1.5 * math.exp(-0.25**2), rel=0.1)


def test_pulse_episodes_reports_what_the_report_functions_compute(tiny_rundir, tmp_path, monkeypatch):
    """`python3 -m slipstrip pulse-episodes` (the Fig. 5 resolution check,
    docs/fig5_resolution.md) is the report's criterion applied to one file: the
    same late-half flag and the same window flags, plus each window's parts,
    JSON and plot written."""
    # The tiny run covers 3 L/c_s: windows of 1 L/c_s give three of them.
    path = str(tiny_rundir / "fig5.h5")
    out_json, out_png = tmp_path / "p.json", tmp_path / "p.png"
    assert episodes_command.main([path, "--json", str(out_json), "--plot", str(out_png), "--window-transits", "1"]) == 0
    summary = json.loads(out_json.read_text())
    info = analysis.read_run_info(path)
    t, _, v = analysis.read_spacetime(path, max_rows=6000)
    dx, transit = info.L / v.shape[1], info.L / info.c_s
    episodes = analysis.pulse_episodes(t, v, info.v0, dx, window=transit)
    assert len(summary["windows"]) == len(episodes["windows"]) == 3
    assert [w["pulse"] for w in summary["windows"]] == episodes["flags"]
    for w, (t0, t1) in zip(summary["windows"], episodes["windows"]):
        rows = (t >= t0) & (t < t1)
        parts = analysis.periodic_pulse_from_spacetime(t[rows], v[rows], info.v0, dx, late_fraction=1.0)
        assert w["median_width_fraction"] == pytest.approx(parts["median_width_fraction"])
    late = analysis.periodic_pulse_from_spacetime(t, v, info.v0, dx)
    assert summary["late_half"]["flag"] == late["flag"]
    assert_figure(out_png)
    # The run's initial condition comes from its stored config, and the table
    # mode turns the JSON into one Markdown row per run with those numbers.
    config = read_config(path)
    assert summary["initial"]["noise_seed"] == config["initial"]["noise_seed"]
    assert summary["initial"]["noise_modes"] == config["initial"]["noise_modes"]
    table = episodes_command.markdown_table([summary, summary])
    lines = table.strip().splitlines()
    assert len(lines) == 5 and lines[2] == lines[3]
    assert f"| {summary['pulse_windows']} of 3 |" in lines[2]
    assert f"seed {config['initial']['noise_seed']}" in lines[2]
    later = summary["windows"][1:]
    one_way = sum(w["moving_fraction"] >= analysis.PULSE_MIN_MOVING_FRACTION for w in later)
    pulses = sum(w["pulse"] for w in later)
    assert f"| {pulses} / {one_way} / 2," in lines[2]
    assert lines[4].startswith("| **all 2** |")
    assert f"| {2 * summary['pulse_windows']} of 6 | {2 * pulses} / {2 * one_way} / 4 |" in lines[4]
    assert len(episodes_command.markdown_table([summary]).strip().splitlines()) == 3  # no total row for one run
    with h5py.File(path, "r") as f:
        ts_t, ts_v = f["timeseries/time"][:], f["timeseries/max_slip_rate"][:] / info.v0
    late_rows = ts_t >= ts_t[0] + 0.5 * (ts_t[-1] - ts_t[0])
    assert summary["late_half_max_slip_rate_v0"]["max"] == pytest.approx(ts_v[late_rows].max())
    assert summary["late_half_max_slip_rate_v0"]["median"] == pytest.approx(np.median(ts_v[late_rows]))
    assert f"{np.median(ts_v[late_rows]):.2f} / " in lines[2]
    capsys_out = io.StringIO()
    monkeypatch.setattr(sys, "stdout", capsys_out)
    assert episodes_command.main(["--table", str(out_json)]) == 0
    assert capsys_out.getvalue().strip().splitlines()[2] == lines[2]


def _module_cli(*args):
    env = dict(os.environ, PYTHONPATH=str(REPO / "python"))
    return subprocess.run([sys.executable, "-m", "slipstrip", *map(str, args)], capture_output=True, text=True,
                          env=env, timeout=300)


# Slow tier for its cost (eight command processes, 4.4 s of CPU): it checks the
# commands' wiring; what they compute is checked in the fast tier by
# test_pulse_episodes_reports_what_the_report_functions_compute and the
# trajectory-divergence tests below.
@pytest.mark.slow
def test_pulse_episodes_and_trajectory_divergence_are_subcommands(tiny_rundir, tmp_path):
    """Both are `python3 -m slipstrip` subcommands with their own help, and
    follow the output-path rule: an existing --json is refused (exit 2, one
    line, the file untouched) unless --overwrite."""
    for command, option in (("pulse-episodes", "--window-transits"), ("trajectory-divergence", "pairs of run files")):
        r = _module_cli(command, "--help")
        assert r.returncode == 0, r.stderr
        assert r.stdout.startswith(f"usage: python3 -m slipstrip {command}") and option in r.stdout
        assert command in _module_cli("--help").stdout
    path = tiny_rundir / "fig5.h5"
    old = tmp_path / "old.json"
    for args in (("pulse-episodes", path), ("trajectory-divergence", path, path)):
        old.write_text("an earlier result\n")
        r = _module_cli(*args, "--json", old)
        assert r.returncode == 2 and "already exists" in r.stderr and len(r.stderr.strip().splitlines()) == 1, r
        assert old.read_text() == "an earlier result\n"
        r = _module_cli(*args, "--json", old, "--overwrite")
        assert r.returncode == 0, r.stderr
        assert json.loads(old.read_text())
    r = _module_cli("trajectory-divergence", path)
    assert r.returncode == 2 and "pairs" in r.stderr


def test_trajectory_divergence_finds_when_two_records_part():
    """`python3 -m slipstrip trajectory-divergence` (docs/fig5_resolution.md): a record
    compared with itself on a twice finer mesh (every other node the same) never
    departs; a copy whose slip rates double after t = 0.6 departs exactly there,
    at the 0.3 threshold (log10 2 = 0.301) but not before; the snapshot times of
    the finer record are shifted by 1e-9 of the spacing and still match."""
    rng = np.random.default_rng(5)
    t = np.linspace(0.0, 1.0, 101)
    coarse = 10.0 ** rng.uniform(-3, 1, size=(t.size, 16))
    fine = np.repeat(coarse, 2, axis=1)  # node 2i of the fine record = node i of the coarse one
    fine[:, 1::2] = 123.0                 # the in-between nodes are never compared
    times, rms = divergence.log_rate_divergence(t, coarse, t + 1e-11, fine, v0=1.0)
    assert times.size == t.size and np.all(rms == 0.0)
    assert divergence.first_exceedance(times, rms, 0.01) is None
    later = fine.copy()
    later[t >= 0.6] *= 2.0
    times, rms = divergence.log_rate_divergence(t, coarse, t, later, v0=1.0)
    assert divergence.first_exceedance(times, rms, 0.3) == pytest.approx(0.6)
    assert np.all(rms[t < 0.6] == 0.0)
    with pytest.raises(ValueError, match="multiple"):
        divergence.log_rate_divergence(t, coarse, t, coarse[:, :12], v0=1.0)


def test_trajectory_divergence_of_a_run_with_itself(tiny_rundir, tmp_path):
    """On a real run file: the same run twice gives zero at every snapshot and
    writes the JSON and the plot."""
    path = str(tiny_rundir / "fig5.h5")
    out_json, out_png = tmp_path / "d.json", tmp_path / "d.png"
    assert divergence.main([path, path, "--json", str(out_json), "--plot", str(out_png)]) == 0
    (summary,) = json.loads(out_json.read_text())
    assert summary["common_snapshots"] == h5py.File(path, "r")["snapshots/time"].shape[0]
    assert max(summary["rms_log10_ratio"]) == 0.0
    assert all(v is None for v in summary["first_exceedance_transits"].values())
    assert all(v == 0.0 for v in summary["rms_at_transits"].values())
    assert_figure(out_png)


def test_fig5_volume_solver_sentence_comes_from_the_committed_summary(tmp_path):
    summary = {"run": "vol.h5", "duration_transits": 251.87, "pulse_windows": 2,
               "windows": [{"pulse": i in (3, 4)} for i in range(12)]}
    path = tmp_path / "vol.json"
    path.write_text(json.dumps(summary))
    text = report.fig5_volume_solver_text(path)
    assert "pulse in 2 of 12 windows over 252 L/c_s" in text
    # The committed summary is the one docs/fig5_resolution.md tabulates.
    committed = json.loads(report.FIG5_VOLUME_SOLVER_JSON.read_text())
    assert f"of {len(committed['windows'])} windows" in report.fig5_volume_solver_text()
    assert report.fig5_volume_solver_text(tmp_path / "absent.json") == ""


def test_trajectory_divergence_reports_a_pair_shorter_than_the_first_sample_time():
    # Was: "rms at t =  L/c_s: " with nothing after it for a pair of 4 L/c_s
    # (the sample times start at 10 L/c_s).
    short = {"rms_at_transits": {}, "time_transits": [0.0, 2.0, 4.03], "rms_log10_ratio": [1e-4, 4e-7, 7.2e-7]}
    assert divergence._rms_samples(short) == "; rms at the last common snapshot, t = 4.03 L/c_s: 7.2e-07"
    long = {"rms_at_transits": {"10": 5.4e-3, "20": 2.7e-2}, "time_transits": [0.0, 25.0], "rms_log10_ratio": [0, 0]}
    assert divergence._rms_samples(long) == "; rms at t = 10, 20 L/c_s: 5.4e-03, 2.7e-02"


def test_pulse_episodes_prints_the_longest_stretch_in_whole_transits():
    # Was: "longest stretch [60.00000000000001, 80.0]" (the window bounds divided by L/c_s).
    assert episodes_command._stretch_text({"longest_stretch_transits": [60.00000000000001, 80.0]}) == "60-80"
    assert episodes_command._stretch_text({"longest_stretch_transits": None}) == "none"
