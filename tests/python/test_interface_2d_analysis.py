"""`analyze` and `plot` of a 2D interface (geometry.nodes_z > 1, docs/3d.md,
docs/analysis.md) and the one-line refusal of the commands that stay
one-dimensional.  One run of configs/3d/demo.toml at 64 x 16 nodes over 40
transits (about 10^4 steps, a few seconds of CPU) keeps 16 events with the
default alpha; the tests check what analyze computes and draws from that
catalog, recomputed here from the catalog itself.

Run: SLIPSTRIP_BUILD_DIR=$PWD/build PYTHONPATH=$PWD/python OMP_NUM_THREADS=1 \\
     /usr/bin/python3 -m pytest -q tests/python/test_interface_2d_analysis.py
"""
import json
import os
import subprocess
import sys

import h5py
import matplotlib.image
import numpy as np
import pytest

from conftest import REPO
from figure_checks import distinct_colours

DEMO = REPO / "configs" / "3d" / "demo.toml"
PYTHON_DIR = REPO / "python"
L, W, MU, D, V0 = 0.5, 0.25, 9e9, 1.667e-7, 2e-3


@pytest.fixture(scope="module")
def analysed(tmp_path_factory, slipstrip_module):
    from slipstrip import analysis
    work = tmp_path_factory.mktemp("interface_2d_analysis")
    run = work / "demo_small.h5"
    slipstrip_module.run(DEMO, run, overrides={"geometry.nodes": 64, "geometry.nodes_z": 16,
                                               "time.duration_transits": 40.0, "output.snapshot_interval": 1e-4})
    summary = analysis.analyze(run, work / "analysis", sensitivity_alphas=(8.0, 15.0))
    with h5py.File(work / "analysis" / "events_alpha15.h5", "r") as f:
        catalog = {k: f["events"][k][:] for k in ("t_start", "T", "x_start", "z_start", "u_mean", "M0", "A", "L_s")}
    return run, work / "analysis", summary, catalog


def test_analyze_reports_the_catalog_statistics_per_area(analysed):
    run, out, summary, catalog = analysed
    n = len(catalog["t_start"])
    assert n >= 10  # enough events that the statistics are not empty
    assert summary["interface"] == "2d" and summary["n_events"] == n
    assert summary["normalisation"] == {"u": "u_mean/D", "T": "T*v0/D", "M0": "M0/(mu*D*L*W)", "A": "A/(L*W)"}
    assert summary["moment_units"] == "N m (mu A u_mean)"
    assert summary["scales"]["nodes_z"] == 16 and summary["scales"]["W"] == W
    u = catalog["u_mean"] / D
    assert summary["n_events_small"] == int(np.sum(u < 1)) and summary["n_events_large"] == int(np.sum(u >= 1))
    # Slip fractions weighted by area (system-spanning: A >= 0.9 L W), recomputed;
    # 1e-12: the same sums in another order.
    w = catalog["u_mean"] * catalog["A"]
    assert summary["slip_fraction_spanning"] == pytest.approx(w[catalog["A"] >= 0.9 * L * W].sum() / w.sum(),
                                                              rel=1e-12)
    assert summary["slip_fraction_small"] == pytest.approx(w[u < 1].sum() / w.sum(), rel=1e-12, abs=1e-300)
    # The area is an observable of its own: in the fits and the stationarity tests.
    assert "small_exponent_A" in summary and "A" in summary["stationarity"]
    assert summary["periodic_pulse"] is None and "one-dimensional" in summary["periodic_pulse_basis"]
    with open(out / "summary.json") as fh:
        assert json.load(fh)["n_events"] == n


def test_normalised_observables_of_a_2d_interface(analysed):
    from slipstrip import analysis
    run, _, _, catalog = analysed
    info = analysis.read_run_info(run)
    assert info.interface_2d and info.W == W and info.nodes_z == 16
    obs = analysis.normalised_observables(catalog, info)
    assert set(obs) == {"u", "T", "M0", "A"}
    assert np.array_equal(obs["A"], catalog["A"] / (L * W))
    assert np.array_equal(obs["M0"], catalog["M0"] / (MU * D * L * W))
    # M0 = mu A u_mean [N m] (a moment, not per unit width): 1e-14, three roundings.
    assert np.allclose(catalog["M0"], MU * catalog["A"] * catalog["u_mean"], rtol=1e-14, atol=0)


def test_analyze_draws_maps_hypocentres_and_four_pdfs(analysed, monkeypatch):
    from slipstrip import analysis
    from slipstrip.analysis import figures
    run, out, summary, catalog = analysed
    largest = int(np.argmax(catalog["M0"]))
    names = {os.path.basename(p) for p in summary["figures"]}
    assert names == {"hypocentres.png", "pdfs.png", "stationarity.png", "threshold_sensitivity.png",
                     f"event_{largest}_maps.png", "space_time.png"}
    # The event maps are the snapshots nearest to the start, middle and end of the event.
    with h5py.File(run, "r") as f:
        ts = f["snapshots/time"][:]
    t0 = catalog["t_start"][largest]
    t1 = t0 + catalog["T"][largest]
    assert summary["event_fields"]["snapshot_times"] == [ts[np.argmin(np.abs(ts - t))] for t in (t0, 0.5 * (t0 + t1), t1)]
    for name in names:
        image = matplotlib.image.imread(out / name)
        assert distinct_colours(image) > 20, name  # not blank
    # What the figures draw: capture them before they are saved.
    drawn = {}
    monkeypatch.setattr(figures, "_save", lambda fig, out_dir, name, pdf: drawn.setdefault(name, fig) and [])
    info = analysis.read_run_info(run)
    cat = {**catalog, "attrs": {}}
    stats = analysis.catalog_statistics(cat, info, n_bootstrap=0)
    figures.plot_pdfs(cat, info, stats, out, False)
    figures.plot_hypocentres(cat, info, out, False)
    axes = drawn["pdfs"].axes
    assert [ax.get_xlabel() for ax in axes] == [r"$\bar u/D$", r"$T v_0/D$", r"$M_0/(\mu D L W)$", r"$A/(L W)$"]
    centres, pdf, _ = analysis.log_binned_pdf(catalog["A"] / (L * W))
    line = next(l for l in axes[3].get_lines() if l.get_label() == "all events")
    assert np.allclose(line.get_xdata(), centres[pdf > 0], rtol=1e-15)
    scatter = drawn["hypocentres"].axes[0].collections[0]
    assert np.array_equal(scatter.get_offsets(), np.column_stack([catalog["x_start"], catalog["z_start"]]))
    assert drawn["hypocentres"].axes[0].get_xlim() == (0.0, L)


def _module(*args):
    env = dict(os.environ, PYTHONPATH=str(PYTHON_DIR))
    return subprocess.run([sys.executable, "-m", "slipstrip", *map(str, args)], capture_output=True, text=True,
                          env=env, timeout=300)


# Slow tier for its cost (four plot processes, 3 s of CPU): it checks the
# command line; the maps themselves are checked in the fast tier by
# test_interface_2d_python.py::test_slip_rate_maps_with_rupture_front_contours.
@pytest.mark.slow
def test_plot_draws_the_maps_of_a_2d_interface(analysed, tmp_path):
    run = analysed[0]
    r = _module("plot", run, "--out", tmp_path / "maps.png", "--times", "1e-3,2e-3,3e-3")
    assert r.returncode == 0, r.stderr
    image = matplotlib.image.imread(tmp_path / "maps.png")
    assert distinct_colours(image) > 50
    r = _module("plot", run, "--out", tmp_path / "default.png")  # maps by default
    assert r.returncode == 0 and (tmp_path / "default.png").is_file(), r.stderr
    r = _module("plot", run, "--kind", "spacetime", "--z", "0.1", "--out", tmp_path / "st.png")
    assert r.returncode == 0, r.stderr
    assert distinct_colours(matplotlib.image.imread(tmp_path / "st.png")) > 50
    for bad in (["--kind", "spacetime", "--z", "5"], ["--kind", "maps", "--z", "0.1"]):
        r = _module("plot", run, *bad, "--out", tmp_path / "bad_z.png")
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
        assert not (tmp_path / "bad_z.png").exists()
    r = _module("plot", run, "--times", "a,b", "--out", tmp_path / "bad.png")
    assert r.returncode == 2 and "--times" in r.stderr


@pytest.mark.parametrize("command", [["pulse-episodes", "{run}"], ["trajectory-divergence", "{run}", "{run}"],
                                     ["transition", "{run}"]])
def test_one_dimensional_commands_refuse_a_2d_interface_in_one_line(analysed, command):
    run = analysed[0]
    r = _module(*[c.format(run=run) for c in command])
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "is a 2D interface (geometry.nodes_z > 1)" in lines[0] and "one-dimensional" in lines[0]


def test_report_refuses_a_2d_interface_run(analysed, tmp_path):
    from slipstrip.report.runs import MissingRun, open_run_file
    run = analysed[0]
    (tmp_path / "reference.h5").symlink_to(run)
    with pytest.raises(MissingRun, match=r"RUNDIR/reference.h5 is a 2D interface .*one-dimensional interface"):
        open_run_file(tmp_path, "reference", allow_incomplete=True)
