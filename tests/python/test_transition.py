"""The order parameter of docs/transition.md on synthetic records whose state
is known by construction: a travelling pulse, random bursts of all sizes
(complexity), uniform stick-slip of the k = 0 mode, steady sliding, and a
coarsening record (complex first, a pulse later)."""
import math

import numpy as np
import pytest
from figure_checks import assert_figure

from slipstrip import transition

V0, L, N = 2e-3, 4.0, 256
DX = L / N
X = np.arange(N) * DX


def _catalog(t_start, m0, spanning_fraction, rng):
    n = len(t_start)
    spanning = rng.random(n) < spanning_fraction
    L_s = np.where(spanning, L, rng.uniform(0.05, 0.5, n) * L)
    u = m0 / L_s
    return {"t_start": np.asarray(t_start), "M0": np.asarray(m0), "u_mean": u, "L_s": L_s,
            "T": np.full(n, 1e-4)}


def pulse(t, speed=1500.0, width=0.05, amplitude=50.0, seed=0):
    rng = np.random.default_rng(seed)
    d = np.mod(X[None, :] - speed * t[:, None], L) - L / 2
    v = V0 * (0.05 + amplitude * np.exp(-0.5 * (d / width) ** 2)) * (1 + 0.02 * rng.standard_normal((t.size, N)))
    return v


def bursts(t, seed=1):
    rng = np.random.default_rng(seed)
    v = V0 * 0.05 * np.ones((t.size, N))
    for _ in range(3 * t.size):
        i = rng.integers(t.size)
        centre, width = rng.uniform(0, L), 10 ** rng.uniform(-2.5, -0.7)
        d = np.mod(X - centre + L / 2, L) - L / 2
        v[i] += V0 * 10 ** rng.uniform(0.7, 2.5) * np.exp(-0.5 * (d / width) ** 2)
    return v


def record(t, v, catalog):
    vmax = v.max(axis=1)
    return transition.WindowRecord(V0, L, DX, t, v, t, vmax, catalog)


def test_travelling_pulse_is_a_periodic_pulse():
    rng = np.random.default_rng(0)
    t = np.linspace(0, 0.02, 600)
    starts = np.arange(0, 0.02, L / 1500.0)
    rec = record(t, pulse(t), _catalog(starts, np.full(starts.size, 1e-3) * (1 + 0.05 * rng.random(starts.size)), 1.0, rng))
    out = transition.classify_record(rec)
    assert out["state"] == "periodic_pulse" and out["converged"]
    assert out["agreement"] == 1.0


def test_random_bursts_of_all_sizes_are_complex():
    rng = np.random.default_rng(2)
    t = np.linspace(0, 0.02, 600)
    starts = np.sort(rng.uniform(0, 0.02, 300))
    m0 = 10 ** rng.uniform(-6, -2, starts.size)
    out = transition.classify_record(record(t, bursts(t), _catalog(starts, m0, 0.05, rng)))
    assert out["state"] == "complex" and out["converged"]
    assert out["agreement"] == 1.0


def test_uniform_stick_slip_is_recognised():
    rng = np.random.default_rng(3)
    t = np.linspace(0, 0.02, 600)
    phase = np.mod(t / 2e-3, 1.0)
    rate = V0 * (0.05 + 80 * np.exp(-0.5 * ((phase - 0.5) / 0.03) ** 2))
    v = rate[:, None] * (1 + 0.03 * rng.standard_normal((t.size, N)))
    starts = np.arange(0.001, 0.02, 2e-3)
    out = transition.classify_record(record(t, v, _catalog(starts, np.full(starts.size, 1e-3), 1.0, rng)))
    assert out["state"] == "uniform_stick_slip" and out["converged"]
    assert out["observables"]["spatial_cv_slipping"] < transition.UNIFORM_MAX_CV


def spanning_ruptures(t, rng, speed=1500.0, width=0.3 * L):
    """Bilateral ruptures from random sites that sweep the whole ring (slipping
    in a band of `width` behind each front), irregular recurrence, stuck between."""
    v = np.full((t.size, N), 0.01 * V0)
    starts, t_k = [], 0.0005
    while t_k < t[-1]:
        starts.append(t_k)
        x_k = rng.uniform(0, L)
        d = np.abs(np.mod(X - x_k + L / 2, L) - L / 2)
        for i in np.nonzero((t >= t_k) & (t <= t_k + (L / 2 + width) / speed))[0]:
            r = speed * (t[i] - t_k)
            v[i, (d < r) & (d > r - width)] = 50 * V0
        t_k += 2e-3 * rng.uniform(0.7, 1.3)
    return v, np.array(starts)


def test_system_spanning_ruptures_are_coarsened_not_complex():
    """The state found at L = 1 m for H >= 0.2 m (docs/transition.md): every
    rupture spans the system, from a new site each time; not one steady pulse
    (fronts go both ways), not uniform (fronts sweep across)."""
    rng = np.random.default_rng(6)
    t = np.linspace(0, 0.045, 2700)  # ~7 ruptures per third: enough for the catalog to vote
    v, starts = spanning_ruptures(t, rng)
    out = transition.classify_record(record(t, v, _catalog(starts, 10 ** rng.normal(-3, 0.05, starts.size), 1.0, rng)))
    assert out["state"] == "spanning_ruptures" and out["converged"]
    assert out["state"] in transition.COARSENED_STATES
    assert out["observables"]["spatial_cv_slipping"] > transition.UNIFORM_MAX_CV
    assert not out["observables"]["pulse"]["flag"]


def test_steady_sliding():
    rng = np.random.default_rng(4)
    t = np.linspace(0, 0.02, 300)
    v = V0 * (1 + 0.01 * rng.standard_normal((t.size, N)))
    out = transition.classify_record(record(t, v, {}))
    assert out["state"] == "steady" and out["converged"]


def test_locked_interface_is_arrested_not_steady():
    """A half-space interface that locks (v = 0 exactly, as the solver's sticking
    allows) is not steady sliding at v0."""
    t = np.linspace(0, 0.02, 300)
    v = np.zeros((t.size, N))
    v[:5] = V0  # slides at first, then locks
    out = transition.classify_record(record(t, v, {}))
    assert out["state"] == "arrested" and out["converged"]
    assert transition.classify_record(record(t, V0 * np.ones((t.size, N)), {}))["state"] == "steady"


def test_coarsening_record_ends_as_a_pulse_and_is_converged_only_when_the_last_thirds_agree():
    rng = np.random.default_rng(5)
    t = np.linspace(0, 0.03, 900)
    v = np.where((t < 0.01)[:, None], bursts(t, seed=6), pulse(t, seed=7))
    early = np.sort(rng.uniform(0, 0.01, 150))
    late = np.arange(0.01, 0.03, L / 1500.0)
    cat = _catalog(np.concatenate([early, late]),
                   np.concatenate([10 ** rng.uniform(-6, -2, early.size), np.full(late.size, 1e-3)]),
                   0.0, rng)
    cat["L_s"][early.size:] = L
    cat["u_mean"][early.size:] = 1e-3 / L
    out = transition.classify_record(record(t, v, cat))
    assert out["states_by_third"][0] == "complex"
    assert out["states_by_third"][1:] == ["periodic_pulse", "periodic_pulse"]
    assert out["converged"] and out["state"] == "periodic_pulse"
    # Cut the record where the pulse has just formed: the last two thirds disagree.
    keep = t < 0.016
    cat_cut = {k: v_[np.asarray(cat["t_start"]) < 0.016] for k, v_ in cat.items()}
    out = transition.classify_record(record(t[keep], v[keep], cat_cut))
    assert not out["converged"]


def test_patch_count_on_a_ring():
    row = np.zeros(20)
    row[[0, 1, 19]] = 1.0  # one patch across the periodic boundary
    row[[5, 6]] = 1.0
    row[[10]] = 1.0
    assert transition.patch_count(row, 0.5) == 3
    assert transition.patch_count(np.ones(5), 0.5) == 1
    assert transition.patch_count(np.zeros(5), 0.5) == 0


def test_autocorrelation_peak_periodic_vs_noise():
    t = np.arange(2000)
    assert transition.autocorrelation_peak(np.sin(2 * np.pi * t / 50)) > 0.9
    assert transition.autocorrelation_peak(np.random.default_rng(8).standard_normal(2000)) < 0.2


def test_pipeline_end_to_end_on_tiny_runs(cli, repo, tmp_path, capsys):
    """CI's tiny version of the map: two very short runs from the transition
    scan's base (a thin strip and a half-space), events, then the classifier
    writes its CSV and the map."""
    import csv
    import subprocess
    files = []
    for height in ("0.05", "inf"):
        out = tmp_path / f"H{height}.h5"
        cmd = [str(cli), "run", str(repo / "configs/reference.toml"), "--quiet", "--out", str(out),
               "--set", "geometry.nodes=64", "--set", "geometry.length=0.8", "--set", f"geometry.height={height}",
               "--set", "time.duration_transits=3", "--set", "output.snapshot_interval=2e-5",
               "--set", "initial.noise_amplitude=1e-2"]
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
        assert r.returncode == 0, r.stderr
        r = subprocess.run([str(cli), "events", str(out)], capture_output=True, text=True, timeout=60)
        assert r.returncode == 0, r.stderr
        files.append(out)
    # A scan directory's summary table is an HDF5 file too, but not a run: not listed, not classified.
    import h5py
    with h5py.File(tmp_path / "summary.h5", "w") as f:
        f.create_group("summary")
    csv_path, png, table = tmp_path / "map.csv", tmp_path / "map.png", tmp_path / "map.md"
    capsys.readouterr()
    assert transition.main([str(tmp_path), "--csv", str(csv_path), "--plot", str(png), "--table", str(table)]) == 0
    assert "summary.h5" not in capsys.readouterr().out
    rows = list(csv.DictReader(csv_path.open()))
    # The Markdown grid: one table for the one L, a column per height, a cell per run.
    text = table.read_text()
    assert "**L = 0.8 m** (N = 64)" in text and "| H = 0.05 m | ∞ |" in text
    grid = [line for line in text.splitlines() if line.startswith("| 0.")]
    assert len(grid) == 1 and grid[0].count("|") == 4
    # The CSV names each run as parent-dir/name, so a committed map carries no machine's absolute path.
    assert {row["file"] for row in rows} == {f"{f.parent.name}/{f.name}" for f in files}
    for row in rows:
        assert row["state"] in transition.STATES
        # Lc(H) from the run's own config (linear stability), Lc(inf) for the half-space itself.
        lc, lc_inf = float(row["critical_length"]), float(row["critical_length_halfspace"])
        assert 0 < lc <= lc_inf * (1 + 1e-9)
        if row["height"] == "inf":
            assert lc == lc_inf
        assert row["status"] == "completed"
    assert sorted(float(row["height"]) for row in rows) == [0.05, math.inf]
    assert_figure(png, page_width=True)

    # --previous: the map read back from its CSV alone gives the same CSV and table
    # (types survive the round trip), and a run classified now replaces its earlier row.
    again_csv, again_table = tmp_path / "again.csv", tmp_path / "again.md"
    assert transition.main(["--previous", str(csv_path), "--csv", str(again_csv), "--table", str(again_table)]) == 0
    assert again_csv.read_text() == csv_path.read_text()
    assert again_table.read_text() == text
    stale = tmp_path / "stale.csv"
    stale.write_text(csv_path.read_text().replace(",completed", ",stale-status"))
    mixed_csv = tmp_path / "mixed.csv"
    assert transition.main([str(files[0]), "--previous", str(stale), "--csv", str(mixed_csv)]) == 0
    mixed = {row["file"]: row["status"] for row in csv.DictReader(mixed_csv.open())}
    assert len(mixed) == 2
    assert mixed[f"{files[0].parent.name}/{files[0].name}"] == "completed"      # classified now
    assert mixed[f"{files[1].parent.name}/{files[1].name}"] == "stale-status"   # kept from the CSV
    with pytest.raises(SystemExit):
        transition.main([])                                                      # nothing to map


def test_run_without_events_is_detected_or_refused(cli, repo, tmp_path):
    """A run file without /events: the events are detected from /slip_sampling
    (the same classification as after `slipstrip events`, and the run file is
    left unchanged); without /slip_sampling (delta_th = 0) the classifier refuses
    with a message instead of voting with NaN observables."""
    import subprocess
    from slipstrip import runfile
    base = [str(cli), "run", str(repo / "configs/reference.toml"), "--quiet", "--set", "geometry.nodes=64",
            "--set", "geometry.length=0.8", "--set", "geometry.height=0.05", "--set", "time.duration_transits=3",
            "--set", "output.snapshot_interval=2e-5", "--set", "initial.noise_amplitude=1e-2"]
    sampled, unsampled = tmp_path / "sampled.h5", tmp_path / "unsampled.h5"
    for out, extra in ((sampled, []), (unsampled, ["--set", "output.delta_th=0"])):
        r = subprocess.run(base + ["--out", str(out)] + extra, capture_output=True, text=True, timeout=120)
        assert r.returncode == 0, r.stderr
    detected = transition.classify_run(sampled)
    assert not runfile.has_group(sampled, "events")          # detection went to a temporary file
    assert detected["observables"]["n_events"] > 0
    r = subprocess.run([str(cli), "events", str(sampled)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    stored = transition.classify_run(sampled)
    assert detected["state"] == stored["state"] and detected["states_by_third"] == stored["states_by_third"]
    for key in ("n_events", "size_spread_decades", "spanning_slip_fraction"):
        # the same C++ detection with the same alpha: identical numbers
        a, b = detected["observables"][key], stored["observables"][key]
        assert a == b or (math.isnan(a) and math.isnan(b)), (key, a, b)
    with pytest.raises(ValueError, match="delta_th"):
        transition.classify_run(unsampled)
    rows = transition.classify_directory([unsampled])
    assert rows[0]["state"] == "unreadable" and "delta_th" in rows[0]["error"]


def test_transition_scan_follows_the_friction_family_and_scales_snapshots_with_L():
    """configs/scans/transition.toml: its friction points lie on the straight line in
    (f0, a, b) through configs/reference.toml (s = 0) and configs/fig5.toml (s = 1), at
    nearly fixed f_ss(v0); every length keeps dx = 2.5 mm and ~24 snapshots per L/c_s."""
    import tomllib
    from pathlib import Path
    from slipstrip import scan
    repo = Path(__file__).resolve().parents[2]
    spec = scan.load_scan(repo / "configs/scans/transition.toml")
    runs = scan.expand_runs(spec)
    ref = tomllib.loads((repo / "configs/reference.toml").read_text())
    fig5 = tomllib.loads((repo / "configs/fig5.toml").read_text())
    end = {k: (ref["friction"][k], fig5["friction"][k]) for k in ("f0", "a", "b")}
    points = sorted({tuple(r.parameters[f"friction.{k}"] for k in ("f0", "a", "b")) for r in runs}, reverse=True)
    assert len(points) == 3
    fr = ref["friction"]
    v0 = ref["loading"]["driving_velocity"]
    steady = []
    for f0, a, b in points:
        s = (f0 - end["f0"][0]) / (end["f0"][1] - end["f0"][0])
        # On the line: a and b at the same s as f0 (to the 3-4 digits the scan file gives).
        assert a == pytest.approx(end["a"][0] + s * (end["a"][1] - end["a"][0]), rel=1e-3)
        assert b == pytest.approx(end["b"][0] + s * (end["b"][1] - end["b"][0]), rel=1e-3)
        # Eq. S1 at steady sliding, phi_ss = D / v0.
        phi_ss = fr["characteristic_slip"] / v0
        steady.append(f0 * (1 + b * math.log(phi_ss / fr["phi_star"])) + a * math.log1p(v0 / fr["v_star"]))
    assert max(steady) - min(steady) < 0.002  # 0.3237 .. 0.3227: "fixed f_ss(v0)" to 0.3 %
    mu = ref["material"]["youngs_modulus"] / (2 * (1 + ref["material"]["poisson_ratio"]))
    c_s = math.sqrt(mu / ref["material"]["density"])
    for r in runs:
        length = r.parameters["geometry.length"]
        assert length / r.parameters["geometry.nodes"] == pytest.approx(2.5e-3, rel=1e-12)
        assert length / c_s / r.parameters["output.snapshot_interval"] == pytest.approx(24, rel=0.01)
    heights = {r.parameters["geometry.height"] for r in runs}
    finite = [h for h in heights if h != "inf"]
    lengths = {r.parameters["geometry.length"] for r in runs}
    # The range: H/L from <= 0.0125 to >= 1, plus the half-space.
    assert min(finite) / max(lengths) <= 0.0125 and max(finite) / min(lengths) >= 1 and "inf" in heights


def test_pulse_episodes_find_a_pulse_that_later_breaks_up():
    """The Fig. 5 run shows a travelling pulse for ~100 L/c_s that then breaks up;
    pulse_episodes must put the pulse windows in the first half of such a record
    and none in the second, with the unchanged space-time criterion."""
    from slipstrip import analysis
    t = np.linspace(0.0, 0.04, 801)
    first = t < 0.02
    v = np.where(first[:, None], pulse(t), bursts(t))
    ep = analysis.pulse_episodes(t, v, V0, DX, window=0.005)
    assert len(ep["windows"]) == 8 and all(ep["determined"])
    assert ep["flags"] == [True] * 4 + [False] * 4
    assert ep["longest_start"] == pytest.approx(0.0) and ep["longest_end"] == pytest.approx(0.02)
    assert ep["pulse_fraction"] == pytest.approx(0.5)
    # A record of bursts only has no episode.
    none = analysis.pulse_episodes(t, bursts(t), V0, DX, window=0.005)
    assert not any(none["flags"]) and math.isnan(none["longest_start"])


def test_transition_heights_tell_scaling_with_L_from_scaling_with_Lc():
    # Synthetic map: the spanning-slip fraction is a function of H/L alone
    # (it crosses the threshold 0.8 at H/L = 0.15 * 4**(1/4)), while Lc(H) is
    # the same function of H for every L.  H*/L must then come out the same for
    # L = 1, 2, 4, and H*/Lc(H*) must grow with L.
    heights = [0.0125, 0.025, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0]

    def fraction(h_over_L):
        return 1.0 / (1.0 + (0.15 / h_over_L) ** 4)

    def lc(h):
        return 0.48 * h / (h + 0.05)

    rows = [{"rate_weakening": 0.016, "length": L, "height": h, "state": "complex",
             "spanning_slip_fraction": fraction(h / L), "critical_length": lc(h)}
            for L in (1.0, 2.0, 4.0) for h in heights]
    stars = transition.transition_heights(rows, threshold=0.8)
    assert [t["length"] for t in stars] == [1.0, 2.0, 4.0]
    exact = 0.15 * 4 ** 0.25  # fraction = 0.8 where (0.15 / x)**4 = 1/4
    for t in stars:
        lo, hi = t["height_over_length_bracket"]
        assert lo < exact < hi
        # log-linear interpolation of a smooth curve between grid points a
        # factor 2-2.5 apart: within 15 % of the exact crossing.
        assert t["height_over_length"] == pytest.approx(exact, rel=0.15)
    ratios = [t["height_over_critical_length"] for t in stars]
    assert ratios[1] > 1.5 * ratios[0] and ratios[2] > 1.5 * ratios[1]


def test_transition_heights_ignore_runs_without_events_and_groups_without_crossing():
    rows = [{"rate_weakening": 0.012, "length": 1.0, "height": h, "state": "spanning_ruptures",
             "spanning_slip_fraction": 0.95, "critical_length": 0.5} for h in (0.05, 0.1, 0.2)]
    rows.append({"rate_weakening": 0.012, "length": 1.0, "height": 0.4, "state": "other",
                 "spanning_slip_fraction": math.nan, "critical_length": 0.5})
    assert transition.transition_heights(rows) == []


def test_transition_heights_markdown_lists_every_crossing():
    rows = [{"rate_weakening": 0.016, "length": L, "height": h, "state": "complex",
             "spanning_slip_fraction": 0.1 if h < 0.15 * L else 0.95, "critical_length": 0.45}
            for L in (1.0, 2.0) for h in (0.1, 0.2, 0.5)]
    table = transition.transition_heights_markdown(transition.transition_heights(rows))
    body = [line for line in table.splitlines() if line.startswith("| 0.0160")]
    assert len(body) == 2 and "| 1 m |" in body[0] and "| 2 m |" in body[1]


def _ensemble_rows(fractions_by_height, length=1.0, slope=0.016, lc=0.45):
    """Rows of one (friction, L) group: at each height one row per seed (1, 7, 8, ...)."""
    return [{"rate_weakening": slope, "length": length, "height": h, "state": "complex", "converged": True,
             "spanning_slip_fraction": f, "critical_length": lc, "noise_seed": seed}
            for h, fractions in fractions_by_height.items() for seed, f in zip((1, 7, 8), fractions)]


def test_transition_height_of_a_seed_ensemble_and_its_spread_over_seed_picks():
    # Three seeds at the two bracketing heights, one elsewhere.  Means: 0.2, 0.6, 0.9, 1.0, so the
    # mean crosses 0.8 between 0.1 and 0.2 at w = (0.8 - 0.6) / (0.9 - 0.6) = 2/3.
    rows = _ensemble_rows({0.05: [0.2], 0.1: [0.5, 0.6, 0.7], 0.2: [0.85, 0.9, 0.95], 0.5: [1.0]})
    (t,) = transition.transition_heights(rows, threshold=0.8)
    expected = math.exp(math.log(0.1) / 3 + 2 * math.log(0.2) / 3)
    assert t["height"] == pytest.approx(expected, rel=1e-12)
    assert t["height_bracket"] == (0.1, 0.2) and t["seeds_at_bracket"] == (3, 3)
    # Every pick of one member per height crosses between 0.1 and 0.2; the lowest H* comes
    # from the highest fractions (0.7 -> 0.95: w = 0.4), the highest from the lowest
    # (0.5 -> 0.85: w = 6/7).
    lo = math.exp(0.6 * math.log(0.1) + 0.4 * math.log(0.2))
    hi = math.exp(math.log(0.1) / 7 + 6 * math.log(0.2) / 7)
    assert t["height_range"] == (pytest.approx(lo, rel=1e-12), pytest.approx(hi, rel=1e-12))
    assert t["seed_picks"] == 9 and t["picks_without_crossing"] == 0
    # With one seed per height the spread is H* itself.
    (single,) = transition.transition_heights(_ensemble_rows({0.1: [0.6], 0.2: [0.9]}), threshold=0.8)
    assert single["height_range"] == (pytest.approx(single["height"]), pytest.approx(single["height"]))


def test_seed_picks_without_a_crossing_are_counted():
    # Seed 8 at H = 0.2 stays below the threshold: the 3 picks (of 3 x 3) that use it never
    # rise through 0.8; the means (0.6, 0.83) still cross.
    rows = _ensemble_rows({0.1: [0.5, 0.6, 0.7], 0.2: [0.85, 0.9, 0.75]})
    (t,) = transition.transition_heights(rows, threshold=0.8)
    assert t["seed_picks"] == 9 and t["picks_without_crossing"] == 3
    assert "3 of 9 picks: no crossing" in transition.transition_heights_markdown([t])


def test_map_table_shows_every_seed_and_runs_differing_by_seed_are_different_cells():
    rows = _ensemble_rows({0.1: [0.5, 0.6, 0.7]})
    rows[1]["state"], rows[2]["converged"] = "spanning_ruptures", False
    for r in rows:
        r.update(nodes=400)
    table = transition.state_grid_markdown(rows)
    assert "| 0.0160 | C R c (4.5) |" in table
    base = {"f0": 0.28, "a": 0.005, "b": 0.075, "length": 1.0, "height": 0.1, "nodes": 400}
    # A map written before seeds were varied has no seed column: its runs used seed 1.
    assert transition._map_cell(base) == transition._map_cell({**base, "noise_seed": 1.0})
    assert transition._map_cell(base) != transition._map_cell({**base, "noise_seed": 7})


def test_an_extended_run_replaces_the_shorter_run_of_the_same_cell():
    base = {"f0": 0.28, "a": 0.005, "b": 0.075, "length": 1.0, "height": 0.2, "nodes": 400, "state": "complex",
            "converged": False}
    rows = [{**base, "noise_seed": 7, "duration": 0.18, "file": "short.h5"},
            {**base, "noise_seed": 8, "duration": 0.18, "file": "other_seed.h5"},
            {**base, "noise_seed": 7, "duration": 0.54, "file": "extended.h5", "state": "spanning_ruptures",
             "converged": True},
            {"file": "broken.h5", "state": "unreadable"}]
    kept = [r["file"] for r in transition.longest_run_per_cell(rows)]
    assert kept == ["other_seed.h5", "extended.h5", "broken.h5"]


def _edge_row(L, h, state, converged=True, seed=1, slope=0.012, lc=None):
    return {"rate_weakening": slope, "length": L, "height": h, "state": state, "converged": converged,
            "noise_seed": seed, "critical_length": lc if lc is not None else 1.6 * math.sqrt(h),
            "spanning_slip_fraction": 0.9 if state == "spanning_ruptures" else 0.3}


def test_thin_edges_bracket_the_thinnest_complex_strip_or_bound_it_from_above():
    rows = [
        # L = 2 m: a closed window; the thin edge lies between 0.0125 (spanning) and 0.025 m.
        _edge_row(2.0, 0.0125, "spanning_ruptures"), _edge_row(2.0, 0.025, "complex"),
        _edge_row(2.0, 0.05, "complex"), _edge_row(2.0, 0.5, "spanning_ruptures"),
        # L = 4 m: complex at every strip run; the thinnest one is not converged.
        _edge_row(4.0, 0.001, "complex", converged=False), _edge_row(4.0, 0.0125, "complex"),
        _edge_row(4.0, math.inf, "arrested"),
        # L = 3 m: seeds disagree at 0.005 m (one complex run makes the height complex), and the strip
        # below is neither complex nor spanning (creeping patches).
        _edge_row(3.0, 0.003, "other", converged=False), _edge_row(3.0, 0.005, "spanning_ruptures", seed=2),
        _edge_row(3.0, 0.005, "complex", seed=1), _edge_row(3.0, 0.05, "complex"),
        # A friction point without a complex run has no window and no edge.
        _edge_row(1.0, 0.0125, "periodic_pulse", slope=0.0059), _edge_row(1.0, 0.1, "spanning_ruptures", slope=0.0059),
    ]
    edges = {e["length"]: e for e in transition.thin_edges(rows)}
    assert sorted(edges) == [2.0, 3.0, 4.0]
    two, three, four = edges[2.0], edges[3.0], edges[4.0]
    assert (two["height_not_complex"], two["height_complex"]) == (0.0125, 0.025)
    assert two["states_not_complex"] == "spanning_ruptures" and two["converged_not_complex"] and two["converged_complex"]
    # Lc(H)/H and L/Lc(H) at the two ends, from the rows' own Lc.
    assert two["critical_over_height_complex"] == pytest.approx(1.6 * math.sqrt(0.025) / 0.025)
    assert two["length_over_critical_not_complex"] == pytest.approx(2.0 / (1.6 * math.sqrt(0.0125)))
    assert four["height_complex"] == 0.001 and math.isnan(four["height_not_complex"])
    assert not four["converged_complex"] and math.isnan(four["length_over_critical_not_complex"])
    assert three["height_complex"] == 0.005 and three["height_not_complex"] == 0.003
    assert three["states_complex"] == "complex/spanning_ruptures"      # both seeds, in seed order
    assert three["states_not_complex"] == "other" and not three["converged_not_complex"]
    # L = 2 m's window is one interval; L = 5 m's holds a spanning strip between two complex ones.
    assert two["inside_not_complex"] == ""
    five = transition.thin_edges([_edge_row(5.0, 0.005, "complex"), _edge_row(5.0, 0.0125, "spanning_ruptures"),
                                  _edge_row(5.0, 0.025, "complex"), _edge_row(5.0, 1.0, "spanning_ruptures")])[0]
    assert five["height_complex"] == 0.005 and five["inside_not_complex"] == "0.0125:spanning_ruptures"
    assert "not complex between complex strips: H = 0.0125 m (`spanning_ruptures`)" in \
        transition.thin_edges_markdown([five])

    text = transition.thin_edges_markdown(list(edges.values()))
    lines = [line for line in text.splitlines() if line.startswith("| 0.0120")]
    assert [line.split("|")[2].strip() for line in lines] == ["2 m", "3 m", "4 m"]
    assert "`spanning_ruptures` below, `complex` above" in lines[0]
    # Lc/H = 1.6 / sqrt(0.001) = 50.6 at the thinnest complex strip.
    assert "bounded above only" in lines[2] and "> 51 |" in lines[2] and "(not converged)" in lines[2]
    assert transition.thin_edges_markdown([]).startswith("No friction point")


def test_thin_edges_and_the_plane_from_committed_maps(tmp_path):
    """--previous maps alone give the thin edges (CSV and table) and the (H, L) plane; two maps holding
    the same run (one of them extended) give one row for it, the longer one."""
    import csv
    fields = ["a", "b", "f0", "nodes", "noise_seed", "duration", "file", "status", "agreement", "states_by_third",
              "rate_weakening", "length", "height", "state", "converged", "critical_length", "spanning_slip_fraction"]

    def row(h, state, duration, name, converged=True):
        return {"a": 0.01, "b": 0.0955, "f0": 0.23, "nodes": 800, "noise_seed": 1, "duration": duration,
                "file": f"scan/{name}.h5", "status": "completed", "agreement": 1.0,
                "states_by_third": "/".join([state] * 3), "rate_weakening": 0.012, "length": 2.0, "height": h,
                "state": state, "converged": converged, "critical_length": 1.6 * math.sqrt(h),
                "spanning_slip_fraction": 0.9 if state == "spanning_ruptures" else 0.3}
    first, second = tmp_path / "first.csv", tmp_path / "second.csv"
    for path, rows in ((first, [row(0.0125, "other", 0.36, "short", converged=False), row(0.025, "complex", 0.36, "b"),
                                row(0.2, "complex", 0.36, "c"), row(0.5, "spanning_ruptures", 0.36, "d")]),
                       (second, [row(0.0125, "spanning_ruptures", 1.07, "long")])):
        with path.open("w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=fields)
            w.writeheader()
            w.writerows(rows)
    edges_csv, plane, merged = tmp_path / "edges.csv", tmp_path / "plane.png", tmp_path / "merged.csv"
    assert transition.main(["--previous", str(first), "--previous", str(second), "--csv", str(merged),
                            "--thin-edges", str(edges_csv), "--plane", str(plane)]) == 0
    kept = [r for r in csv.DictReader(merged.open()) if r["height"] == "0.0125"]
    assert [r["file"] for r in kept] == ["scan/long.h5"]
    (edge,) = list(csv.DictReader(edges_csv.open()))
    assert list(edge) == list(transition.THIN_EDGE_COLUMNS)
    assert (float(edge["height_not_complex"]), float(edge["height_complex"])) == (0.0125, 0.025)
    assert edge["states_not_complex"] == "spanning_ruptures" and edge["converged_not_complex"] == "True"
    assert_figure(plane, page_width=True)


def test_a_read_error_of_a_running_run_is_reported_with_its_cause_not_raised(monkeypatch):
    """The compiled event detection raises RuntimeError on an HDF5 read error; on a run still being
    written a long read can see the file change under it (docs/output.md).  The map lists such a run as
    not classified, saying why, and goes on with the others."""
    def parameters(path):
        return {"file": str(path), "status": "running" if "live" in str(path) else "completed", "length": 1.0,
                "height": 0.1, "nodes": 400, "f0": 0.28, "a": 0.005, "b": 0.075, "rate_weakening": 0.016,
                "noise_seed": 1, "duration": 0.18}

    def failing_read(path):
        raise RuntimeError(f"HDF5 error: H5Dread({path}:/slip_sampling/crossing_time) failed: addr overflow")
    monkeypatch.setattr(transition, "_run_parameters", parameters)
    monkeypatch.setattr(transition, "classify_run", failing_read)
    live, done = transition.classify_directory(["live.h5", "done.h5"])
    assert live["state"] == done["state"] == "unreadable"
    assert "addr overflow" in live["error"] and "still being written" in live["error"]
    assert "addr overflow" in done["error"] and "still being written" not in done["error"]
