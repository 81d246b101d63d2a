"""slipstrip.fronts: wave speeds, the direction convention and the front-speed
measurement on synthetic arrival records with known speeds."""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO
from slipstrip import fronts

PMMA = fronts.Body(2.1e9, 0.35, 1170.0, "stress")
HOMALITE = fronts.Body(1.9e9, 0.34, 1230.0, "stress")


def test_rayleigh_speed_closed_form():
    # nu = 1/4 in plane strain (c_d^2 = 3 c_s^2): c_R^2/c_s^2 = 2 - 2/sqrt(3) exactly.
    body = fronts.Body(1.0, 0.25, 1.0, "strain")
    assert body.dilatational_wave_speed == pytest.approx(math.sqrt(3.0), rel=1e-15)
    # bisection to 1e-15 relative in c^2: rounding-level agreement
    assert fronts.rayleigh_speed(body) == pytest.approx(math.sqrt(2 - 2 / math.sqrt(3)), rel=1e-12)


def test_generalised_rayleigh_speed_matches_the_stability_theory():
    # The values docs/inplane_bodies.md quotes from the C++ stability theory
    # (zero of K_ser,xx, equal to the C++ Weertman root to 1e-10), printed to 0.01 m/s:
    # this independent Python root agrees to that print precision.
    assert fronts.generalised_rayleigh_speed(PMMA, HOMALITE) == pytest.approx(1182.45, abs=0.005)
    for ratio, expected in ((0.9, 1161.90), (0.8, 1065.12)):
        slow = fronts.Body(PMMA.shear_modulus * ratio**2, PMMA.poisson_ratio, PMMA.density, "stress")
        assert fronts.generalised_rayleigh_speed(PMMA, slow) == pytest.approx(expected, abs=0.005)
    # c_GR lies between the two Rayleigh speeds; a strong contrast (c_s ratio 0.6) has none
    c = fronts.generalised_rayleigh_speed(PMMA, HOMALITE)
    assert fronts.rayleigh_speed(HOMALITE) < c < fronts.rayleigh_speed(PMMA)
    slow = fronts.Body(PMMA.shear_modulus * 0.36, PMMA.poisson_ratio, PMMA.density, "stress")
    assert fronts.generalised_rayleigh_speed(PMMA, slow) is None
    # identical bodies: the limit, the Rayleigh speed
    assert fronts.generalised_rayleigh_speed(PMMA, PMMA) == fronts.rayleigh_speed(PMMA)


def test_positive_direction_is_the_slip_direction_of_the_more_compliant_body():
    # V = v_x,top - v_x,bottom > 0: the bottom body moves towards -x relative to the top.
    assert fronts.positive_direction(PMMA, HOMALITE) == -1   # Homalite (slower) at the bottom
    assert fronts.positive_direction(HOMALITE, PMMA) == +1   # Homalite on top
    assert fronts.positive_direction(PMMA, None) == +1       # rigid base: the top body is compliant
    assert fronts.positive_direction(PMMA, PMMA) == 0


def synthetic_record(length, nodes, center, speeds, dt, t0=1e-4, process=0.0):
    """Arrival times of two fronts leaving `center` at speeds {+1: c, -1: c}: exactly
    d = c (t - t0) (process = 0) or the crack-tip model v = c (1 - l/d), whose
    arrival time is t0 + (d + l ln(d - l))/c; rounded up to whole steps dt as the
    solver records them (first step with v above the threshold)."""
    x = np.arange(nodes) * length / nodes
    offset = (x - center + 0.5 * length) % length - 0.5 * length
    d = np.abs(offset)
    c = np.where(offset >= 0, speeds[+1], speeds[-1])
    if process > 0:
        t = t0 + (d + process * np.log(np.maximum(d - process, 1e-300))) / c
        t[d <= 2 * process] = np.nan  # inside the nucleation: no front of the model
    else:
        t = t0 + d / c
    return x, np.ceil(t / dt) * dt


def test_front_speeds_of_a_synthetic_record_with_known_speeds():
    length, nodes, dt = 1.0, 512, 3.6e-7
    # Centre near the end of the period: the -x front wraps around through x = L.
    x, t = synthetic_record(length, nodes, 0.05, {+1: 1182.45, -1: 950.0}, dt)
    branches = fronts.front_branches(x, t, 0.05, length)
    for sign, expected in ((+1, 1182.45), (-1, 950.0)):
        d, ta = branches[sign]
        assert d.max() == pytest.approx(0.5 * length, abs=length / nodes)
        speed = fronts.front_speed(d, ta, 0.1, 0.3)
        # Arrival times are rounded up to whole steps: an error of at most dt at each
        # end of a 0.2 m window (~1.7e-4 s) moves the slope by <= dt/span ~ 2e-3 relative;
        # least squares over ~100 nodes averages it down (measured 6e-5; 1e-3 allowed).
        assert speed == pytest.approx(expected, rel=1e-3)


def test_limiting_speed_of_an_accelerating_front():
    # v(d) = c (1 - l/d), l = 0.012 m (what the PMMA control run shows): the window
    # speed lags c, the 1/d fit recovers c.  Its model error: each segment's secant
    # speed is not v at the segment's mean d (second order in the segment width)
    # plus the rounding of arrivals to steps: measured 5.6e-4 relative; 2e-3 allowed.
    length, nodes, dt, c, ell = 1.0, 1024, 1.8e-7, 1233.8, 0.012
    x, t = synthetic_record(length, nodes, 0.5, {+1: c, -1: c}, dt, process=ell)
    d, ta = fronts.front_branches(x, t, 0.5, length)[+1]
    window_speed = fronts.front_speed(d, ta, 0.1, 0.3)
    assert window_speed < 0.96 * c  # the lag the model predicts (~0.94 c over 0.1-0.3 m)
    c_lim, rows = fronts.limiting_speed(d, ta, 0.1, 0.3)
    assert len(rows) == fronts.SEGMENTS
    assert c_lim == pytest.approx(c, rel=2e-3)


def test_front_speed_is_nan_where_the_front_never_got():
    d = np.array([0.01, 0.02, 0.03])
    t = np.array([1e-5, 2e-5, 3e-5])
    assert math.isnan(fronts.front_speed(d, t, 0.1, 0.3))
    c_lim, _ = fronts.limiting_speed(d, t, 0.1, 0.3)
    assert math.isnan(c_lim)
    # ... and null in the JSON summary (strict JSON has no NaN)
    assert json.loads(json.dumps(fronts._json_ready({"speed": c_lim, "rows": [(0.1, c_lim)]}),
                                 allow_nan=False)) == {"speed": None, "rows": [[0.1, None]]}


# --- runs of configs/examples/bimaterial_rupture.toml -------------------------

EXAMPLE = REPO / "configs" / "examples" / "bimaterial_rupture.toml"
MIRROR = ["--set", "bottom.body=mirror", "--set", "bottom.shear_modulus=2.1e9",
          "--set", "bottom.poisson_ratio=0.35", "--set", "bottom.density=1170"]


def run_example(cli, out, *overrides):
    r = subprocess.run([str(cli), "run", str(EXAMPLE), *overrides, "--out", str(out), "--quiet"],
                       capture_output=True, text=True, timeout=1800)
    assert r.returncode == 0, r.stderr
    return out


def test_identical_bodies_control_fronts_are_symmetric_and_tend_to_rayleigh(cli, tmp_path):
    # The control of the bimaterial example: two PMMA half-spaces (mirror pair, under a
    # second of CPU time at N = 256).  The measurement on a real run with a known answer.
    out = run_example(cli, tmp_path / "control.h5", *MIRROR, "--set", "geometry.nodes=256")
    png, js = tmp_path / "fronts.png", tmp_path / "fronts.json"
    r = subprocess.run([sys.executable, "-m", "slipstrip", "rupture-fronts", str(out), "--json", str(js),
                        "--plot", str(png)], capture_output=True, text=True, timeout=300,
                       env={**os.environ, "PYTHONPATH": str(REPO / "python")})
    assert r.returncode == 0, r.stderr
    assert png.stat().st_size > 0
    summary = json.loads(js.read_text())
    assert summary["positive_direction"] == 0 and summary["more_compliant_body"] is None
    c_r = fronts.rayleigh_speed(PMMA)
    assert summary["generalised_rayleigh_speed"] == pytest.approx(c_r, rel=1e-15)
    plus, minus = summary["fronts"]["+x"], summary["fronts"]["-x"]
    # Mirror symmetry about the nucleation centre (a node): the arrival times are whole
    # steps, so the two fronts give the same speeds (1e-9: rounding of the fits).
    assert plus["speed"] == pytest.approx(minus["speed"], rel=1e-9)
    # Sub-Rayleigh over the window 0.1-0.3 m and still accelerating (measured 1157.8 m/s
    # at N = 256, 1156.2 at 512, 1155.1 at 1024: 0.94 c_R).
    assert 0.9 * c_r < plus["speed"] < c_r
    # The 1/d model's limiting speed is the Rayleigh speed (1233.8 m/s): measured +1.4 %,
    # +0.2 %, +0.6 % at N = 256, 512, 1024; 2 % allowed (the scatter of a four-segment
    # extrapolation, not a discretisation trend).
    assert plus["limiting_speed_1_over_d"] == pytest.approx(c_r, rel=0.02)


@pytest.mark.slow
def test_bimaterial_rupture_prefers_the_direction_of_slip_of_the_more_compliant_body(cli, tmp_path):
    # The example as it is (N = 512, about a minute of CPU time).  Measured at N = 512
    # and N = 1024 (docs/bodies.md section 6) for every tolerance below.
    out = run_example(cli, tmp_path / "bimaterial.h5")
    s = fronts.rupture_fronts(str(out))
    assert s["more_compliant_body"] == "bottom" and s["positive_direction"] == -1
    c_gr = s["generalised_rayleigh_speed"]
    assert c_gr == pytest.approx(1182.45, abs=0.005)
    pos, neg = s["fronts"]["-x"], s["fronts"]["+x"]
    assert pos["role"] == "positive" and neg["role"] == "negative"
    # Both fronts crossed the window (0.1-0.3 m) below c_GR (measured 0.945 and 0.938 c_GR).
    assert pos["reached_distance"] > 0.3 and neg["reached_distance"] > 0.3
    assert 0.9 * c_gr < neg["speed"] < pos["speed"] < c_gr
    # The positive front is faster: measured 8.6 m/s (N = 512) and 8.2 m/s (N = 1024);
    # each speed moves by at most 1.1 m/s between the two grids, so half the measured
    # difference is several times the discretisation error.
    assert pos["speed"] - neg["speed"] > 4.0
    # ... and carries twice the slip rate (measured 1.92 and 2.15; > 1.5 allowed: peak
    # slip rates converge slowly, +20 % from N = 512 to 1024), with the normal stress
    # reduced at the positive front (min 0.77 and 0.73 sigma0) and hardly at the negative
    # one (0.96 sigma0 at both N): the bimaterial mechanism, not an artefact.
    assert pos["max_slip_rate"] > 1.5 * neg["max_slip_rate"]
    assert pos["min_normal_stress"] < 0.85e6 < 0.93e6 < neg["min_normal_stress"]
    # The positive front closes in on c_GR: over the last segment (0.25-0.3 m) 0.971 c_GR
    # (N = 512) and 0.967 c_GR (N = 1024), where the identical control is at 0.956 c_R;
    # 0.95 c_GR allowed (twice the change between the grids below the measured value).
    assert 0.95 * c_gr < pos["segments"][-1]["speed"] < c_gr
    # The negative front's 1/d-model limiting speed is c_GR: measured +0.35 % (N = 512),
    # +0.25 % (N = 1024); 1.5 % allowed, the model's scatter in the identical control
    # (+1.4 %, +0.2 %, +0.6 % of c_R at N = 256, 512, 1024).
    assert neg["limiting_speed_1_over_d"] == pytest.approx(c_gr, rel=0.015)
