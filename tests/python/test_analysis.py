"""Tests of python/slipstrip/analysis/ (slip-event statistics and figures).

The module is imported from the package (it reads run files through
slipstrip.runfile and detects events through the bindings).  The end-to-end
tests make their run with the CLI binary (the `cli` fixture of conftest.py)
and are skipped without it.

Run: /usr/bin/python3 -m pytest tests/python/test_analysis.py
"""
import json
import math
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest
from figure_checks import assert_figure
from scipy import stats

from slipstrip import analysis

REPO = Path(__file__).resolve().parents[2]


def pareto_sample(rng, exponent, xmin, n):
    """Inverse-CDF draw from p(x) ~ x^-exponent, x >= xmin."""
    return xmin * (1.0 - rng.random(n)) ** (-1.0 / (exponent - 1.0))


def truncated_power_law_sample(rng, exponent, lo, hi, n):
    """Inverse-CDF draw from p(x) ~ x^-exponent on [lo, hi]."""
    s = 1.0 - exponent
    u = rng.random(n)
    return (lo ** s + u * (hi ** s - lo ** s)) ** (1.0 / s)


# ---------------------------------------------------------------------------
# Power law
# ---------------------------------------------------------------------------

def test_power_law_mle_recovers_exponent_untruncated():
    rng = np.random.default_rng(1)
    x = pareto_sample(rng, 2.45, 1.0, 5000)
    fit = analysis.fit_power_law(x, xmin=1.0)
    # 3 standard errors: a correct estimator fails this 0.3% of the time.
    assert abs(fit.exponent - 2.45) < 3 * fit.stderr
    # The Fisher error of the untruncated law is (a - 1)/sqrt(n) (Clauset et al. Eq. 3.2).
    assert fit.stderr == pytest.approx((fit.exponent - 1) / math.sqrt(5000), rel=1e-12)
    assert fit.n == 5000


def test_power_law_mle_truncated_at_split():
    # Like u/D of small events: power law on [0.02, 1], cut at the split u = D.
    rng = np.random.default_rng(2)
    x = truncated_power_law_sample(rng, 2.45, 0.02, 1.0, 5000)
    fit = analysis.fit_power_law(x, xmin=0.02, xmax=1.0, n_bootstrap=200, seed=3)
    assert abs(fit.exponent - 2.45) < 3 * fit.stderr
    # Fisher error vs bootstrap: 200 resamples estimate a standard deviation to
    # ~5% (1/sqrt(2*200)); 20% is 4 of those.
    assert fit.bootstrap_stderr == pytest.approx(fit.stderr, rel=0.2)


def test_xmin_sweep_of_an_exact_power_law_is_flat():
    # An exact truncated power law: every x_min gives the same exponent within
    # its error (3 sigma each, five fits: a correct estimator fails ~1.5 %).
    rng = np.random.default_rng(5)
    x = truncated_power_law_sample(rng, 2.45, 0.01, 1.0, 20000)
    sweep = analysis.exponent_xmin_sweep(x, 0.03, xmax=1.0)
    assert [round(f.xmin / 0.03, 6) for f in sweep] == [0.5, 1.0, 2.0, 4.0]  # 0.25 x_opt is below the data
    for f in sweep:
        assert abs(f.exponent - 2.45) < 3 * f.stderr


def test_xmin_sweep_shows_the_curvature_of_a_broken_power_law():
    # A continuous density with exponent 1.8 below 0.1 and 2.8 above (92 % and
    # 8 % of the mass on [0.01, 1]): the exponent fitted from x_min grows with
    # x_min, by much more than its statistical error.
    rng = np.random.default_rng(6)
    lo = truncated_power_law_sample(rng, 1.8, 0.01, 0.1, 11000)
    hi = truncated_power_law_sample(rng, 2.8, 0.1, 1.0, 900)
    sweep = analysis.exponent_xmin_sweep(np.concatenate([lo, hi]), 0.05, xmax=1.0)
    exps = [f.exponent for f in sweep]
    assert len(sweep) == 5
    # Rising until x_min passes the break, then 2.8 within its error.
    assert exps[0] < exps[1] < exps[2] < exps[3]
    assert abs(exps[3] - 2.8) < 3 * sweep[3].stderr and abs(exps[4] - 2.8) < 3 * sweep[4].stderr
    assert exps[3] - exps[0] > 10 * max(f.stderr for f in sweep[:4])
    # Too few samples above x_min: that fit is left out, not reported as NaN.
    assert all(f.n >= 50 for f in sweep)
    assert analysis.exponent_xmin_sweep(x := np.array([0.5, 0.6]), 0.5, xmax=1.0) == []


def test_power_law_truncation_matters_for_shallow_laws():
    # With exponent 1.5 on [0.02, 1] an untruncated law would put 14% of its mass
    # above the cut (50^-0.5), so ignoring the cut biases the exponent up by many
    # standard errors, while the truncated likelihood recovers it.
    rng = np.random.default_rng(13)
    x = truncated_power_law_sample(rng, 1.5, 0.02, 1.0, 5000)
    fit = analysis.fit_power_law(x, xmin=0.02, xmax=1.0)
    assert abs(fit.exponent - 1.5) < 3 * fit.stderr
    naive = analysis.fit_power_law(x, xmin=0.02)
    assert naive.exponent - 1.5 > 5 * naive.stderr


def test_power_law_truncated_likelihood_matches_scipy_on_a_grid():
    # Independent reference: maximise the truncated log-likelihood by brute force
    # on a fine grid, with the normalisation integrated by scipy.integrate.quad.
    from scipy import integrate
    rng = np.random.default_rng(4)
    x = truncated_power_law_sample(rng, 1.7, 0.5, 20.0, 800)
    fit = analysis.fit_power_law(x, xmin=0.5, xmax=20.0)
    grid = np.linspace(1.4, 2.0, 601)
    ll = [-a * np.sum(np.log(x)) - x.size * math.log(integrate.quad(lambda t: t ** -a, 0.5, 20.0)[0])
          for a in grid]
    # Grid spacing 1e-3: the grid maximum is within one spacing of the true maximum.
    assert fit.exponent == pytest.approx(grid[int(np.argmax(ll))], abs=1.5e-3)


def test_power_law_xmin_by_ks_finds_the_tail():
    # Below x = 1 the data are uniform (not a power law); above, Pareto 2.2.
    rng = np.random.default_rng(5)
    body = rng.uniform(0.1, 1.0, 2000)
    tail = pareto_sample(rng, 2.2, 1.0, 4000)
    fit = analysis.fit_power_law(np.concatenate([body, tail]))
    # KS selection must not start inside the uniform body (a fit from there is
    # badly biased) and must keep a substantial tail; it need not hit x = 1
    # exactly, since the KS distance is nearly flat for xmin >= 1 (measured:
    # xmin = 1.98 for this seed, n = 1724 of 4000 tail samples).  The exponent
    # must be recovered within 3 standard errors.
    assert 0.9 <= fit.xmin and fit.n >= 1000
    assert abs(fit.exponent - 2.2) < 3 * fit.stderr


def test_power_law_too_few_points_gives_nan():
    fit = analysis.fit_power_law([1.0, 2.0, 3.0])
    assert math.isnan(fit.exponent) and math.isnan(fit.stderr)


# ---------------------------------------------------------------------------
# Log-normal
# ---------------------------------------------------------------------------

def test_lognormal_fit_recovers_parameters():
    rng = np.random.default_rng(6)
    mu, sigma, n = 1.3, 0.6, 2000
    fit = analysis.fit_lognormal(rng.lognormal(mu, sigma, n), n_bootstrap=300, seed=7)
    # MLE standard errors: sigma/sqrt(n) for mu, sigma/sqrt(2n) for sigma; 3 of each.
    assert abs(fit.mu - mu) < 3 * sigma / math.sqrt(n)
    assert abs(fit.sigma - sigma) < 3 * sigma / math.sqrt(2 * n)
    assert fit.ks_pvalue > 0.01  # a true log-normal sample is not rejected


def test_lognormal_ks_rejects_a_power_law():
    rng = np.random.default_rng(8)
    fit = analysis.fit_lognormal(pareto_sample(rng, 2.0, 1.0, 2000), n_bootstrap=300, seed=9)
    # 300 resamples: the smallest possible p is 1/301; a heavy Pareto tail is far from log-normal.
    assert fit.ks_pvalue < 0.01


def test_lognormal_too_few_events_gives_nan():
    fit = analysis.fit_lognormal([1.0, 2.0])
    assert math.isnan(fit.mu) and math.isnan(fit.ks_pvalue)


# ---------------------------------------------------------------------------
# Binning and slip partition
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("bpd", [3, 5, 10])
def test_log_binned_pdf_integrates_to_one(bpd):
    rng = np.random.default_rng(10)
    x = np.concatenate([pareto_sample(rng, 2.45, 0.02, 3000), rng.lognormal(2.0, 0.5, 500), [0.0, -1.0, np.nan]])
    centres, pdf, edges = analysis.log_binned_pdf(x, bins_per_decade=bpd)
    # Exact up to round-off: every finite positive sample falls in one bin.
    assert np.sum(pdf * np.diff(edges)) == pytest.approx(1.0, rel=1e-12)
    assert np.allclose(np.diff(np.log10(edges)), np.log10(edges[-1] / edges[0]) / (edges.size - 1))
    assert np.all((centres > edges[:-1]) & (centres < edges[1:]))


def test_log_binned_pdf_matches_density_of_known_law():
    # p(x) = 1/x^2 on [1, inf): the bin-averaged density is 1/(x_lo x_hi) = 1/centre^2.
    rng = np.random.default_rng(11)
    x = pareto_sample(rng, 2.0, 1.0, 200000)
    c, p, e = analysis.log_binned_pdf(x, bins_per_decade=5, lo=1.0, hi=100.0)
    expected = 1.0 / c ** 2
    counts = p * np.diff(e) * x.size
    # Poisson errors per bin; 4 sigma (plus the normalisation factor).
    assert np.all(np.abs(p - expected) < 4 * expected / np.sqrt(np.maximum(counts, 1)) + 1e-12)


def test_slip_fractions_hand_built_catalog():
    D, L = 1.0, 10.0
    u = np.array([0.5, 0.2, 2.0, 3.0])
    Ls = np.array([1.0, 5.0, 10.0, 9.5])
    # Weights u L_s: 0.5, 1.0, 20.0, 28.5; total 50.
    fr = analysis.slip_fractions(u, Ls, D, L)
    assert fr["small"] == pytest.approx(1.5 / 50.0, rel=1e-15)
    assert fr["spanning"] == pytest.approx(48.5 / 50.0, rel=1e-15)
    empty = analysis.slip_fractions([], [], D, L)
    assert math.isnan(empty["small"]) and math.isnan(empty["spanning"])


# ---------------------------------------------------------------------------
# Periodic-pulse criterion
# ---------------------------------------------------------------------------

def _info(**kw):
    base = dict(D=1e-6, L=1.0, H=0.1, v0=1e-3, mu=1e9, c_s=1000.0, sigma0=1e6, delta_th=1e-8,
                n_nodes=100, duration=1.0)
    base.update(kw)
    return analysis.RunInfo(**base)


def _catalog(t_start, u_mean, L_s, T=None):
    n = len(t_start)
    T = np.full(n, 1e-4) if T is None else T
    return {"t_start": np.asarray(t_start, float), "u_mean": np.asarray(u_mean, float),
            "L_s": np.asarray(L_s, float), "T": np.asarray(T, float),
            "M0": 1e9 * np.asarray(u_mean) * np.asarray(L_s), "attrs": {}}


def test_periodic_pulse_flag_periodic_vs_random():
    info = _info()
    rng = np.random.default_rng(12)
    n = 40
    # Period 0.02 s with 2.5% jitter, u_mean 10 D with 3% scatter: CVs well below 0.2.
    periodic = _catalog(0.02 * np.arange(n) + 0.0005 * rng.standard_normal(n),
                        10e-6 * (1 + 0.03 * rng.standard_normal(n)), np.full(n, info.L))
    r = analysis.periodic_pulse_from_catalog(periodic, info)
    assert r["flag"] and r["spanning_slip_fraction"] == pytest.approx(1.0)
    # Complex state: many small events, spanning events at random (Poisson) times
    # with log-normal slips.
    t_small = np.sort(rng.uniform(0, 1, 500))
    small = _catalog(t_small, 0.02e-6 * pareto_sample(rng, 2.45, 1, 500), rng.uniform(0.01, 0.3, 500))
    t_big = np.sort(rng.uniform(0, 1, 30))
    big = _catalog(t_big, 1e-6 * rng.lognormal(1.5, 0.6, 30), np.full(30, info.L))
    mixed = {k: np.concatenate([small[k], big[k]]) for k in ("t_start", "u_mean", "L_s", "T", "M0")}
    assert not analysis.periodic_pulse_from_catalog(mixed, info)["flag"]
    # Periodic in time but irregular in slip: still not a single steady pulse.
    irregular = _catalog(periodic["t_start"], 1e-6 * rng.lognormal(1.5, 0.6, n), np.full(n, info.L))
    assert not analysis.periodic_pulse_from_catalog(irregular, info)["flag"]
    # Too few events: no flag.
    assert not analysis.periodic_pulse_from_catalog(_catalog([0.1, 0.2], [1e-5, 1e-5], [1.0, 1.0]), info)["flag"]


def test_periodic_pulse_flag_from_timeseries():
    t = np.linspace(0, 1, 2000)
    v0 = 1e-3
    steady = 20 * v0 * (1 + 0.02 * np.sin(40 * t))
    assert analysis.periodic_pulse_from_timeseries(t, steady, v0)["flag"]
    bursts = v0 * np.where(np.sin(30 * t) > 0.9, 50.0, 0.01)
    assert not analysis.periodic_pulse_from_timeseries(t, bursts, v0)["flag"]
    creep = np.full(t.size, v0)  # stable steady sliding is not a pulse
    assert not analysis.periodic_pulse_from_timeseries(t, creep, v0)["flag"]


# ---------------------------------------------------------------------------
# numpy grouping (event-coloured map)
# ---------------------------------------------------------------------------

def test_group_nodal_slips_hand_built():
    # N = 4 nodes, delta_th = 1, v0 = 1, alpha = 4: threshold alpha delta_th/(v0 N) = 1.
    nan = np.nan
    ct = np.array([[1.0, 1.2, 1.5, 10.0],
                   [1.9, 2.0, nan, 10.5],
                   [3.0, 4.0, 5.0, 11.0],   # node 2's 5.0 follows a NaN: ignored (NaN tail)
                   [4.5, nan, nan, 11.0]])
    g = analysis.group_nodal_slips(ct, 1.0, 1.0, alpha=4.0, exclude_first_last=False,
                                   min_extent_dx=1, min_mean_slip_dth=1)
    # Sorted NS times: 1.0 1.2 1.5 1.9 2.0 | 3.0 (gap 1.0, not > 1: same event) 4.0 4.5 | 10.0 10.5 11.0 11.0
    # Gaps: 0.2 0.3 0.4 0.1 1.0 1.0 0.5 5.5 0.5 0.5 0 -> one break, before 10.0.
    assert g.n_detected == 2
    assert g.label[2, 2] == -1 and g.label[0, 3] == 1 and g.label[3, 0] == 0
    assert g.waiting_time_threshold == 1.0


def test_group_nodal_slips_filters():
    nan = np.nan
    # Three events (threshold 1 with alpha=4, N=4, delta_th=v0=1): events 0, 1, 2.
    ct = np.array([[0.0, 0.1, 5.0, nan],
                   [0.2, 0.3, 9.2, nan],
                   [9.0, 9.1, 9.5, nan],
                   [9.3, 9.4, nan, nan]])
    g = analysis.group_nodal_slips(ct, 1.0, 1.0, alpha=4.0, exclude_first_last=False)
    # Event 0: nodes 0, 1 with 2 NS each; event 1: one NS of node 2 (extent 1 dx < 2 dx):
    # removed; event 2: nodes 0, 1, 2 with 2 NS each (u_mean = 2 delta_th: kept).
    assert g.n_detected == 3
    assert list(g.kept) == [True, False, True]
    g2 = analysis.group_nodal_slips(ct, 1.0, 1.0, alpha=4.0)
    assert list(g2.kept) == [False, False, False]


# ---------------------------------------------------------------------------
# A power law fitted to few events carries a caution
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("n_small, cautioned", [(30, True), (3000, False)])
def test_power_law_of_few_events_is_cautioned(n_small, cautioned):
    info = _info()
    rng = np.random.default_rng(5)
    # Small events (u < D) from p(u/D) ~ (u/D)^-1.8 on [0.01, 1], plus large ones for the log-normal.
    u = np.concatenate([truncated_power_law_sample(rng, 1.8, 0.01, 1.0, n_small) * info.D,
                        info.D * np.exp(rng.normal(1.0, 0.3, 50))])
    n = u.size
    catalog = _catalog(np.sort(rng.random(n)), u, np.full(n, 0.1 * info.L),
                       T=np.exp(rng.normal(0.0, 0.5, n)) * info.D / info.v0)
    res = analysis.catalog_statistics(catalog, info, n_bootstrap=0)
    fitted = res["small_exponent_u_n"]
    assert math.isfinite(res["small_exponent_u"])
    caution = [c for c in res["cautions"] if c.startswith("the power law of u ")]
    assert bool(caution) == cautioned == (fitted < analysis.POWER_LAW_CAUTION_EVENTS)
    if cautioned:
        assert f"only {fitted} events" in caution[0]
        public = {k: v for k, v in res.items() if not k.startswith("_")}  # as analyze() passes it
        lines = analysis.format_summary(dict(_summary_stub(), **public)).splitlines()
        assert any(l.startswith("caution: the power law of u") for l in lines)


def _summary_stub():
    """What analyze() adds around catalog_statistics, for format_summary."""
    return {"run": "r.h5", "alpha": 15.0, "periodic_pulse": False, "figures": [],
            "stationarity": {k: {"pvalue": 0.5} for k in ("u", "T", "M0")}, "threshold_sensitivity": {}}


# ---------------------------------------------------------------------------
# summarize_run on a hand-made file with too few events
# ---------------------------------------------------------------------------

def test_summarize_run_few_events_returns_nans(tmp_path):
    path = tmp_path / "few.h5"
    with h5py.File(path, "w") as f:
        g = f.create_group("slip_sampling")
        for k, v in dict(delta_th=1e-8, dx=1e-3, v0=2e-3, mu=9e9, D=5e-7, L=1.0).items():
            g.attrs[k] = v
        g.create_dataset("crossing_time", data=np.zeros((1, 1000)))
        e = f.create_group("events")
        e.attrs["alpha"] = 15.0
        data = dict(t_start=[0.1, 0.2, 0.3], T=[1e-4] * 3, x_start=[0.1] * 3, L_s=[1.0, 0.2, 0.1],
                    u_mean=[1e-6, 1e-7, 5e-8], M0=[9e3, 1.8e2, 45.0], max_slip_rate=[0.1] * 3,
                    n_clusters=[1, 1, 1])
        for k, v in data.items():
            e.create_dataset(k, data=np.asarray(v))
    s = analysis.summarize_run(path)
    assert s["n_events"] == 3 and s["n_events_small"] == 2 and s["n_events_large"] == 1
    for k in ("small_exponent_u", "small_exponent_u_err", "lognormal_mu", "lognormal_sigma",
              "lognormal_ks_pvalue"):
        assert math.isnan(s[k]), k
    w = np.array([1e-6 * 1.0, 1e-7 * 0.2, 5e-8 * 0.1])
    assert s["slip_fraction_small"] == pytest.approx(w[1:].sum() / w.sum())
    assert s["slip_fraction_spanning"] == pytest.approx(w[0] / w.sum())
    assert s["periodic_pulse"] is False


# ---------------------------------------------------------------------------
# End to end on a run made by the CLI
# ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def quick_run(cli, tmp_path_factory):
    path = tmp_path_factory.mktemp("run") / "quick.h5"
    subprocess.run([str(cli), "run", str(REPO / "configs" / "quickstart.toml"),
                    "--set", "time.duration_transits=20", "--out", str(path), "--quiet"],
                   check=True, capture_output=True)
    return path


def _events_group(path):
    """/events of a file: every dataset's bytes and every attribute, for bitwise comparison."""
    with h5py.File(path, "r") as f:
        g = f["events"]
        data = {k: (g[k].dtype.str, g[k][()].tobytes()) for k in g}
        attrs = {k: np.asarray(v).tobytes() if not isinstance(v, (str, bytes)) else v for k, v in g.attrs.items()}
    return data, attrs


@pytest.mark.parametrize("into", ["run file", "--out file"])
def test_in_process_detection_equals_the_cli(quick_run, cli, tmp_path, into):
    """run_event_detection (bindings, in-process) writes the same /events as `slipstrip events`."""
    by_cli, by_bindings = tmp_path / "cli.h5", tmp_path / "bindings.h5"
    for copy in (by_cli, by_bindings):
        copy.write_bytes(quick_run.read_bytes())
    if into == "run file":
        r = subprocess.run([str(cli), "events", str(by_cli), "--alpha", "30"], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        assert analysis.run_event_detection(by_bindings, 30.0) == str(by_bindings)
        cli_file, bindings_file = by_cli, by_bindings
    else:
        cli_file, bindings_file = tmp_path / "cli_events.h5", tmp_path / "bindings_events.h5"
        r = subprocess.run([str(cli), "events", str(by_cli), "--alpha", "30", "--out", str(cli_file)],
                           capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        assert analysis.run_event_detection(by_bindings, 30.0, bindings_file) == str(bindings_file)
    cli_data, cli_attrs = _events_group(cli_file)
    data, attrs = _events_group(bindings_file)
    assert cli_attrs["n_events"] == attrs["n_events"] and len(cli_data["t_start"][1]) > 0
    assert data == cli_data
    assert attrs == cli_attrs


def test_in_process_detection_of_a_damaged_file_raises_without_hdf5_stack(quick_run, tmp_path, capfd):
    """From a worker thread (as in a scan), a truncated run file gives one
    exception naming the cause and no HDF5 error stack on stderr."""
    import threading
    damaged = tmp_path / "truncated.h5"
    damaged.write_bytes(quick_run.read_bytes()[:3000])
    errors = []

    def detect():
        try:
            analysis.run_event_detection(damaged, 15.0, tmp_path / "events.h5")
        except RuntimeError as err:
            errors.append(str(err))

    worker = threading.Thread(target=detect)
    worker.start()
    worker.join()
    assert len(errors) == 1 and "truncated" in errors[0]
    assert "HDF5-DIAG" not in capfd.readouterr().err


# min_slip_rate_v0 = 3: the creep filter (docs/events.md "Ignoring creep")
# applied by both, with the same comparison of delta_th against K v0 Delta t.
@pytest.mark.parametrize("min_slip_rate_v0", [0.0, 3.0])
def test_numpy_grouping_matches_cpp_catalog(quick_run, tmp_path, min_slip_rate_v0):
    out = tmp_path / "cat.h5"
    analysis.run_event_detection(quick_run, 15.0, out, min_slip_rate_v0)
    cat = analysis.read_catalog(out)
    with h5py.File(quick_run, "r") as f:
        ct = f["slip_sampling/crossing_time"][:]
        delta_th = float(f["slip_sampling"].attrs["delta_th"])
        v0 = float(f["slip_sampling"].attrs["v0"])
        dx = float(f["slip_sampling"].attrs["dx"])
    g = analysis.group_nodal_slips(ct, delta_th, v0, 15.0, min_slip_rate_v0=min_slip_rate_v0)
    assert cat["attrs"]["min_slip_rate_v0"] == min_slip_rate_v0
    assert (cat["attrs"]["n_nodal_slips_below_min_slip_rate"] > 0) == (min_slip_rate_v0 > 0)
    assert g.n_detected == cat["attrs"]["n_events_detected"]
    assert int(g.kept.sum()) == cat["attrs"]["n_events"]
    # The kept events' u_mean and L_s recomputed from the numpy labels agree with the
    # C++ catalog (both are counts times delta_th or dx: exact up to round-off).
    kept_ids = np.nonzero(g.kept)[0]
    for row, ev in enumerate(kept_ids):
        mask = g.label == ev
        k = np.count_nonzero(mask.any(axis=0))
        assert cat["L_s"][row] == pytest.approx(k * dx, rel=1e-12)
        assert cat["u_mean"][row] == pytest.approx(delta_th * mask.sum() / k, rel=1e-12)


# Slow tier for its cost (11 s of CPU, most of it six figures drawn as PNG and
# PDF): it checks the command's outputs; the detection and statistics it
# calls are checked in the fast tier by the tests above.
@pytest.mark.slow
def test_analyze_end_to_end(quick_run, tmp_path):
    run = tmp_path / "run.h5"
    run.write_bytes(quick_run.read_bytes())  # analyze --write-events adds /events to the run file
    out_dir = tmp_path / "out"
    assert analysis.main(["analyze", str(run), "--out-dir", str(out_dir), "--pdf", "--write-events"]) == 0
    summary = json.loads((out_dir / "summary.json").read_text())
    assert summary["n_events"] is not None and summary["n_events"] >= 0
    for name in ("space_time", "space_slip", "event_map", "pdfs", "stationarity", "threshold_sensitivity"):
        assert_figure(out_dir / f"{name}.png")
        assert (out_dir / f"{name}.pdf").is_file(), name
    assert set(summary["threshold_sensitivity"]) == {"8", "15", "30", "60"}
    assert summary["event_map"]["n_detected_numpy"] == summary["event_map"]["n_detected_cpp"]
    with h5py.File(run, "r") as f:
        assert "events" in f and f["events"].attrs["alpha"] == 15.0
    s = analysis.summarize_run(run)
    assert s["n_events"] == summary["n_events"]
    for key in ("n_events", "small_exponent_u", "small_exponent_u_err", "lognormal_mu", "lognormal_sigma",
                "lognormal_ks_pvalue", "slip_fraction_small", "slip_fraction_spanning", "periodic_pulse",
                "n_events_large", "n_events_small"):
        assert key in s, key
    assert isinstance(s["periodic_pulse"], bool)


def test_main_rejects_missing_file(tmp_path, capsys):
    assert analysis.main(["analyze", str(tmp_path / "nope.h5")]) == 2
    assert "nope.h5" in capsys.readouterr().err


def test_in_process_detection_waits_for_a_lock_held_for_a_moment(quick_run, tmp_path):
    """A reader in another process holds HDF5's lock on the run file for 0.5 s: the detection into
    that file (which HDF5 refuses while the lock is held) waits for it and then writes /events.  A
    scan's event step met such a moment under load and lost the run's catalog."""
    import sys
    import time
    run = tmp_path / "run.h5"
    run.write_bytes(quick_run.read_bytes())
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time, h5py\n"
                               f"f = h5py.File({str(run)!r}, 'r')\nprint('open', flush=True)\ntime.sleep(0.5)\n"
                               "f.close()\n"], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "open"
        start = time.monotonic()
        assert analysis.run_event_detection(run, 30.0) == str(run)
        waited = time.monotonic() - start
    finally:
        holder.wait(timeout=30)
    with h5py.File(run, "r") as f:
        assert f["events"].attrs["n_events"] > 0
    # It did wait for the holder (whose lock outlives the call's start by up to 0.5 s), and not much longer.
    assert 0.2 < waited < 5.0
