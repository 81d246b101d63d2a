"""The reproduction report types no number by hand (python/slipstrip/report/):
every number in its rows comes from the runs, the configs, the linear
stability, the paper's claims (claims.CLAIMS, the one place for the paper's
numbers, each with its place in the paper) or the report's named criteria,
which the rows print from the same constants the measurements use.

Two checks: (1) no string in the report's code holds a number with a unit
("10 v0", "0.9 L", "5 %", "0.2 m", "2 σ"): such a number is printed from a
constant instead; (2) the run descriptions of report.RUNS, which name the
configs' parameters in words, agree with the committed configs.

Run: PYTHONPATH=$PWD/python /usr/bin/python3 -m pytest -q tests/python/test_report_numbers.py
"""
import ast
import math
import re
import tomllib
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
REPORT = REPO / "python" / "slipstrip" / "report"
# A number followed by a unit or scale of the report's text.
NUMBER_WITH_UNIT = re.compile(
    r"(?<![\w.^/{])(\d+(?:\.\d+)?(?:e-?\d+)?)\s*(%|v0|v_0|L/c_s|L\b|H\b|dx\b|D\b|σ|sigma\b|c_d|c_s|mm\b|ms\b|m\b"
    r"|decades?\b|kg)")
# Notation, not a number: the wave-reflection time 2H/c_s of the paper.
NOTATION = re.compile(r"2H/c_s|mu/\(2H\)")
# The report's modules whose strings are row text, captions and labels (runs.py's
# run descriptions are checked against the configs below).
TEXT_MODULES = ["sections.py", "figures.py", "document.py", "measurements.py", "verdicts.py", "command.py"]


def _text_strings(path):
    """Every string constant of the module that is not a docstring (f-string parts included)."""
    tree = ast.parse(path.read_text())
    docstrings = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                docstrings.add(id(first.value))
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docstrings:
            yield node.lineno, node.value


@pytest.mark.parametrize("module", TEXT_MODULES)
def test_report_text_holds_no_number_typed_by_hand(module):
    found = []
    for line, text in _text_strings(REPORT / module):
        for match in NUMBER_WITH_UNIT.finditer(NOTATION.sub("", text)):
            found.append(f"{module}:{line}: {match.group(0)!r} in {text[:80]!r}")
    assert found == [], "numbers typed into the report's text:\n" + "\n".join(found)


def test_the_scan_finds_a_typed_number():
    # The pattern catches the kinds of number the report used to type.
    for typed in ("v > 10 v0", "L_s < 0.9 L", "at ≥ 90 % of them", "H = 0.2 m run", "by 2 σ", "after 10 L/c_s",
                  "within 4 dx", "at 0.2 D"):
        assert NUMBER_WITH_UNIT.search(NOTATION.sub("", typed)), typed
    assert not NUMBER_WITH_UNIT.search(NOTATION.sub("", "T ~ 2H/c_s, Fig. 3c, S10, log10(v/v0)"))


def _config(name):
    return tomllib.loads((REPO / "configs" / f"{name}.toml").read_text())


# Words of the run descriptions -> where the config holds that number.
DESCRIBED = {
    r"H = ([\d.e-]+) m": ("geometry", "height"),
    r"L = ([\d.e-]+) m": ("geometry", "length"),
    r"rho = ([\d.e-]+)": ("material", "density"),
    r"f0 = ([\d.e-]+)": ("friction", "f0"),
    r"\ba = ([\d.e-]+)": ("friction", "a"),
    r"\bb = ([\d.e-]+)": ("friction", "b"),
    r"first ([\d.e-]+) L/c_s": ("time", "duration_transits"),
    r"snapshots every ([\d.e-]+) s": ("output", "snapshot_interval"),
    r"initial noise ([\d.e-]+)": ("initial", "noise_amplitude"),
}


def test_run_descriptions_agree_with_the_configs():
    from slipstrip.report import RUNS
    checked = 0
    for name, description in RUNS.items():
        config = _config(name)
        for pattern, (section, key) in DESCRIBED.items():
            for match in re.finditer(pattern, description):
                assert float(match.group(1)) == float(config[section][key]), (name, match.group(0), config[section][key])
                checked += 1
    # "instead of 1e-3 (reference": the reference's noise.
    for name, description in RUNS.items():
        for match in re.finditer(r"instead of ([\d.e-]+) \(reference", description):
            assert float(match.group(1)) == float(_config("reference")["initial"]["noise_amplitude"]), name
            checked += 1
    # "c_s x 2" / "c_s / 2" of the density family: c_s = sqrt(mu/rho) against the reference's.
    rho_ref = float(_config("reference")["material"]["density"])
    for name, description in RUNS.items():
        for match in re.finditer(r"c_s (x|/) ([\d.]+)", description):
            ratio = math.sqrt(rho_ref / float(_config(name)["material"]["density"]))
            stated = float(match.group(2)) if match.group(1) == "x" else 1.0 / float(match.group(2))
            assert ratio == pytest.approx(stated, rel=1e-12), (name, match.group(0))  # exact ratios of densities
            checked += 1
    assert checked >= 20  # the descriptions do name numbers; the patterns found them
