"""Run configuration: load from a TOML file, TOML text or a Python dict, apply
overrides, and read the resolved values back as a dict.

All parsing and validation happens in C++ (config/config.cpp, from the key
table of config/config_schema.cpp), so errors carry
exactly the messages of the command-line program (e.g. the suggestion for a
misspelt key).  A dict is turned into TOML text here and then parsed by the
same C++ code.
"""
from __future__ import annotations

import json
import math
import os
import re
from typing import Any, Iterable, Mapping

from . import _slipstrip

__all__ = ["Config", "ConfigWarning", "load_config", "to_toml_text", "overrides_from", "config_schema"]


class ConfigWarning(UserWarning):
    """A valid config value that looks like a unit mistake or degrades the
    result (the plausibility rules of config/config_schema.cpp, docs/config.md
    "Warnings"): issued by slipstrip.run(), printed by `slipstrip run`."""

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _toml_key(key: str) -> str:
    key = str(key)
    return key if _BARE_KEY.match(key) else json.dumps(key)


def _toml_value(value: Any) -> str:
    """One TOML value (number, string, bool, array) as text."""
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):  # NumPy scalar
        try:
            value = value.item()
        except (TypeError, ValueError):
            pass
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)  # shortest text that reads back to the same double
    if isinstance(value, str):
        # A JSON string is a valid TOML basic string (same escapes).
        return json.dumps(value)
    if isinstance(value, os.PathLike):
        return json.dumps(os.fspath(value))
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    raise TypeError(f"cannot write {value!r} (type {type(value).__name__}) as a TOML value: "
                    "allowed are numbers, strings, booleans and lists of them")


def to_toml_text(data: Mapping[str, Any]) -> str:
    """Nested dict -> TOML text.  Top-level dicts become [sections] (nested
    dicts become [section.sub]); everything else is a key = value line."""
    lines: list[str] = []

    def emit(table: Mapping[str, Any], prefix: tuple[str, ...]) -> None:
        scalars = [(k, v) for k, v in table.items() if not isinstance(v, Mapping)]
        tables = [(k, v) for k, v in table.items() if isinstance(v, Mapping)]
        if prefix and (scalars or not tables):
            lines.append("[" + ".".join(_toml_key(p) for p in prefix) + "]")
        for k, v in scalars:
            lines.append(f"{_toml_key(k)} = {_toml_value(v)}")
        if prefix and scalars:
            lines.append("")
        for k, v in tables:
            emit(v, prefix + (str(k),))

    emit(data, ())
    return "\n".join(lines) + "\n"


def overrides_from(overrides: Mapping[str, Any] | Iterable[str] | str | None) -> list[str]:
    """Normalise overrides to the C++ form ["section.key=value", ...].

    Accepts a list of such strings, a single string, a flat dict
    {"geometry.nodes": 64} or a nested dict {"geometry": {"nodes": 64}}."""
    if overrides is None:
        return []
    if isinstance(overrides, str):
        return [overrides]
    if isinstance(overrides, Mapping):
        out: list[str] = []

        def walk(table: Mapping[str, Any], prefix: str) -> None:
            for k, v in table.items():
                path = f"{prefix}.{k}" if prefix else str(k)
                if isinstance(v, Mapping):
                    walk(v, path)
                else:
                    out.append(f"{path}={_toml_value(v)}")

        walk(overrides, "")
        return out
    return [str(o) for o in overrides]


def config_schema() -> list[dict[str, Any]]:
    """Every config key as declared in the C++ schema (config/config_schema.cpp):
    dicts with section, name, type, unit, default, allowed, help,
    alternative_to and choices, in the order of to_toml."""
    return _slipstrip.config_schema()


def _looks_like_toml_text(text: str) -> bool:
    # A path never contains a newline; a one-line TOML document has '=' or '['.
    return "\n" in text or "=" in text or text.strip().startswith("[") or text.strip() == ""


class Config(_slipstrip._Config):
    """A resolved, validated run configuration (a C++ SimulationConfig).

    Build it with Config.from_file / from_string / from_dict, or with
    load_config(source, overrides) which accepts any of those sources.
    Config() gives the defaults (Table S1 of the paper).
    """

    @classmethod
    def _wrap(cls, native: _slipstrip._Config) -> "Config":
        if isinstance(native, cls):
            return native
        c = cls()
        c._assign(native)
        return c

    @classmethod
    def from_file(cls, path: str | os.PathLike, overrides=None) -> "Config":
        return cls._wrap(_slipstrip.load_config_file(os.fspath(path), overrides_from(overrides)))

    @classmethod
    def from_string(cls, toml_text: str, overrides=None) -> "Config":
        return cls._wrap(_slipstrip.load_config_string(toml_text, overrides_from(overrides)))

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], overrides=None) -> "Config":
        if not isinstance(data, Mapping):
            raise TypeError(f"Config.from_dict: data of type {type(data).__name__} is not a mapping: pass a "
                            "dict of sections such as {'geometry': {'nodes': 256}} (or Config() for the defaults)")
        return cls.from_string(to_toml_text(data), overrides)

    @property
    def toml(self) -> str:
        """The resolved config as TOML text (every key filled in)."""
        return self.to_toml()

    def as_dict(self) -> dict[str, dict[str, Any]]:
        """The resolved config as a nested dict {section: {key: value}} (a fresh copy),
        built from the config schema (config/config_schema.cpp): the same values
        tomllib reads from to_toml()."""
        return self._as_dict()

    def __getitem__(self, section: str) -> dict[str, Any]:
        return self.as_dict()[section]

    def warnings(self) -> list[str]:
        """The plausibility warnings of this config (docs/config.md, "Warnings"); [] when none."""
        return list(_slipstrip.plausibility_warnings(self))

    def run_header(self) -> str:
        """What a run of this config will cost and its warnings, as `slipstrip run` prints them."""
        return _slipstrip.run_header(self)

    def with_overrides(self, overrides) -> "Config":
        """A new Config: this one with overrides applied (and validated)."""
        return Config.from_string(self.to_toml(), overrides)

    @property
    def shear_wave_speed(self) -> float:
        """c_s = sqrt(mu / rho) [m/s]"""
        return self.material.shear_wave_speed

    @property
    def length_transit_time(self) -> float:
        """L / c_s [s]: the time unit of the paper's figures"""
        return self.length / self.material.shear_wave_speed

    # A resolved Config is read-only: its sections are validated together (a
    # density alone could contradict a Young's modulus given elsewhere), so a
    # change goes through the same parser as a file, via with_overrides().
    # Without this, `cfg.material.density = 0` would change a temporary copy
    # of the C++ struct and silently do nothing.
    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(_read_only_message(name, value))

    @property
    def material(self) -> _FrozenMaterial:
        """The elastic material (read-only; see with_overrides)."""
        return _FrozenMaterial(super().material)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, _slipstrip._Config):
            return NotImplemented
        return self.to_toml() == other.to_toml()

    __hash__ = None  # mutable C++ object underneath

    def __reduce__(self):
        # Picklable (e.g. for multiprocessing) through its exact TOML text.
        return (Config.from_string, (self.to_toml(),))

    def __repr__(self) -> str:
        return (f"Config(L={self.length!r} m, H={self.height!r} m, N={self.nodes}, "
                f"v0={self.driving_velocity!r} m/s, duration={self.duration!r} s)")


def _read_only_message(name: str, value: Any) -> str:
    return (f"a resolved Config is read-only (cannot set {name} = {value!r}): "
            f"use cfg.with_overrides({{'{name}': {value!r}}}) for a new, validated Config")


class _FrozenMaterial(_slipstrip.ElasticMaterial):
    """The material of a resolved Config: an ElasticMaterial (so it can be
    passed to strip_response and the other functions that take one) whose
    fields cannot be set."""

    _FIELDS = ("shear_modulus", "poisson_ratio", "density", "plane")

    def __init__(self, native: _slipstrip.ElasticMaterial) -> None:
        super().__init__()
        for name in self._FIELDS:
            object.__setattr__(self, name, getattr(native, name))

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(_read_only_message(f"material.{name}", value))

    def copy(self) -> _slipstrip.ElasticMaterial:
        """A mutable ElasticMaterial with the same fields."""
        return _slipstrip.ElasticMaterial(**{n: getattr(self, n) for n in self._FIELDS})


def load_config(source=None, overrides=None) -> Config:
    """A Config from any source, with overrides applied:

    * None                      -> the defaults;
    * Config                    -> a copy (overrides applied on top);
    * dict                      -> TOML sections, e.g. {"geometry": {"nodes": 256}};
    * pathlib.Path              -> a TOML file;
    * str                       -> TOML text if it contains a newline, '=' or
                                   starts with '[' (or is empty), else a file path.

    overrides: list of "section.key=value" strings, or a (flat or nested) dict.
    Raises slipstrip.ConfigError (a ValueError) with the C++ message."""
    if source is None:
        return Config.from_string("", overrides)
    if isinstance(source, _slipstrip._Config):
        return Config.from_string(source.to_toml(), overrides)
    if isinstance(source, Mapping):
        return Config.from_dict(source, overrides)
    if isinstance(source, os.PathLike):
        return Config.from_file(source, overrides)
    if isinstance(source, str):
        if _looks_like_toml_text(source):
            return Config.from_string(source, overrides)
        return Config.from_file(source, overrides)
    raise TypeError(f"config source of type {type(source).__name__} is not supported: "
                    "pass a path, TOML text, a dict or a Config")
