"""The config schema seen from Python (config/config_schema.cpp): the key list,
Config.as_dict() built from it, and docs/config.md generated from it.

References: tomllib reading the resolved TOML text (an independent parser of
what to_toml writes), the defaults of an empty config, and the CLI's
`config-docs --check` on the committed docs.

Run: /usr/bin/python3 -m pytest tests/python/test_config_schema.py
"""
import math
import subprocess
import tomllib

import pytest

from conftest import REPO


@pytest.fixture(scope="module")
def ss(slipstrip_module):
    return slipstrip_module


def test_schema_lists_every_key_of_the_resolved_config(ss):
    from slipstrip.config import config_schema

    schema = config_schema()
    resolved = tomllib.loads(ss.load_config(None).to_toml())
    primary = {(k["section"], k["name"]) for k in schema if k["alternative_to"] is None}
    written = {(section, key) for section, keys in resolved.items() for key in keys}
    assert primary == written
    for k in schema:
        if k["alternative_to"] is None:
            assert k["default"] == resolved[k["section"]][k["name"]], k
        else:
            # dx, youngs_modulus, duration_transits resolve into their partner.
            assert (k["section"], k["alternative_to"]) in primary, k
            assert k["default"] is None
        assert k["help"], k
        if k["type"] == "choice":
            assert resolved[k["section"]][k["name"]] in k["choices"], k


def test_schema_ranges_are_the_validator_ranges(ss):
    from slipstrip.config import config_schema

    beta = next(k for k in config_schema() if (k["section"], k["name"]) == ("time", "beta"))
    assert beta["allowed"] == "0 < beta <= 0.4 (dt = beta dx / c_s)"
    with pytest.raises(ss.ConfigError, match=r"time\.beta = 0\.6 is out of range: expected "
                                             r"0 < beta <= 0\.4 \(dt = beta dx / c_s\)"):
        ss.load_config({"time": {"beta": 0.6}})


@pytest.mark.parametrize("source", [
    None,
    {"geometry": {"height": math.inf, "nodes": 16}, "time": {"beta": 0.3},
     "output": {"stations": [0.5, 1.0]}},
    {"geometry": {"nodes": 16},
     "friction": {"a": {"profile": "piecewise_linear", "x": [0.0, 4.0], "values": [0.005, 0.01]}}},
])
def test_as_dict_is_what_tomllib_reads_from_to_toml(ss, source):
    cfg = ss.load_config(source)
    assert cfg.as_dict() == tomllib.loads(cfg.to_toml())
    assert ss.load_config(cfg.as_dict()) == cfg


def test_docs_config_md_is_generated_from_the_schema(cli):
    r = subprocess.run([str(cli), "config-docs", "--check", str(REPO / "docs" / "config.md")],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
