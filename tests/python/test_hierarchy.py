"""Tests of python/slipstrip/hierarchy.py (the measurements behind the paper's
Fig. 2 event hierarchy, the split of p(u), the first event, the tip zone) on
synthetic data with known answers.

Run: /usr/bin/python3 -m pytest tests/python/test_hierarchy.py
"""
import math
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from scipy import stats

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "python"))
from slipstrip import hierarchy as hi  # noqa: E402

DTH = 1e-8


def constant_rate_crossings(rates, n_levels, stop_level=None):
    """crossing_time of nodes slipping at constant rates from t = 0: level j
    (slip (j+1) DTH) is reached at (j+1) DTH / rate; a node with stop_level
    stops there (NaN above, the column's tail)."""
    j = np.arange(1, n_levels + 1)[:, None]
    ct = j * DTH / np.asarray(rates, float)[None, :]
    if stop_level is not None:
        for node, lev in stop_level.items():
            ct[lev:, node] = np.nan
    return ct


def test_slip_history_of_constant_rates_is_exact():
    rates = np.array([1e-3, 2e-3, 5e-4, 3e-3])
    ct = constant_rate_crossings(rates, 400)
    hist = hi.SlipHistory(ct, DTH)
    t = np.array([1e-4, 7.3e-4, 1.1e-3])  # every node has crossed some levels, none all 400
    # Slip is linear in time between crossings, so constant rates are reproduced to round-off.
    assert np.allclose(hist.at(t), rates[None, :] * t[:, None], rtol=1e-12, atol=1e-20)
    grid = np.linspace(2e-4, 1.2e-3, 11)
    assert np.allclose(hist.velocity(grid), np.broadcast_to(rates, (10, 4)), rtol=1e-9)
    # Subset of nodes, and the module-level wrapper.
    assert np.allclose(hist.at(t, [1, 3]), rates[None, [1, 3]] * t[:, None], rtol=1e-12)
    assert np.allclose(hi.slip_at(ct, DTH, 1e-3), rates * 1e-3, rtol=1e-12)


def test_slip_history_of_a_band_with_an_offset_and_a_stopped_node():
    rates = np.array([1e-3, 2e-3, 1.5e-3])
    ct = constant_rate_crossings(rates, 1000, stop_level={1: 600})  # node 1 stops at slip 600 DTH
    full = hi.SlipHistory(ct, DTH)
    band = hi.SlipHistory(ct[100:], DTH, level_offset=100)
    t = np.array([1.5e-3, 2e-3])  # every node is above level 100 (slip >= 1.5e-3 s * 1e-3 m/s = 150 DTH)
    assert np.allclose(band.at(t), full.at(t), rtol=1e-12)
    # After node 1 stopped (t > 600 DTH / 2e-3 m/s = 3e-3 s) its slip stays at 600 DTH.
    assert full.at(4e-3)[1] == pytest.approx(600 * DTH, rel=1e-12)
    assert full.at(4e-3)[0] == pytest.approx(4e-6, rel=1e-12)


def test_sampling_band_holds_every_crossing_of_the_window(tmp_path):
    rates = np.array([1e-3, 1.2e-3, 0.8e-3, 1e-3])
    ct = constant_rate_crossings(rates, 5000)
    path = tmp_path / "run.h5"
    with h5py.File(path, "w") as f:
        g = f.create_group("slip_sampling")
        g.create_dataset("crossing_time", data=ct)
        g.attrs["v0"], g.attrs["delta_th"] = 1e-3, DTH
    band, off = hi.sampling_band(path, 2e-2, 2.1e-2, margin_levels=20)
    assert off > 0 and off + band.shape[0] < 5000  # a band, not the whole record
    hist = hi.SlipHistory(band, DTH, off)
    t = np.array([2e-2, 2.05e-2, 2.1e-2])
    assert np.allclose(hist.at(t), rates[None, :] * t[:, None], rtol=1e-12)


def test_crack_fit_recovers_an_elliptical_profile():
    dx = 2.5e-3
    x = 0.01 + np.arange(60) * dx        # the slip zone's nodes; its edges are dx/2 beyond them
    xc, h, A = 0.01 + 29.5 * dx, 30 * dx, 3e-6
    y = A * np.sqrt(np.maximum(0.0, h * h - (x - xc) ** 2))
    fit = hi.crack_fit(x, y)
    # The model is exact: R^2 = 1 and A is recovered to round-off.
    assert fit["r2"] == pytest.approx(1.0, abs=1e-12)
    assert fit["x_c"] == pytest.approx(xc, rel=1e-12) and fit["h"] == pytest.approx(h, rel=1e-12)
    assert fit["A"] == pytest.approx(A, rel=1e-12)
    # 5 % multiplicative noise keeps it crack-like (R^2 well above the report's 0.9).
    noisy = y * np.random.default_rng(0).lognormal(0, 0.05, y.size)
    assert hi.crack_fit(x, noisy)["r2"] > 0.95


def test_crack_fit_rejects_a_ramp_and_a_flat_top():
    # Slip piled up at one end of the zone (a pulse that stopped) and a flat-topped
    # (uniform) profile are not crack-like: R^2 below the report's 0.9.
    x = np.arange(50) * 2.5e-3
    assert hi.crack_fit(x, np.linspace(0.0, 1.0, 50))["r2"] < 0.9
    assert hi.crack_fit(x, np.r_[np.zeros(2), np.ones(46), np.zeros(2)] + 1e-3 * np.arange(50))["r2"] < 0.9


def test_density_split_finds_the_dip_between_power_law_and_hump():
    rng = np.random.default_rng(1)
    # Power law u^-2.45 on [0.04, 1] (inverse CDF) plus a log-normal hump at ln u ~ 1.4.
    a, lo, hi_ = 2.45, 0.04, 1.0
    q = rng.uniform(size=20000)
    s = 1 - a
    small = (lo ** s + q * (hi_ ** s - lo ** s)) ** (1 / s)
    large = rng.lognormal(1.4, 0.6, 4000)
    res = hi.density_split(np.concatenate([small, large]))
    # The exact density of ln u of the mixture, and its minimum between the two maxima.
    g = np.linspace(math.log(lo), 4, 4000)
    u = np.exp(g)
    pl = np.where(u <= hi_, u ** (1 - a) * s / (hi_ ** s - lo ** s), 0.0)
    dens = 20000 * pl + 4000 * stats.norm.pdf(g, 1.4, 0.6)
    inner = (g > math.log(0.06)) & (g < 1.4)
    true_split = math.exp(g[inner][np.argmin(dens[inner])])
    # The kernel density (Scott bandwidth ~0.2 in ln u) smooths the dip: ±0.3 in ln u.
    assert abs(math.log(res["split"] / true_split)) < 0.3, (res, true_split)
    assert res["hump"] == pytest.approx(math.exp(1.4 - 0.0), rel=0.35)


def test_density_split_of_a_plain_power_law_has_no_hump():
    rng = np.random.default_rng(2)
    q = rng.uniform(size=20000)
    s = 1 - 2.45
    x = (0.04 ** s + q * (1.0 - 0.04 ** s)) ** (1 / s)
    assert math.isnan(hi.density_split(x)["split"])


def _sampling_file(path, ct, v0=1e-3):
    with h5py.File(path, "w") as f:
        g = f.create_group("slip_sampling")
        g.create_dataset("crossing_time", data=ct)
        g.attrs["v0"], g.attrs["delta_th"] = v0, DTH


def test_first_event_extent(tmp_path):
    n = 40
    # Every node slips 30 levels in the first 3e-7 s (one burst), then, after a long
    # wait, nodes 0-9 slip again.
    ct = np.full((60, n), np.nan)
    ct[:30] = np.linspace(1e-8, 3e-7, 30)[:, None] + 1e-10 * np.arange(n)[None, :]
    ct[30:60, :10] = 1e-3 + np.linspace(1e-8, 3e-7, 30)[:, None]
    _sampling_file(tmp_path / "a.h5", ct)
    fe = hi.first_event(tmp_path / "a.h5", alpha=15.0, rows_per_read=8)
    assert fe["extent"] == 1.0 and fe["complete"] and fe["n_ns"] == 30 * n
    # Only the first half of the interface slips at first.
    ct2 = np.full((60, n), np.nan)
    ct2[:30, :20] = ct[:30, :20]
    ct2[:30, 20:] = 1e-3 + np.linspace(1e-8, 3e-7, 30)[:, None]
    _sampling_file(tmp_path / "b.h5", ct2)
    assert hi.first_event(tmp_path / "b.h5", alpha=15.0)["extent"] == 0.5


def test_tip_zone_measures_the_stress_breakdown_length():
    n, dx = 400, 2.5e-3
    x = np.arange(n) * dx
    front = 200
    tau = np.full(n, 1.0)
    # Peak of 1.5 at the tip, linear drop to 0.5 over 20 nodes behind it (tip moving to +x).
    tau[front] = 1.5
    behind = front - np.arange(1, 21)
    tau[behind] = 1.5 - np.arange(1, 21) / 20.0
    tau[: front - 20] = 0.5
    v = np.zeros(n)
    v[100: front + 1] = 1.0
    z = hi.tip_zone(x, tau, np.zeros(n), v, front, +1, D=1e-6, v_threshold=0.5)
    # 90 % of the drop of 1.0 is reached 18 nodes behind the peak.
    assert z["size"] == pytest.approx(18 * dx, abs=1e-12)
    # The mirror image for a tip moving to -x.
    zm = hi.tip_zone(x, tau[::-1].copy(), np.zeros(n), v[::-1].copy(), n - 1 - front, -1, D=1e-6, v_threshold=0.5)
    assert zm["size"] == pytest.approx(18 * dx, abs=1e-12)


def test_bilateral_then_pulses():
    n, nt, v0 = 200, 60, 1.0
    v = np.full((nt, n), 0.01)
    i0 = 100
    for k in range(nt):
        r = 2 * k  # fronts move 2 nodes per step
        if k < 10:
            v[k, i0 - r: i0 + r + 1] = 50.0  # bilateral crack, centre slipping
        else:
            for c in (i0 - r, i0 + r):       # two pulses of 8 nodes at the fronts
                lo_ = max(0, c - 4)
                v[k, lo_: min(n, c + 4)] = 50.0
    res = hi.bilateral_then_pulses(v, i0, v0, dx=1.0)
    assert res["found"] and res["center_steps"] == 10
    assert res["n_pulses"] == 2 and res["pulse_width_nodes"] == 8


def test_ring_helpers():
    m = np.zeros(20, bool)
    m[[18, 19, 0, 1]] = True
    assert hi.ring_segment(m, 0) == (18, 1)
    assert hi.ring_segment(m, 5) is None
    assert hi.ring_distance(19, 1, 20) == 2
    y = np.cos(2 * np.pi * np.arange(40) / 20)  # minima at 10 and 30
    assert list(hi.local_extrema(y, "min")) == [10, 30]
    assert list(hi.local_extrema(y, "max")) == [0, 20]
    assert hi.nearest_extremum_distance([10, 30], 36, 40) == 6
