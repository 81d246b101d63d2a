"""Stationarity tests of event catalogs on synthetic catalogs of known kind.

Slip events come in clusters, so successive events are not independent.  A
stationary but clustered catalog must pass the block-permutation test at about
its nominal level, while the plain two-sample KS test (which assumes
independent events) rejects it far more often; a catalog whose event sizes
drift must be rejected by both."""
import math

import numpy as np

from slipstrip import analysis

N_REALISATIONS = 120
LEVEL = analysis.STATIONARITY_LEVEL


def clustered_catalog(rng, drift: float = 0.0, clusters: int = 150, per_cluster: int = 12):
    """Event times in [0, 1]: cluster centres uniform, events within 0.003 of
    them; log-size = the cluster's own level (N(0, 1)) + N(0, 0.3) scatter,
    plus `drift` x t (in units of the cluster-level spread)."""
    centres = rng.uniform(0.0, 1.0, clusters)
    level = rng.standard_normal(clusters)
    t = (centres[:, None] + rng.uniform(0.0, 0.003, (clusters, per_cluster))).ravel()
    logsize = (level[:, None] + 0.3 * rng.standard_normal((clusters, per_cluster))).ravel() + drift * t
    keep = t <= 1.0
    return t[keep], np.exp(logsize[keep])


def rejection_rates(drift: float, seed: int):
    rng = np.random.default_rng(seed)
    plain = blocks = 0
    for i in range(N_REALISATIONS):
        t, size = clustered_catalog(rng, drift)
        first, last = t < 0.2, t > 0.8
        from scipy import stats
        plain += stats.ks_2samp(size[first], size[last]).pvalue < LEVEL
        r = analysis.block_permutation_stationarity(t, {"u": size}, 0.0, 1.0, n_permutations=200, seed=i)
        blocks += r["u"]["pvalue"] < LEVEL
    return plain / N_REALISATIONS, blocks / N_REALISATIONS


def test_block_permutation_keeps_its_level_on_stationary_clustered_catalogs():
    plain, blocks = rejection_rates(drift=0.0, seed=1)
    # Binomial(120, 0.05): mean 6, 99.9 % upper quantile 15 events = 0.125; the
    # plain KS test, blind to the clustering, rejects several times more often.
    assert blocks <= 0.125
    assert plain >= 3 * LEVEL and plain > 2 * blocks


def test_block_permutation_detects_a_drift_in_event_sizes():
    # Sizes drift by 1.5 cluster-level standard deviations over the record.
    plain, blocks = rejection_rates(drift=1.5, seed=2)
    assert blocks >= 0.8 and plain >= 0.8


def test_block_permutation_is_reproducible_and_resolves_p():
    t, size = clustered_catalog(np.random.default_rng(3))
    a = analysis.block_permutation_stationarity(t, {"u": size}, 0.0, 1.0, n_permutations=300, seed=7)
    b = analysis.block_permutation_stationarity(t, {"u": size}, 0.0, 1.0, n_permutations=300, seed=7)
    assert a == b
    p = a["u"]["pvalue"]
    assert 1 / 301 <= p <= 1 and math.isclose(p * 301, round(p * 301))
    # The observed statistic is the KS distance of the first and last fifth of the blocks.
    first, last = t < 0.2, t >= 0.8
    from scipy import stats
    assert math.isclose(a["u"]["ks"], stats.ks_2samp(size[first], size[last]).statistic, rel_tol=1e-12)  # round-off of two CDF differences
