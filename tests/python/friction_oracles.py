"""Closed forms of the paper's friction law used as oracles by several stability tests.

Written from the config's parameters alone (never from the code under test), once, so that two tests
checking different limits against the same critical stiffness cannot drift apart."""
import math


def eq_s1_critical_stiffness(cfg) -> float:
    """K_c = tau_v g_phi - tau_phi g_v [Pa/m] of Eq. S1 with the regularised aging law at v0
    (docs/stability.md section 4): tau_v = sigma0 a/(v0 + v*), g_phi = -r/D,
    tau_phi g_v = -sigma0 f0 b v0/(r D), r = sqrt(v0^2 + v*^2)."""
    d = cfg.as_dict()
    f = d["friction"]
    f0, a, b, D, v_star = f["f0"], f["a"], f["b"], f["characteristic_slip"], f["v_star"]
    v0 = d["loading"]["driving_velocity"]
    sigma0 = d["loading"]["normal_stress"]
    r = math.hypot(v0, v_star)
    return sigma0 / D * (f0 * b * v0 / r - a * r / (v0 + v_star))
