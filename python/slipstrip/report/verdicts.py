"""Verdict rules of the report (stated in docs/reproduction.md) and the
formatting of values and verdicts."""
from __future__ import annotations

import math


def _finite(x) -> bool:
    try:
        return x is not None and math.isfinite(float(x))
    except (TypeError, ValueError):
        return False


# Rules of the verdicts (stated in the doc).
SIGMA_RULE = 2.0        # a value with an error agrees if |slipstrip - paper| <= 2 sigma
RELATIVE_RULE = 0.10    # an exact number (Lc, a stated percentage of Lc(inf), a friction slope) agrees within 10 %
FACTOR_RULE = 2.0       # "comparable to", "~ H", "approximately": agrees within a factor 2
ORDER_RULE = math.sqrt(10.0)  # O(x): agrees within a factor sqrt(10) (the same power of ten, rounded)
MAJORITY = 0.5          # a property the paper shows on one example event holds for more than half of such events
LOGNORMAL_LEVEL = 0.05  # a log-normal fit agrees unless its KS test rejects it at p < 5 %


def within_factor(x: float, factor: float = FACTOR_RULE) -> bool:
    """x within a factor `factor` of 1 (a ratio to the scale the paper names)."""
    return _finite(x) and 1.0 / factor <= x <= factor


def fmt(x, err=None, digits=3) -> str:
    if not _finite(x):
        return "n/a"
    s = f"{x:.{digits}g}"
    if err is not None:
        s += f" ± {err:.2g}" if _finite(err) else " ± n/a"
    return s


def shown(x: float, limit: float, digits: int = 1, fmt_: str = "f") -> str:
    """x printed with `digits` decimals (fmt_ "f") or significant digits ("g"),
    more if needed so that the printed number is on the same side of `limit`
    as x: a verdict never reads "differs (2.0 σ)" under a 2 σ rule."""
    if abs(x - limit) <= 1e-9 * abs(limit):  # at the limit up to round-off (1.1 / 1.0 - 1 is 10 %)
        x = limit
    for d in range(digits, digits + 6):
        s = f"{x:.{d}{fmt_}}"
        if (float(s) > limit) == (x > limit) and (float(s) < limit) == (x < limit):
            return s
    return f"{x:.{digits + 6}{fmt_}}"


def verdict_sigma(value, err, paper) -> str:
    if not (_finite(value) and _finite(err)):
        return "no value"
    d = value - paper
    k = abs(d) / err if err > 0 else math.inf
    ks = shown(k, SIGMA_RULE) if math.isfinite(k) else "inf"
    return (f"agrees ({ks} σ)" if k <= SIGMA_RULE else f"differs by {d:+.2g} ({ks} σ)")


def verdict_relative(value, paper) -> str:
    if not _finite(value):
        return "no value"
    r = value / paper - 1
    ps = shown(abs(r) * 100, RELATIVE_RULE * 100, 0)
    ps = ("+" if r >= 0 else "-") + ps + "%"
    # 1e-9: 1.1 / 1.0 - 1 is 0.10000000000000009 in floating point, which is 10 %.
    return f"agrees ({ps})" if abs(r) <= RELATIVE_RULE * (1 + 1e-9) else f"differs by {ps}"


def verdict_factor(ratio, rule: float = FACTOR_RULE) -> str:
    """ratio = slipstrip / paper scale; agrees within a factor `rule`."""
    if not _finite(ratio) or ratio <= 0:
        return "no value"
    ok = 1 / rule <= ratio <= rule
    rs = shown(ratio, rule if ratio >= 1 else 1 / rule, 2, "g")
    return f"agrees (ratio {rs})" if ok else f"differs (ratio {rs})"


def verdict_order(ratio) -> str:
    """O(x) claims: agrees within a factor sqrt(10)."""
    return verdict_factor(ratio, ORDER_RULE)


def xmin_sweep_cell(sweep: list[dict]) -> str:
    """The exponents of analysis.exponent_xmin_sweep, one per x_min."""
    if not sweep:
        return "n/a (too few events)"
    parts = [f"x_min = {fmt(f['xmin_factor'], digits=2)} x_opt: {fmt(f['exponent'], f['stderr'])} (n = {f['n']})"
             for f in sweep]
    lo, hi = min(f["exponent"] for f in sweep), max(f["exponent"] for f in sweep)
    return "; ".join(parts) + f"; range {fmt(lo)}-{fmt(hi)} (x_opt: the KS-optimal x_min)"


def verdict_xmin_sweep(sweep: list[dict], paper: float) -> str:
    """Agrees if the paper's value lies within the sweep's exponents widened by
    SIGMA_RULE of their statistical errors: the slope of a guide to the eye
    (no stated fit range) cannot be held to a tighter standard."""
    if not sweep:
        return "no value"
    lo = min(f["exponent"] - SIGMA_RULE * f["stderr"] for f in sweep)
    hi = max(f["exponent"] + SIGMA_RULE * f["stderr"] for f in sweep)
    if lo <= paper <= hi:
        return f"agrees within the fit-range systematic ({lo:.3g}-{hi:.3g})"
    return f"differs even allowing for the fit range ({lo:.3g}-{hi:.3g})"


def verdict_guide(exponent, err, sweep: list[dict], paper: float) -> str:
    """A power law drawn as a guide to the eye: the fit-range rule decides
    (`verdict_xmin_sweep`); the KS-optimal fit's distance in σ is added."""
    v = verdict_xmin_sweep(sweep, paper)
    if v == "no value":
        return v
    if _finite(exponent) and _finite(err) and err > 0:
        v += f"; the KS-optimal fit alone: {abs(exponent - paper) / err:.1f} σ"
    return v


def verdict_bool(ok, detail="") -> str:
    if ok is None:
        return "no value"
    return ("agrees" if ok else "differs") + (f" ({detail})" if detail else "")


def verdict_majority(n_ok: int, n: int, what: str) -> str:
    """A property the paper shows on an example event: agrees if it holds for
    more than MAJORITY of the events of that kind."""
    if n == 0:
        return "no value (no such event)"
    f = n_ok / n
    return verdict_bool(f > MAJORITY, f"{what} in {n_ok} of {n} ({f:.0%})")


def verdict_class(verdict: str) -> str:
    """agree / differ / not checkable (for the headline counts)."""
    v = verdict.strip().lower()
    if v.startswith("agrees"):
        return "agree"
    if v.startswith("differs"):
        return "differ"
    return "not checkable"


def verdict_beats_chance(observed: int, n: int, p_null: float, what: str) -> str:
    """Agrees if the observed fraction exceeds the chance fraction p_null by
    more than SIGMA_RULE binomial standard errors (of the chance fraction)."""
    if n == 0 or not _finite(p_null):
        return "no value (no such event)"
    f = observed / n
    sd = math.sqrt(max(p_null * (1 - p_null), 1e-12) / n)
    z = (f - p_null) / sd
    return verdict_bool(z > SIGMA_RULE, f"{what}: {observed} of {n} ({f:.0%}) against {p_null:.0%} by chance, "
                                        f"{z:+.1f} σ")
