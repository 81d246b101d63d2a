"""Quasi-static critical wavelength of antiplane bodies against closed forms
solved here (docs/stability.md, section 4).

Dropping inertia, the neutral wavenumber solves S(k, 0) = K_c, K_c = tau_v g_phi
- tau_phi g_v the friction's critical stiffness.  An antiplane strip does not bend:
its static stiffness (mu k / 2) coth(kH) is above the half-space's mu k / 2 and
above its long-wave limit mu / (2H), so the neutral k lies below the half-space
one and there is none when mu / (2H) >= K_c.  Pairs of different bodies use the
series stiffness of the two faces, each 2 x (mu k / 2) coth(kH) (a rigid base:
the top face alone).

The roots are found by scipy's brentq on the closed forms, K_c from Eq. S1 + the
regularised Eq. S2 written out here (not linearise_friction).  Tolerance: both
sides evaluate S0 and K_c to a few 1e-16 relative, and the root moves by that
divided by d ln S0 / d ln k = 1 - 2x / sinh 2x (x = kH, at least 0.04 for the
heights below), so ~1e-14; 1e-12 leaves room and is 1e3 times below the error
being fixed (the half-space value at H = 0.06 m is 43% off).
"""
import math
import subprocess

import pytest
from friction_oracles import eq_s1_critical_stiffness

brentq = pytest.importorskip("scipy.optimize").brentq

REL = 1e-12


@pytest.fixture(scope="module")
def ss(slipstrip_module):
    return slipstrip_module


def face_stiffness(mu, H, k):
    """2 x the antiplane strip's S(k, 0): mu k coth(kH), mu k for a half-space."""
    return mu * k if math.isinf(H) else mu * k / math.tanh(k * H)


def closed_form_wavelength(stiffness, K_c, k_max):
    """2 pi / k with stiffness(k) = K_c, stiffness increasing, below K_c as k -> 0."""
    k = brentq(lambda k: stiffness(k) - K_c, 1e-9 * k_max, k_max, xtol=1e-300, rtol=1e-15, maxiter=500)
    return 2.0 * math.pi / k


def reference_antiplane(ss, repo, overrides=None):
    return ss.load_config(repo / "configs" / "reference.toml", {"material.plane": "antiplane", **(overrides or {})})


def test_identical_antiplane_strips(ss, repo):
    cfg = reference_antiplane(ss, repo)
    mu = cfg.material.shear_modulus
    K_c = eq_s1_critical_stiffness(cfg)
    threshold = mu / (2.0 * K_c)  # 0.0529 m
    assert threshold == pytest.approx(0.0528657, rel=1e-6)
    half_space = ss.quasi_static_critical_wavelength(cfg.with_overrides({"geometry.height": "inf"}))
    assert half_space == pytest.approx(math.pi * mu / K_c, rel=1e-13)
    worst = 0.0
    for H in (0.054, 0.06, 0.1, 0.2, 0.5, 2.0):
        got = ss.quasi_static_critical_wavelength(cfg.with_overrides({"geometry.height": H}))
        # (mu k / 2) coth(kH) = K_c; above K_c at the half-space k = 2 K_c / mu
        expected = closed_form_wavelength(lambda k: 0.5 * face_stiffness(mu, H, k), K_c, 2.0 * K_c / mu)
        worst = max(worst, abs(got / expected - 1.0))
        assert got == pytest.approx(expected, rel=REL), H
        assert got > half_space
    print(f"identical antiplane strips: worst relative error {worst:.2e}")
    assert ss.quasi_static_critical_wavelength(cfg.with_overrides({"geometry.height": 0.06})) == pytest.approx(
        0.5845359, rel=1e-6)


@pytest.mark.parametrize("bottom", [
    {"bottom.body": "rigid"},
    {"bottom.body": "elastic", "bottom.shear_modulus": 36e9, "bottom.height": 0.8},
    {"bottom.body": "elastic", "bottom.shear_modulus": 36e9, "bottom.height": "inf"},
    {"bottom.body": "elastic", "bottom.shear_modulus": 2e9, "bottom.height": 0.3},
])
def test_antiplane_pairs_of_different_bodies(ss, repo, bottom):
    cfg = ss.load_config(repo / "configs" / "examples" / "antiplane_slider_on_stiff_base.toml", bottom)
    d = cfg.as_dict()
    mu = cfg.material.shear_modulus
    K_c = eq_s1_critical_stiffness(cfg)
    for H in (0.2, 0.4, "inf"):
        got = ss.quasi_static_critical_wavelength(cfg.with_overrides({"geometry.height": H}))
        Ht = math.inf if H == "inf" else H
        if bottom["bottom.body"] == "rigid":
            stiffness = lambda k: face_stiffness(mu, Ht, k)
        else:
            mu_b, H_b = d["bottom"]["shear_modulus"], float(d["bottom"]["height"])
            stiffness = lambda k: 1.0 / (1.0 / face_stiffness(mu, Ht, k) + 1.0 / face_stiffness(mu_b, H_b, k))
        # at most the softer face's stiffness, which exceeds K_c at its half-space k (times 2: coth > 1)
        k_max = 2.0 * K_c / min(mu, d["bottom"].get("shear_modulus") or mu) * 2.0
        expected = closed_form_wavelength(stiffness, K_c, k_max)
        assert got == pytest.approx(expected, rel=REL), (bottom, H, got / expected - 1.0)


def test_thin_antiplane_strip_has_no_unstable_wavelength(ss, repo, cli):
    cfg = reference_antiplane(ss, repo)
    threshold = cfg.material.shear_modulus / (2.0 * eq_s1_critical_stiffness(cfg))
    for H in (0.05, 0.999 * threshold):
        with pytest.raises(ValueError, match=r"H = [0-9.e-]+ m: no unstable wavelength; the antiplane strip's "
                           r"static stiffness .* exceeds mu/\(2H\)"):
            ss.quasi_static_critical_wavelength(cfg.with_overrides({"geometry.height": H}))
    # the dynamic Lc(H) says so too, naming the height
    with pytest.raises(ValueError, match=r"H = 0\.05 m: no unstable wavelength"):
        ss.critical_wavelength_vs_height(cfg, [0.05])
    r = subprocess.run([str(cli), "stability", str(repo / "configs" / "reference.toml"), "--set",
                        "material.plane=antiplane", "--height-range", "0.04:0.06:2"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode != 0
    assert "H = 0.04 m: no unstable wavelength" in r.stderr
    # Inertia softens the strip on the imaginary axis: at k -> 0, S(0, i omega_c) =
    # (mu / (2H)) x cot x with x = omega_c H / c_s, so the dynamic Lc exists down to
    # the H where that equals K_c (0.0520 m), a little below mu / (2 K_c).
    d = cfg.as_dict()
    lin = ss.linearise_friction(cfg)
    omega_c = math.sqrt(eq_s1_critical_stiffness(cfg) * abs(lin["state_rate_dstate"]) / lin["strength_dv"])
    c_s = math.sqrt(cfg.material.shear_modulus / d["material"]["density"])
    mu, K_c = cfg.material.shear_modulus, eq_s1_critical_stiffness(cfg)
    dynamic_threshold = brentq(lambda H: mu / (2 * H) * (omega_c * H / c_s) / math.tan(omega_c * H / c_s) - K_c,
                               0.5 * threshold, threshold)
    assert dynamic_threshold == pytest.approx(0.0519976, rel=1e-5)
    with pytest.raises(ValueError, match=r"no unstable wavelength"):
        ss.critical_wavelength_vs_height(cfg, [0.999 * dynamic_threshold])
    between = 1.001 * dynamic_threshold
    assert math.isfinite(ss.critical_wavelength_vs_height(cfg, [between])[0])
    with pytest.raises(ValueError, match=r"no unstable wavelength"):
        ss.quasi_static_critical_wavelength(cfg.with_overrides({"geometry.height": between}))
    # a strip on a rigid base is twice as stiff: mu/H
    rigid = cfg.with_overrides({"bottom.body": "rigid", "geometry.height": 0.1})
    with pytest.raises(ValueError, match=r"H = 0\.1 m on a rigid base: no unstable wavelength"):
        ss.quasi_static_critical_wavelength(rigid)
