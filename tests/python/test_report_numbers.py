"""The reproduction report types no number by hand (python/slipstrip/report/):
every number in its rows comes from the runs, the configs, the linear
stability, the paper's claims (claims.CLAIMS, the one place for the paper's
numbers, each with its place in the paper) or the report's named criteria,
which the rows print from the same constants the measurements use.

Two checks: (1) no string in the report's code holds a number with a unit
("10 v0", "0.9 L", "5 %", "0.2 m", "2 σ"): such a number is printed from a
constant instead; (2) the run list's descriptions (report.run_description:
the figure a run reproduces, from report.RUNS, then H, L and what else its
config changes from configs/reference.toml) print every number from the
committed configs and change with them, and the figure is the one the
config's header comment names.

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
    r"D = ([\d.e-]+) m": ("friction", "characteristic_slip"),
    r"duration ([\d.e-]+) L/c_s": ("time", "duration_transits"),
    r"duration ([\d.e-]+) s\b": ("time", "duration"),
    r"snapshots every ([\d.e-]+) s": ("output", "snapshot_interval"),
    r"initial noise ([\d.e-]+)": ("initial", "noise_amplitude"),
    r"relative amplitude ([\d.e-]+)": ("initial", "local_amplitude"),
    r"at x = ([\d.e-]+) m": ("initial", "local_center"),
    r"width ([\d.e-]+) m": ("initial", "local_width"),
}
# A number in a description: every one must be matched by a pattern above.
ANY_NUMBER = re.compile(r"(?<![\w.^])-?\d+(?:\.\d+)?(?:e-?\d+)?(?![\w.])")
# Figure numbers of the paper are names, not values.
FIGURE_NAMES = re.compile(r"Figs?\. (?:S?\d+[a-d]?(?:-S?\d+)?(?:, )?)+")


def test_run_descriptions_agree_with_the_configs():
    from slipstrip.report import RUNS, run_description
    checked = 0
    for name in RUNS:
        description, config = run_description(name), _config(name)
        numbers = [m.span() for m in ANY_NUMBER.finditer(FIGURE_NAMES.sub(lambda m: "#" * len(m.group(0)),
                                                                           description))]
        matched = set()
        for pattern, (section, key) in DESCRIBED.items():
            for match in re.finditer(pattern, description):
                assert float(match.group(1)) == float(config[section][key]), (name, match.group(0), config[section][key])
                matched.add(match.span(1))
                checked += 1
        # "instead of the reference's 1e-3": the reference's noise.
        for match in re.finditer(r"instead of the reference's ([\d.e-]+)", description):
            assert float(match.group(1)) == float(_config("reference")["initial"]["noise_amplitude"]), name
            matched.add(match.span(1))
            checked += 1
        # "c_s x 2" / "c_s / 2" of the density family: c_s = sqrt(mu/rho) against the reference's.
        for match in re.finditer(r"c_s (x|/) ([\d.]+)", description):
            ratio = math.sqrt(float(_config("reference")["material"]["density"]) / float(config["material"]["density"]))
            stated = float(match.group(2)) if match.group(1) == "x" else 1.0 / float(match.group(2))
            assert ratio == pytest.approx(stated, rel=1e-12), (name, match.group(0))  # exact ratios of densities
            matched.add(match.span(2))
            checked += 1
        unmatched = [description[a:b] for a, b in numbers if (a, b) not in matched]
        assert unmatched == [], (name, description, unmatched)
    assert checked >= 40  # the descriptions do name numbers; the patterns found them


def test_run_descriptions_follow_the_configs(tmp_path):
    """The numbers of a description come from the config: change the config and
    the description changes with it."""
    from slipstrip.report import run_description
    for name in ("reference", "fig3c_H02"):
        text = (REPO / "configs" / f"{name}.toml").read_text()
        (tmp_path / f"{name}.toml").write_text(text)
    edited = (tmp_path / "fig3c_H02.toml").read_text().replace("height = 0.2", "height = 0.3", 1)
    assert edited != (tmp_path / "fig3c_H02.toml").read_text()
    (tmp_path / "fig3c_H02.toml").write_text(edited.replace("[friction]", "[friction]\nf0 = 0.25", 1)
                                             if "f0 =" not in edited else edited.replace("f0 = 0.28", "f0 = 0.25", 1))
    assert "H = 0.2 m" in run_description("fig3c_H02")
    shown = run_description("fig3c_H02", configs=tmp_path)
    assert "H = 0.3 m" in shown and "f0 = 0.25" in shown and "H = 0.2 m" not in shown, shown
    assert run_description("reference", configs=tmp_path) == run_description("reference")


def test_run_roles_name_the_figure_of_the_config_header():
    """RUNS names what each run reproduces; its first figure is the one the
    config's header comment names (the noise run: the remark it names)."""
    from slipstrip.report import RUNS
    for name, role in RUNS.items():
        header = " ".join(line.lstrip("# ") for line in (REPO / "configs" / f"{name}.toml").read_text().splitlines()
                          if line.startswith("#"))
        figure = re.match(r"Fig\. S?\d+[a-d]?", role)
        assert (figure.group(0) if figure else role.split(",")[0].removeprefix("the ")) in header, (name, role)
