"""Seeded fuzz corpus of the slipstrip CLI (run by
tests/python/test_fuzz.py, described in docs/reliability.md, "Fuzz corpus").

The generator is pure: `generate(repo, layout, seed)` returns the same list of
`Case`s for the same seed, base configs and run-file layout (the base run file
is itself bitwise reproducible).  Three families:

* ``config``: mutated copies of configs/quickstart.toml and
  configs/reference.toml (deleted, duplicated, renamed keys and sections,
  wrong types, extreme numbers, truncated files, binary garbage, empty file,
  very long lines, deep nesting) and special paths (a directory, a missing
  file, /dev/zero, /dev/null, a FIFO, a symlink to a directory);
* ``override``: `--set` overrides with bad keys, values and syntax (and a few
  bad CLI options) on top of the two base configs;
* ``runfile``: damaged copies of a small run file given to `slipstrip events`,
  `python3 -m slipstrip analyze` and `python3 -m slipstrip export`: truncated
  files, missing groups, datasets and attributes, attributes of the wrong
  shape or dtype, NaN / negative / infinite crossing times;
* ``nodefile``: friction node files (`profile = "node_file"`) holding a 20 MB
  line, binary bytes, UTF-16, NUL bytes, terminal escapes, too few values,
  non-finite values, or that are not files at all;
* ``outpath``: output paths that name an input, an existing file, a directory,
  a dangling symbolic link, a missing directory, or a left-over restart point,
  for every command that writes (`run`, `events`, `stability`, `transition`,
  `plot`, `analyze`, `export`);
* ``restart``: damaged restart points given to `slipstrip run --resume`:
  edited time, step and next output times (with and without their checksum
  repaired), flipped bits in every dataset, deleted attributes, truncated or
  foreign files, a directory, /dev/zero, a dangling link and a FIFO in its
  place.

Every message, of every family, must be one printable line of at most
MAX_MESSAGE_BYTES bytes (io/messages.hpp plus the command's prefix).

Every case that reaches a time loop is capped to a few time steps on a tiny
grid: `--set geometry.nodes=16 --set time.duration_transits=0.05` (about 3
steps) is added unless the mutation targets that very key, in which case the
values drawn for it are either invalid or small.

A case is described only by data (bytes to write, argv with placeholders,
damage operations); the test materialises and runs it.
"""
from __future__ import annotations

import signal
import random
import re
from dataclasses import dataclass, field
from pathlib import Path

SEED = 20240515
BASES = ("configs/quickstart.toml", "configs/reference.toml")
CAP_NODES = ("--set", "geometry.nodes=16")
CAP_DURATION = ("--set", "time.duration_transits=0.05")

# Placeholders in argv, filled in by the runner.
CLI, CONFIG, WORK, RUNFILE = "{cli}", "{config}", "{work}", "{runfile}"


@dataclass
class Case:
    ident: str                 # e.g. "config-0042"
    family: str                # "config" | "override" | "runfile" | "nodefile" | "outpath" | "restart"
    kind: str                  # the mutation, e.g. "extreme:geometry.height=1e308"
    argv: list                 # command line after the executable, with placeholders
    python: bool = False       # run as /usr/bin/python3 -m slipstrip ... (else the C++ CLI)
    config_bytes: bytes | None = None   # written to {config}
    config_special: str | None = None   # "directory", "missing", "fifo", "symlink_dir", or a device path
    base_run: str | None = None         # "plain" | "events": which base run file to copy to {runfile}
    damage: list = field(default_factory=list)  # operations applied to {runfile} (h5py)
    names: tuple = ()          # an exit-2 message must name one of these (key, section, option, attribute)
    path_ok: bool = False      # ... or, for damage without a key (truncation, garbage), the input's path
    files: dict = field(default_factory=dict)   # {name in {work}: bytes, or "directory", "fifo", "->TARGET"}
    restart_damage: list = field(default_factory=list)  # operations applied to {runfile}.restart (h5py)
    restart_special: str | None = None  # the restart point replaced by "directory", "fifo", "->TARGET", bytes
    # What the case must end in, where that is known: "refused" (exit 2: the
    # input is damaged or the output forbidden; a resume of a damaged restart
    # point that exits 0 would be a silently wrong run) or "completed" (exit 0:
    # valid input).  None: any passing class.
    expect: str | None = None


# ---------------------------------------------------------------------------
# TOML helpers
# ---------------------------------------------------------------------------

KEY_LINE = re.compile(r"^(\s*)([A-Za-z_][A-Za-z0-9_]*)(\s*=\s*)([^#\n]*?)(\s*(#.*)?)$")
SECTION_LINE = re.compile(r"^\s*\[([A-Za-z_]+)\]")


def key_lines(text: str):
    """[(line index, section, key, value text)] of the `key = value` lines."""
    out, section = [], ""
    for i, line in enumerate(text.split("\n")):
        m = SECTION_LINE.match(line)
        if m:
            section = m.group(1)
            continue
        m = KEY_LINE.match(line)
        if m and section:
            out.append((i, section, m.group(2), m.group(4)))
    return out


def section_lines(text: str):
    return [(i, SECTION_LINE.match(l).group(1)) for i, l in enumerate(text.split("\n")) if SECTION_LINE.match(l)]


def replace_value(text: str, index: int, value: str) -> str:
    lines = text.split("\n")
    m = KEY_LINE.match(lines[index])
    lines[index] = f"{m.group(1)}{m.group(2)}{m.group(3)}{value}{m.group(5) or ''}"
    return "\n".join(lines)


# Every key of docs/config.md, for renames into other sections and for overrides.
ALL_KEYS = {
    "geometry": ["length", "height", "nodes", "dx"],
    "material": ["shear_modulus", "youngs_modulus", "poisson_ratio", "density", "plane"],
    "loading": ["driving_velocity", "normal_stress"],
    "friction": ["law", "f0", "a", "b", "characteristic_slip", "v_star", "phi_star"],
    "state": ["law"],
    "interface": ["law", "slip_amplitude", "mode", "profile", "rise_time", "stress_amplitude",
                  "pulse_center", "pulse_width", "load_pulse_amplitude"],
    "initial": ["noise_amplitude", "noise_seed", "noise_modes", "sine_amplitude", "sine_mode", "local_amplitude",
                "local_center", "local_width"],
    "time": ["beta", "duration", "duration_transits", "history"],
    "output": ["timeseries_interval", "snapshot_interval", "snapshot_slip_increment", "delta_th",
               "flush_interval", "stations", "station_interval", "front_slip_rate"],
}
FLAT_KEYS = [f"{s}.{k}" for s, keys in ALL_KEYS.items() for k in keys]
STRING_KEYS = {"material.plane", "friction.law", "state.law", "interface.law", "interface.profile",
               "time.history"}

EXTREME_NUMBERS = ["0", "-0.0", "-1", "1e-300", "5e-324", "-5e-324", "1e308", "-1e308", "1.7976931348623157e308",
                   "inf", "-inf", "+inf", "nan", "-nan", '"inf"', '"nan"', '"-inf"', '"1e308"',
                   "9223372036854775807", "-9223372036854775808", "18446744073709551616",
                   "99999999999999999999999999999", "1e400", "-1e400", "0x7fffffffffffffff", "0o777",
                   "0b1010", "1_000", "2", "0.5", "7", "3.7", "1e-12", "1e-6", "1e13", "1e6"]
WRONG_TYPES = ['"text"', '""', "true", "false", "[1, 2]", "[]", "[[1.0]]", "{ a = 1 }", "{}",
               "1979-05-27", "07:32:00", "1979-05-27T07:32:00Z", "'single'", '"""multi\nline"""',
               '"\\u0000"', '"\\uD800"', '"strain"', '"slip"']
# Keys whose valid values cost a lot of steps or nodes: keep their draws invalid or small.
NODE_KEYS = {"geometry.nodes", "geometry.dx"}
DURATION_KEYS = {"time.duration", "time.duration_transits"}
SAFE_NODE_VALUES = ["0", "-1", "7", "8", "9", "17", "16777217", "9223372036854775807", "1e308", "5e-324",
                    "nan", "inf", '"16"', "16.0", "-16", "0.03125", "0.3", "1e-300", "1e308", "0.0"]
SAFE_DURATION_VALUES = ["0", "-1", "1e-300", "5e-324", "1e308", "6.5e12", "inf", "nan", '"1e-3"', "true",
                        "1e-12", "1e-9", "2e-6", "1e-5", "0.05", "9223372036854775807", "-inf", "[1.0]"]


def draw_value(rng: random.Random, flat_key: str) -> str:
    if flat_key in NODE_KEYS:
        return rng.choice(SAFE_NODE_VALUES)
    if flat_key in DURATION_KEYS:
        return rng.choice(SAFE_DURATION_VALUES)
    pool = EXTREME_NUMBERS + WRONG_TYPES
    if flat_key in STRING_KEYS:
        pool = pool + ['"paper"', '"PAPER"', '"aging "', '"slp"', '"stress"', '"modal"', '"block"', '"free"',
                       '"prescribed_slip"', '"x" ', '"' + "a" * 5000 + '"']
    if flat_key == "output.stations":
        pool = pool + ["[0.1, 1e308]", "[nan]", "[-0.1]", "[0.5]", "[0.0, 0.0]", "[inf]", '["a"]', "[[0.1]]",
                       "[" + ", ".join(["0.01"] * 2000) + "]", "[1e-300]", "[5e-324, 0.1]"]
    return rng.choice(pool)


def caps_for(flat_keys) -> list:
    argv = []
    if not any(k in NODE_KEYS for k in flat_keys):
        argv += CAP_NODES
    if not any(k in DURATION_KEYS for k in flat_keys):
        argv += CAP_DURATION
    return argv


def run_argv(extra=()) -> list:
    return ["run", CONFIG, *extra, "--out", WORK + "/out.h5", "--quiet"]


# ---------------------------------------------------------------------------
# Family 1: mutated config files
# ---------------------------------------------------------------------------

def _config_cases(rng: random.Random, bases: dict, n: int) -> list:
    cases = []

    def add(kind, data, flat_keys=(), names=(), special=None, extra=()):
        argv = run_argv([*caps_for(flat_keys), *extra])
        cases.append(Case(ident=f"config-{len(cases):04d}", family="config", kind=kind, argv=argv,
                          config_bytes=data, config_special=special,
                          names=tuple(names), path_ok=not names))

    # Fixed special inputs.
    add("empty file", b"")
    add("whitespace only", b"  \n\t\n\n")
    add("comment only", b"# nothing here\n")
    add("directory", None, special="directory")
    add("missing file", None, special="missing")
    add("symlink to a directory", None, special="symlink_dir")
    add("FIFO", None, special="fifo")
    add("/dev/zero", None, special="/dev/zero")
    add("/dev/null", None, special="/dev/null")
    add("2 MiB of comment (over the 1 MiB limit)", b"#" + b"x" * (2 << 20) + b"\n")
    add("1 MiB + 1 byte", b"#" + b"x" * (1 << 20) + b"\n")
    for name, text in bases.items():
        data = text.encode()
        add(f"{name}: 200 KB comment line", data + b"#" + b"y" * 200_000 + b"\n")
        add(f"{name}: 100k-character key", data + b"\n[geometry]\n" + b"k" * 100_000 + b" = 1\n",
            names=("k" * 64,))
        add(f"{name}: 100k-digit number", data.replace(b"noise_seed = 1", b"noise_seed = 1" + b"0" * 100_000),
            flat_keys=("initial.noise_seed",), names=("initial.noise_seed",))
        add(f"{name}: 100k-character string", data.replace(b'law = "aging"', b'law = "' + b"a" * 100_000 + b'"'),
            names=("state.law",))
        add(f"{name}: 10000-deep nested array", data + b"\n[output]\nstations = " + b"[" * 10_000 +
            b"]" * 10_000 + b"\n", names=("output.stations", "stations"))
        add(f"{name}: 10000-deep inline table", data + b"\n[output]\nstations = " + b"{a=" * 10_000 +
            b"1" + b"}" * 10_000 + b"\n", names=("output.stations", "stations"))
        add(f"{name}: CRLF line ends", data.replace(b"\n", b"\r\n"))
        add(f"{name}: UTF-8 BOM", b"\xef\xbb\xbf" + data)
        add(f"{name}: UTF-16", text.encode("utf-16"))
        add(f"{name}: NUL after every line", data.replace(b"\n", b"\x00\n"))

    kinds = ["delete", "duplicate", "rename", "move", "wrong_type", "extreme", "extreme", "truncate",
             "garbage", "insert_garbage", "delete_section", "duplicate_section", "rename_section", "two_values"]
    while len(cases) < n:
        name = rng.choice(sorted(bases))
        text = bases[name]
        keys = key_lines(text)
        kind = rng.choice(kinds)
        lines = text.split("\n")
        if kind in ("delete", "duplicate", "rename", "move", "wrong_type", "extreme"):
            i, section, key, value = rng.choice(keys)
            flat = f"{section}.{key}"
            if kind == "delete":
                del lines[i]
                add(f"{name}: delete {flat}", "\n".join(lines).encode(), names=(flat,))
            elif kind == "duplicate":
                lines.insert(i + 1, lines[i])
                add(f"{name}: duplicate {flat}", "\n".join(lines).encode(), names=(flat, key))
            elif kind == "rename":
                new = _typo(rng, key)
                lines[i] = lines[i].replace(key, new, 1)
                add(f"{name}: rename {flat} -> {section}.{new}", "\n".join(lines).encode(),
                    flat_keys=(flat,), names=(section + "." + new.strip('"'),))
            elif kind == "move":
                other = rng.choice([s for s in ALL_KEYS if s != section] + [""])
                del lines[i]
                if other:
                    lines += [f"[{other}]", f"{key} = {value}"]
                    new_flat = f"{other}.{key}"
                else:
                    lines.insert(0, f"{key} = {value}")
                    new_flat = key
                add(f"{name}: move {flat} -> {new_flat or '<top>'}", "\n".join(lines).encode(),
                    flat_keys=(flat,), names=(new_flat, key))
            else:
                new_value = rng.choice(WRONG_TYPES) if kind == "wrong_type" else draw_value(rng, flat)
                add(f"{name}: {kind} {flat} = {new_value[:40]}", replace_value(text, i, new_value).encode(),
                    flat_keys=(flat,), names=(flat,))
        elif kind == "two_values":
            (i, s1, k1, _), (j, s2, k2, _) = rng.sample(keys, 2)
            t = replace_value(text, i, draw_value(rng, f"{s1}.{k1}"))
            t = replace_value(t, j, draw_value(rng, f"{s2}.{k2}"))
            add(f"{name}: two values {s1}.{k1}, {s2}.{k2}", t.encode(), flat_keys=(f"{s1}.{k1}", f"{s2}.{k2}"),
                names=(f"{s1}.{k1}", f"{s2}.{k2}"))
        elif kind == "truncate":
            data = text.encode()
            cut = rng.randrange(len(data))
            add(f"{name}: truncated at byte {cut}", data[:cut])
        elif kind == "garbage":
            length = rng.choice([1, 7, 64, 1000, 65536])
            add(f"binary garbage, {length} bytes", rng.randbytes(length))
        elif kind == "insert_garbage":
            data = text.encode()
            at = rng.randrange(len(data))
            junk = rng.randbytes(rng.choice([1, 3, 16, 200]))
            add(f"{name}: {len(junk)} garbage bytes at {at}", data[:at] + junk + data[at:])
        else:
            sections = section_lines(text)
            i, section = rng.choice(sections)
            if kind == "delete_section":
                # Its keys now belong to the section before (or to the top level).
                before = [s for j, s in sections if j < i]
                prefix = f"{before[-1]}." if before else ""
                del lines[i]
                add(f"{name}: delete [{section}]", "\n".join(lines).encode(),
                    names=(section,) + tuple(f"'{prefix}{k}'" for k in ALL_KEYS[section]))
            elif kind == "duplicate_section":
                lines.append(f"[{section}]")
                add(f"{name}: duplicate [{section}]", "\n".join(lines).encode(), names=(section,))
            else:
                new = _typo(rng, section)
                lines[i] = lines[i].replace(section, new, 1)
                add(f"{name}: rename [{section}] -> [{new}]", "\n".join(lines).encode(), names=(new.strip('"'),))
    return cases


def _typo(rng: random.Random, word: str) -> str:
    ops = ["swap", "drop", "add", "upper", "suffix", "unicode", "dash", "far"]
    while True:
        op = rng.choice(ops)
        if op == "swap" and len(word) > 1:
            i = rng.randrange(len(word) - 1)
            new = word[:i] + word[i + 1] + word[i] + word[i + 2:]
        elif op == "drop" and len(word) > 1:
            i = rng.randrange(len(word))
            new = word[:i] + word[i + 1:]
        elif op == "add":
            i = rng.randrange(len(word) + 1)
            new = word[:i] + rng.choice("abcxyz_") + word[i:]
        elif op == "upper":
            new = word.upper()
        elif op == "suffix":
            new = word + "_2"
        elif op == "unicode":
            new = '"' + word + 'é"'      # a quoted key with a non-ASCII letter
        elif op == "dash":
            new = word.replace("_", "-") if "_" in word else word + "-x"
        else:
            new = "zzqq" + word[::-1]
        if new != word:
            return new


# ---------------------------------------------------------------------------
# Family 2: --set overrides
# ---------------------------------------------------------------------------

BAD_OVERRIDE_SYNTAX = [
    "", "=", "==", "=1", "geometry.nodes", "geometry.nodes=", "geometry.nodes==16", "geometry.nodes=16=17",
    "nodes=16", ".nodes=16", "geometry.=16", "geometry..nodes=16", "geometry.nodes.x=16", "a.b.c=1",
    "[geometry]", "geometry nodes=16", "geometry.no des=16", "geometry.nodes\n=16", " geometry.nodes = 16 ",
    "GEOMETRY.NODES=16", "geometry.nodes=\"16", "geometry.nodes='16", "geometry.nodes=[16",
    "geometry.nodes={", "geometry.nodes=16 # comment", "state.law=slip\n[geometry]\nnodes = 9",
    "state.law=\"slip\"\nnodes = 9", "geometry.nodes=16\x7f", "géométrie.nodes=16", "geometry.nœuds=16",
    "geometry." + "n" * 10_000 + "=1", "x" * 100_000 + "=1", "geometry.length=" + "1" * 100_000,
    "state.law=" + "s" * 100_000, "geometry.nodes=\t16", "geometry.nodes=-", "geometry.nodes=+",
    "geometry.nodes=1e", "geometry.nodes=0x", "time.beta=.25", "time.beta=25.", "time.beta=2.5e",
    "geometry.height=in", "geometry.height=INF", "geometry.height=Infinity", "geometry.height=-inf",
]
BAD_CLI = [
    ["--max-steps", "0"], ["--max-steps", "-1"], ["--max-steps", "nan"], ["--max-steps", "1e400"],
    ["--max-memory-gib", "0"], ["--max-memory-gib", "inf"], ["--max-memory-gib", "x"],
    ["--max-output-gib", "-5"], ["--set"], ["--nonsense"], ["--quiet=3"], ["--out"],
]


def _override_cases(rng: random.Random, bases: dict, n: int) -> list:
    cases = []

    def add(kind, overrides, flat_keys=(), names=(), extra=()):
        argv = run_argv([*caps_for(flat_keys), *[a for o in overrides for a in ("--set", o)], *extra])
        name = rng.choice(sorted(bases))
        cases.append(Case(ident=f"override-{len(cases):04d}", family="override", kind=kind, argv=argv,
                          config_bytes=bases[name].encode(), names=tuple(names)))

    for text in BAD_OVERRIDE_SYNTAX:
        key = text.split("=", 1)[0].strip()
        flat = key if key in FLAT_KEYS else ""
        # Malformed overrides are named as a whole: "override 'TEXT': expected the form section.key=value".
        add(f"syntax {text[:40]!r}", [text], flat_keys=(flat,) if flat else (),
            names=_override_names(text) + ("override '",))
    for extra in BAD_CLI:
        names = (extra[0], "override '") if extra == ["--set"] else (extra[0],)
        add(f"cli {' '.join(extra)}", [], extra=extra, names=names + (("out.h5",) if extra == ["--out"] else ()))
    kinds = ["value", "value", "value", "value", "typo_key", "unknown_section", "pair", "value_then_fix"]
    while len(cases) < n:
        kind = rng.choice(kinds)
        flat = rng.choice(FLAT_KEYS)
        if kind == "value":
            o = f"{flat}={_unquote_maybe(rng, draw_value(rng, flat))}"
            add(f"value {o[:60]}", [o], flat_keys=(flat,), names=_override_names(o))
        elif kind == "typo_key":
            section, key = flat.split(".")
            o = f"{section}.{_typo(rng, key)}=1"
            add(f"typo key {o[:60]}", [o], names=_override_names(o))
        elif kind == "unknown_section":
            section, key = flat.split(".")
            o = f"{_typo(rng, section)}.{key}=1"
            add(f"unknown section {o[:60]}", [o], names=_override_names(o))
        elif kind == "pair":
            other = rng.choice(FLAT_KEYS)
            os_ = [f"{flat}={_unquote_maybe(rng, draw_value(rng, flat))}",
                   f"{other}={_unquote_maybe(rng, draw_value(rng, other))}"]
            add(f"pair {os_[0][:30]} {os_[1][:30]}", os_, flat_keys=(flat, other),
                names=_override_names(os_[0]) + _override_names(os_[1]))
        else:
            # A bad value followed by a valid one for the same key: later overrides win.
            if flat in NODE_KEYS | DURATION_KEYS or flat == "output.stations":
                continue
            o = f"{flat}={_unquote_maybe(rng, draw_value(rng, flat))}"
            add(f"bad then default {o[:50]}", [o, f"{flat}={_default_value(flat)}"], flat_keys=(flat,),
                names=_override_names(o))
    return cases


def _unquote_maybe(rng, value: str) -> str:
    """Overrides take bare words as strings: sometimes drop the TOML quotes."""
    if value.startswith('"') and value.endswith('"') and len(value) >= 2 and rng.random() < 0.5:
        return value[1:-1]
    return value


def _override_names(o: str) -> tuple:
    key = o.split("=", 1)[0].strip()
    names = (key[:60],) if key else ()
    if key in ("time.duration", "time.duration_transits"):
        names += ("time.duration",)   # the resolved form of the pair, used by the step-count guard
    return names


DEFAULTS = {"geometry.length": "0.5", "geometry.height": "0.025", "material.shear_modulus": "9e9",
            "material.youngs_modulus": "9e9", "material.poisson_ratio": "0.33", "material.density": "1200",
            "material.plane": "strain", "loading.driving_velocity": "2e-3", "loading.normal_stress": "1e6",
            "friction.law": "paper", "friction.f0": "0.28", "friction.a": "0.005", "friction.b": "0.075",
            "friction.characteristic_slip": "5e-7", "friction.v_star": "1e-7", "friction.phi_star": "3.3e-4",
            "state.law": "aging", "interface.law": "rate_and_state", "interface.slip_amplitude": "1e-6",
            "interface.mode": "1", "interface.profile": "ramp", "interface.rise_time": "1e-4",
            "interface.stress_amplitude": "1e5", "interface.pulse_center": "0.0", "interface.pulse_width": "inf",
            "interface.load_pulse_amplitude": "0.0", "initial.noise_amplitude": "0.0", "initial.noise_seed": "1",
            "initial.noise_modes": "0",
            "initial.sine_amplitude": "0.0", "initial.sine_mode": "1", "initial.local_amplitude": "0.0",
            "initial.local_center": "0.0", "initial.local_width": "0.0", "time.beta": "0.25",
            "time.history": "auto", "output.timeseries_interval": "0.0", "output.snapshot_interval": "0.0",
            "output.snapshot_slip_increment": "0.0", "output.delta_th": "1e-8", "output.flush_interval": "5.0",
            "output.station_interval": "0", "output.front_slip_rate": "0"}


def _default_value(flat: str) -> str:
    return DEFAULTS[flat]


# ---------------------------------------------------------------------------
# Family 3: damaged run files
# ---------------------------------------------------------------------------

ATTR_VALUES = [
    ("array3", "an array of 3 floats"), ("array2d", "a 4x4 array"), ("empty_array", "an empty array"),
    ("string", "a string"), ("bytes", "bytes"), ("bool", "a boolean"), ("int64", "an int64"),
    ("int8", "an int8"), ("uint64max", "uint64 max"), ("float32", "a float32"), ("complex", "a complex"),
    ("nan", "NaN"), ("inf", "inf"), ("-inf", "-inf"), ("-1", "-1"), ("0", "0"), ("1e308", "1e308"),
    ("5e-324", "5e-324"), ("string_array", "an array of strings"), ("toml_garbage", "not TOML"),
]
DATA_VALUES = ["nan_all", "nan_one", "neg_one", "inf_one", "-inf_one", "1e308_one", "neg_zero_one",
               "int64", "int8", "float32", "string", "one_d", "three_d", "empty_rows", "wrong_width",
               "scalar", "decreasing", "bool", "huge_rows"]
COMMANDS = ["events", "events_out", "events_csv", "analyze", "export"]


def _runfile_cases(rng: random.Random, layout: dict, n: int, n_python: int) -> list:
    """layout: {"objects": {path: "group"|"dataset"}, "attrs": {path: [names]}, "size": bytes}."""
    cases = []
    python_left = n_python
    objects = sorted(layout["objects"])
    attr_slots = sorted((p, a) for p, names in layout["attrs"].items() for a in names)
    datasets = sorted(p for p, k in layout["objects"].items() if k == "dataset")
    size = layout["size"]

    def add(kind, damage, names, command=None):
        nonlocal python_left
        if command is None:
            command = rng.choice(COMMANDS if python_left > 0 else COMMANDS[:3])
        if command in ("analyze", "export"):
            python_left -= 1
        base = "events" if command == "analyze" and rng.random() < 0.5 else "plain"
        if command == "events":
            argv, python = ["events", RUNFILE], False
        elif command == "events_out":
            argv, python = ["events", RUNFILE, "--out", WORK + "/catalog.h5"], False
        elif command == "events_csv":
            argv, python = ["events", RUNFILE, "--out", WORK + "/catalog.h5", "--csv", WORK + "/c.csv",
                            "--alpha", rng.choice(["15", "0", "-1", "nan", "inf", "1e308", "5e-324", "x"])], False
        elif command == "analyze":
            argv, python = ["analyze", RUNFILE, "--out-dir", WORK + "/analysis"], True
        else:
            argv, python = ["export", RUNFILE, "--seas", WORK + "/seas"], True
        cases.append(Case(ident=f"runfile-{len(cases):04d}", family="runfile", kind=f"{command}: {kind}",
                          argv=argv, python=python, base_run=base, damage=damage,
                          names=tuple(names) + (("alpha",) if command == "events_csv" else ()),
                          path_ok=True))   # the run file's path suffices (the brief: "a key or path")

    # Every command on the undamaged file and on a few fixed damages.
    for command in COMMANDS:
        add("undamaged", [], (), command)
        add("empty file", [("truncate", 0)], (), command)
        add("text file", [("replace_bytes", "text")], (), command)
        add("HDF5 superblock only", [("truncate", 800)], (), command)
        add("no /slip_sampling", [("delete", "/slip_sampling")], ("slip_sampling",), command)
    kinds = ["truncate", "truncate", "delete", "del_attr", "del_attr", "set_attr", "set_attr", "set_attr",
             "set_data", "set_data", "crossing", "crossing", "crossing", "swap_kind"]
    while len(cases) < n:
        kind = rng.choice(kinds)
        if kind == "truncate":
            cut = rng.choice([rng.randrange(size), rng.randrange(size // 2, size), size - rng.randrange(1, 4096)])
            add(f"truncated at {cut} of {size} bytes", [("truncate", max(cut, 0))], ())
        elif kind == "delete":
            path = rng.choice(objects)
            add(f"delete {path}", [("delete", path)], _path_names(path))
        elif kind == "del_attr":
            path, attr = rng.choice(attr_slots)
            add(f"delete attribute {path}@{attr}", [("del_attr", path, attr)], (attr,) + _path_names(path))
        elif kind == "set_attr":
            path, attr = rng.choice(attr_slots)
            value, label = rng.choice(ATTR_VALUES)
            add(f"attribute {path}@{attr} = {label}", [("set_attr", path, attr, value)],
                (attr,) + _path_names(path))
        elif kind == "set_data":
            path = rng.choice(datasets)
            value = rng.choice(DATA_VALUES)
            add(f"dataset {path} -> {value}", [("set_data", path, value)], _path_names(path))
        elif kind == "crossing":
            value = rng.choice(["nan_one", "neg_one", "inf_one", "-inf_one", "1e308_one", "neg_zero_one",
                                "nan_all", "decreasing", "5e-324_one", "-5e-324_one"])
            add(f"crossing_time {value}", [("set_data", "/slip_sampling/crossing_time", value)],
                ("crossing_time", "slip_sampling"))
        else:
            path = rng.choice(objects)
            add(f"{path} replaced by a {'dataset' if layout['objects'][path] == 'group' else 'group'}",
                [("swap_kind", path)], _path_names(path))
    return cases


def _path_names(path: str) -> tuple:
    parts = [p for p in path.split("/") if p]
    return tuple([path, path.lstrip("/")] + parts)


# ---------------------------------------------------------------------------

# ---------------------------------------------------------------------------
# Family 4: friction node files
# ---------------------------------------------------------------------------

NODE_FILE_OVERRIDE = 'friction.a={ profile = "node_file", path = "a.txt" }'
NODES = 16   # CAP_NODES


def _node_file_cases(rng: random.Random) -> list:
    cases = []
    valid = b"".join(b"0.005\n" for _ in range(NODES))

    def add(kind, content, expect="refused"):
        files = {"a.txt": content} if content is not None else {}
        cases.append(Case(ident=f"nodefile-{len(cases):04d}", family="nodefile", kind=kind,
                          argv=run_argv([*CAP_NODES, *CAP_DURATION, "--set", NODE_FILE_OVERRIDE]),
                          config_bytes=b"", files=files, names=("friction.a",), expect=expect))

    add("valid (16 values)", valid, expect="completed")
    add("valid with CRLF and comments", b"# a per node\r\n" + valid.replace(b"\n", b"\r\n"), expect=None)
    add("one 20 MB line of digits", b"1" * (20 << 20) + b"\n")
    add("a 2 MB line of digits and a letter", b"0." + b"5" * (2 << 20) + b"x\n" + valid)
    add("20 MB of newlines then garbage", b"\n" * (20 << 20) + b"garbage\n")
    add("binary garbage", bytes(rng.randrange(256) for _ in range(4096)))
    add("UTF-16 with BOM", valid.decode().encode("utf-16"))
    add("UTF-16LE without BOM", valid.decode().encode("utf-16-le"))
    add("NUL inside a number", b"0.0\x0005\n" + valid)
    add("NUL bytes only", b"\x00" * 64)
    add("terminal escapes", b"\x1b[31m0.005\x1b[0m\n" + valid)
    add("bell and backspace", b"0.005\x07\x08\n" + valid)
    add("Unicode direction override", "0.005\u202e5\n".encode() + valid)
    add("a line separator U+2028", "0.005\u20280.005\n".encode() + valid)
    add("C1 control NEL", "0.005\u0085\n".encode() + valid)
    add("invalid UTF-8", b"0.\xc3\x28\n" + valid)
    add("empty file", b"")
    add("comments only", b"# nothing\n# here\n")
    add("15 values for 16 nodes", valid[: -len(b"0.005\n")])
    add("17 values for 16 nodes", valid + b"0.005\n")
    for bad in (b"nan", b"inf", b"-inf", b"1e400", b"0x10", b"1,5", b"1 2", b"--1", b"+", b"."):
        add(f"value {bad.decode()}", bad + b"\n" + valid[len(b"0.005\n"):])
    add("negative a", b"-0.005\n" + valid[len(b"0.005\n"):], expect=None)   # allowed where the law allows it
    add("a directory", "directory")
    add("a FIFO", "fifo")
    add("a symlink to /dev/zero", "->/dev/zero")
    add("a dangling symlink", "->nowhere/a.txt")
    add("missing", None)
    return cases


# ---------------------------------------------------------------------------
# Family 5: output paths
# ---------------------------------------------------------------------------

def _outpath_cases() -> list:
    cases = []

    def add(kind, argv, names, python=False, files=None, base_run=None, config=True):
        cases.append(Case(ident=f"outpath-{len(cases):04d}", family="outpath", kind=kind, argv=argv,
                          python=python, files=dict(files or {}), base_run=base_run,
                          config_bytes=None if not config else b"", names=tuple(names), expect="refused"))

    run = ["run", CONFIG, *CAP_NODES, *CAP_DURATION, "--quiet", "--out"]
    add("run --out the config, --overwrite", [*run, CONFIG, "--overwrite"], ["--out", "is the input"])
    add("run --out an existing file", [*run, WORK + "/old.h5"], ["--out"], files={"old.h5": b"old"})
    add("run --out a directory", [*run, WORK + "/d", "--overwrite"], ["--out"], files={"d": "directory"})
    add("run --out a dangling symlink", [*run, WORK + "/link.h5"], ["--out"],
        files={"link.h5": "->nowhere/target.h5"})
    add("run --out in a missing directory", [*run, WORK + "/missing/x.h5"], ["--out"])
    add("run --out in a file", [*run, WORK + "/old.h5/x.h5"], ["--out"], files={"old.h5": b"old"})
    add("run --out next to a left-over restart point", [*run, WORK + "/prev.h5"], ["prev.h5.restart"],
        files={"prev.h5.restart": b"someone else's"})
    add("run --out a FIFO, --overwrite", [*run, WORK + "/fifo", "--overwrite"], ["--out"], files={"fifo": "fifo"})
    add("stability --out the config", ["stability", CONFIG, "--out", CONFIG], ["--out", "is the input"])
    add("stability --out an existing file", ["stability", CONFIG, "--out", WORK + "/old.csv"], ["--out"],
        files={"old.csv": b"old"})
    ev = ["events", RUNFILE]
    add("events --csv the run file", [*ev, "--csv", RUNFILE], ["--csv"], base_run="plain", config=False)
    add("events --out the run file", [*ev, "--out", RUNFILE], ["--out"], base_run="plain", config=False)
    add("events --csv an existing file", [*ev, "--csv", WORK + "/old.csv"], ["--csv"], base_run="plain",
        files={"old.csv": b"old"}, config=False)
    add("events --out an existing file", [*ev, "--out", WORK + "/old.h5"], ["--out"], base_run="plain",
        files={"old.h5": b"old"}, config=False)
    add("events --out and --csv the same file", [*ev, "--out", WORK + "/c", "--csv", WORK + "/c"], ["--csv"],
        base_run="plain", config=False)
    add("events into a run file whose restart point is being written (lock held)", ev, ["in use"],
        base_run="plain", files={"run.h5.lock": "locked"}, config=False)
    for command, option in (("transition", "--csv"), ("transition", "--plot"), ("plot", "--out")):
        add(f"{command} {option} the run file, --overwrite", [command, RUNFILE, option, RUNFILE, "--overwrite"],
            [option], python=True, base_run="plain", config=False)
    add("transition --csv an existing file", ["transition", RUNFILE, "--csv", WORK + "/old.csv"], ["--csv"],
        python=True, base_run="plain", files={"old.csv": b"old"}, config=False)
    add("analyze --out-dir the run file", ["analyze", RUNFILE, "--out-dir", RUNFILE], ["--out-dir"],
        python=True, base_run="plain", config=False)
    add("export --seas the run file", ["export", RUNFILE, "--seas", RUNFILE], ["--seas"], python=True,
        base_run="plain", config=False)
    return cases


# ---------------------------------------------------------------------------
# Family 6: damaged restart points
# ---------------------------------------------------------------------------

# The interrupted base run stops after this many steps (of about 3).
RESTART_STEP = 1
RESTART_FIELDS = [("simulation", "time"), ("simulation", "step_index"), ("run", "next_timeseries"),
                  ("run", "next_snapshot"), ("run", "next_snapshot_slip"), ("run", "next_station"),
                  ("output", "timeseries_rows"), ("output", "snapshots"), ("output", "station_rows"),
                  ("output", "crossing_rows")]
RESTART_VALUES = {float: [-1.0, float("nan"), float("inf"), float("-inf"), 1e308, -0.0, 0.0, 1e-300, 1.0],
                  int: [-1, 0, 2, 2 ** 62]}


# Attributes a resume does not read (informational), or may do without (the
# checksum: a restart point written before checksums, resumed with a warning).
RESTART_OPTIONAL_ATTRS = {"code_version", "written_at", "checksum"}


def _same_bits(a, b) -> bool:
    import struct
    if isinstance(a, float) or isinstance(b, float):
        return struct.pack("<d", float(a)) == struct.pack("<d", float(b))
    return int(a) == int(b)


def _restart_cases(rng: random.Random, restart_layout: dict) -> list:
    """restart_layout: {"datasets": [...], "attrs": [(path, name)], "values":
    {"group@attr": value of the base restart point}}."""
    cases = []

    def add(kind, damage=(), special=None, names=(), expect="refused"):
        cases.append(Case(ident=f"restart-{len(cases):04d}", family="restart", kind=kind,
                          argv=["run", "--resume", RUNFILE, "--quiet"], base_run="interrupted",
                          restart_damage=list(damage), restart_special=special, names=tuple(names),
                          path_ok=True, expect=expect))

    add("undamaged", expect="completed")
    add("checksum deleted (an older restart point)", [("del_attr", "/", "checksum")], expect="completed")
    for group, attr in RESTART_FIELDS:
        integer = group == "output" or attr == "step_index"
        original = restart_layout["values"][f"{group}@{attr}"]
        for value in RESTART_VALUES[int if integer else float]:
            op = ("set_attr_value", f"/{group}", attr, value)
            # Kept checksum: any change of the stored bytes is damage.  Repaired
            # (deleted) checksum: the field validation must refuse every value
            # that is not the original one (-0.0 for 0.0 is the same run).
            add(f"{group}@{attr} = {value!r}, checksum kept", [op], names=(attr,),
                expect="completed" if _same_bits(value, original) else "refused")
            add(f"{group}@{attr} = {value!r}, checksum repaired", [op, ("del_attr", "/", "checksum")],
                names=(attr,), expect="completed" if value == original else "refused")
    for path in restart_layout["datasets"]:
        bit = rng.randrange(64)
        add(f"bit {bit} flipped in {path}", [("flip_bit", path, bit)], names=("checksum",))
    for path, attr in restart_layout["attrs"]:
        add(f"attribute {path}@{attr} deleted", [("del_attr", path, attr)], names=(attr, "checksum"),
            expect="completed" if attr in RESTART_OPTIONAL_ATTRS else "refused")
    add("config of another run", [("set_attr_value", "/", "config", "[geometry]\nnodes = 32\n")])
    add("format attribute changed", [("set_attr_value", "/", "format", "something else")])
    for fraction in (0.0, 0.1, 0.5, 0.9):
        add(f"truncated to {fraction:g} of its size", [("truncate_fraction", fraction)])
    add("a text file", special=b"not a restart point\n")
    add("a directory", special="directory", names=("directory",))
    add("a FIFO", special="fifo", names=("regular file",))
    add("a symlink to /dev/zero", special="->/dev/zero", names=("regular file",))
    add("a dangling symlink", special="->nowhere.restart")
    add("missing", special="missing", names=("no restart point",))
    return cases


def generate(repo: Path, layout: dict, seed: int = SEED, n_config: int = 480, n_override: int = 380,
             n_runfile: int = 220, n_python: int = 70, restart_layout: dict | None = None) -> list:
    """The whole corpus, in a fixed order (a function of the arguments only).
    restart_layout ({"datasets": [...], "attrs": [(path, name)]}, of the base
    restart point) adds the restart family."""
    bases = {Path(b).name: (Path(repo) / b).read_text() for b in BASES}
    rng = random.Random(seed)
    cases = _config_cases(random.Random(rng.random()), bases, n_config)
    cases += _override_cases(random.Random(rng.random()), bases, n_override)
    cases += _runfile_cases(random.Random(rng.random()), layout, n_runfile, n_python)
    extra_rng = random.Random(rng.random())
    quickstart = bases["quickstart.toml"].encode()
    for case in _node_file_cases(extra_rng) + _outpath_cases():
        if case.config_bytes is not None:   # b"": the case runs configs/quickstart.toml
            case.config_bytes = quickstart
        cases.append(case)
    if restart_layout is not None:
        cases += _restart_cases(extra_rng, restart_layout)
    return cases


# ---------------------------------------------------------------------------
# Running one case (in a worker process of the test's pool)
# ---------------------------------------------------------------------------

# A hang is either a busy loop or a process blocked for ever.  The first is caught by
# CPU time (RLIMIT_CPU: SIGXCPU, then SIGKILL), which does not depend on how loaded the
# shared machine is; the second by a wall-clock backstop.  A wall limit alone misread
# load as hangs: with load average ~9 on the 2-core machine, `analyze` cases (7 s of
# CPU, mostly matplotlib) took 13-18 s of wall time against the former 20 s limit.
CPU_LIMIT = 20            # CPU seconds per case
TIMEOUT = 120.0           # wall seconds per case (blocked, not computing)
MEMORY_LIMIT = 4 << 30    # bytes of address space per case (RLIMIT_AS)
PASSING = ("completed", "input error", "diverged", "output error")
# The longest stderr line allowed: io::kMaxMessageChars (400) plus a command's
# prefix ("error: ", "analyze: ", "export: ", "warning: ").
MAX_MESSAGE_BYTES = 420


def _limit_resources():
    import resource
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    resource.setrlimit(resource.RLIMIT_CPU, (CPU_LIMIT, CPU_LIMIT + 1))


def _attr_value(spec: str):
    import numpy as np
    return {
        "array3": np.array([0.01, 0.02, 0.03]), "array2d": np.zeros((4, 4)), "empty_array": np.zeros(0),
        "string": "five", "bytes": np.bytes_(b"\xff\xfe"), "bool": np.bool_(True), "int64": np.int64(3),
        "int8": np.int8(-3), "uint64max": np.uint64(2**64 - 1), "float32": np.float32(1e-3),
        "complex": np.complex128(1 + 2j), "nan": np.nan, "inf": np.inf, "-inf": -np.inf, "-1": -1.0, "0": 0.0,
        "1e308": 1e308, "5e-324": 5e-324, "string_array": np.array([b"a", b"b"]),
        "toml_garbage": "[geometry\nnodes = = 3\x7f",
    }[spec]


def _data_value(spec: str, old):
    import numpy as np
    a = np.array(old, dtype=np.float64) if old.dtype.kind in "fiub" else np.zeros((3, 4))
    flat = a.reshape(-1)
    if spec.endswith("_one") and flat.size:
        v = {"nan_one": np.nan, "neg_one": -1.0, "inf_one": np.inf, "-inf_one": -np.inf, "1e308_one": 1e308,
             "neg_zero_one": -0.0, "5e-324_one": 5e-324, "-5e-324_one": -5e-324}[spec]
        flat[flat.size // 2] = v
        return a
    if spec == "nan_all":
        return np.full_like(a, np.nan)
    if spec == "decreasing":
        return a[::-1].copy()
    if spec == "int64":
        return np.nan_to_num(a).astype(np.int64)
    if spec == "int8":
        return np.zeros(a.shape, np.int8)
    if spec == "float32":
        return a.astype(np.float32)
    if spec == "bool":
        return a > 0
    if spec == "string":
        return np.array([b"x"] * max(1, flat.size)).reshape(a.shape if a.size else (1,))
    if spec == "one_d":
        return flat.copy()
    if spec == "three_d":
        return a.reshape((1,) + a.shape) if a.ndim else a.reshape(1, 1, 1)
    if spec == "empty_rows":
        return np.zeros((0,) + a.shape[1:])
    if spec == "wrong_width":
        return np.zeros(a.shape[:-1] + (a.shape[-1] + 1,)) if a.ndim else np.zeros(2)
    if spec == "scalar":
        return np.float64(1.0)
    if spec == "huge_rows":
        return np.zeros((100_000,) + a.shape[1:]) if a.ndim else np.zeros(100_000)
    raise ValueError(spec)


def _apply_damage(path: Path, ops):
    import h5py
    import numpy as np
    for op in ops:
        if op[0] == "truncate":
            with open(path, "r+b") as f:
                f.truncate(op[1])
        elif op[0] == "truncate_fraction":
            with open(path, "r+b") as f:
                f.truncate(int(path.stat().st_size * op[1]))
        elif op[0] == "replace_bytes":
            path.write_text("this is not an HDF5 file\n")
        else:
            with h5py.File(path, "r+") as f:
                target = op[1]
                if op[0] == "delete":
                    del f[target]
                elif op[0] == "del_attr":
                    del f[target].attrs[op[2]]
                elif op[0] == "set_attr":
                    obj = f[target]
                    del obj.attrs[op[2]]
                    obj.attrs[op[2]] = _attr_value(op[3])
                elif op[0] == "set_data":
                    new = _data_value(op[2], f[target][()])
                    attrs = dict(f[target].attrs)
                    del f[target]
                    f[target] = new
                    for k, v in attrs.items():
                        f[target].attrs[k] = v
                elif op[0] == "set_attr_value":
                    obj = f[target]
                    if op[2] in obj.attrs:
                        del obj.attrs[op[2]]
                    obj.attrs[op[2]] = np.int64(op[3]) if isinstance(op[3], int) else op[3]
                elif op[0] == "flip_bit":
                    data = f[target][()]
                    raw = data.view(np.uint64)
                    raw[raw.size // 2] ^= np.uint64(1) << np.uint64(op[2])
                    f[target][...] = raw.view(data.dtype)
                elif op[0] == "swap_kind":
                    kind = isinstance(f[target], h5py.Group)
                    del f[target]
                    if kind:
                        f[target] = np.arange(3.0)
                    else:
                        f.create_group(target)
                else:
                    raise ValueError(op)


def _materialise(case: Case, work: Path, base_runs: dict) -> dict:
    import os
    import shutil
    work.mkdir(parents=True)
    subst = {WORK: str(work)}
    config = work / "config.toml"
    if case.config_special is None:
        if case.config_bytes is not None:
            config.write_bytes(case.config_bytes)
    elif case.config_special == "directory":
        config.mkdir()
    elif case.config_special == "missing":
        pass
    elif case.config_special == "symlink_dir":
        config.symlink_to(work)
    elif case.config_special == "fifo":
        os.mkfifo(config)
    else:
        config = Path(case.config_special)
    subst[CONFIG] = str(config)
    if case.base_run:
        runfile = work / "run.h5"
        shutil.copy(base_runs[case.base_run], runfile)
        _apply_damage(runfile, case.damage)
        subst[RUNFILE] = str(runfile)
        if case.base_run == "interrupted":
            restart = work / "run.h5.restart"
            shutil.copy(base_runs["interrupted"] + ".restart", restart)
            _apply_damage(restart, case.restart_damage)
            if case.restart_special is not None:
                restart.unlink()
                _make_special(restart, case.restart_special)
    for name, content in case.files.items():
        _make_special(work / name, content)
    return subst


def _make_special(path: Path, content):
    """bytes: a file with them; "directory", "fifo", "missing", "locked" (an
    empty file the runner holds an flock on), "->TARGET" (a symbolic link)."""
    import os
    if isinstance(content, bytes):
        path.write_bytes(content)
    elif content == "directory":
        path.mkdir()
    elif content == "fifo":
        os.mkfifo(path)
    elif content in ("missing",):
        pass
    elif content == "locked":
        path.write_bytes(b"")
    elif content.startswith("->"):
        path.symlink_to(content[2:])
    else:
        raise ValueError(content)


def execute(case: Case, cli: str, python_dir: str, base_runs: dict, tmp: str) -> dict:
    """Runs one case; returns {"ident", "kind", "class", "ok", "returncode", "stderr", "seconds"}."""
    import os
    import signal
    import subprocess
    import sys
    import time
    work = Path(tmp) / case.ident
    subst = _materialise(case, work, base_runs)
    argv = [subst.get(a, a).replace(WORK, str(work)) for a in case.argv]
    exe = [sys.executable, "-m", "slipstrip"] if case.python else [cli]
    env = dict(os.environ, PYTHONPATH=python_dir, SLIPSTRIP_BIN=cli, OMP_NUM_THREADS="1")
    # A "locked" file stands for a run another process is writing: this worker
    # holds its flock while the case runs (another open file description).
    import fcntl
    held = [os.open(work / name, os.O_RDWR) for name, c in case.files.items() if c == "locked"]
    for fd in held:
        fcntl.flock(fd, fcntl.LOCK_EX)
    t0 = time.monotonic()
    proc = subprocess.Popen(exe + argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env=env, cwd=work, start_new_session=True, preexec_fn=_limit_resources)
    try:
        out, err = proc.communicate(timeout=TIMEOUT)
        timed_out = False
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        timed_out = True
    seconds = time.monotonic() - t0
    for fd in held:
        os.close(fd)
    stderr = err.decode(errors="replace")
    cls, ok = classify(case, proc.returncode, stderr, timed_out, subst)
    if ok:
        import shutil
        shutil.rmtree(work, ignore_errors=True)
    named = proc.returncode == 2 and any(n and n in stderr for n in case.names)
    return {"ident": case.ident, "family": case.family, "kind": case.kind, "class": cls, "ok": ok, "named": named,
            "returncode": proc.returncode, "stderr": stderr[-2000:], "seconds": seconds}


def classify(case: Case, rc: int, stderr: str, timed_out: bool, subst: dict):
    """(class, passed).  Passing classes: completed (exit 0), nothing kept (exit
    1 of `events`/`analyze`, one line "0 events kept ..." saying why), input
    error (exit 2, one line naming a key or path), diverged (exit 3 with the
    diagnostic), output error (exit 4)."""
    if timed_out:
        return "hang (timeout)", False
    if rc == -signal.SIGXCPU:
        return "hang (CPU limit)", False
    if rc < 0:
        return f"signal {-rc}", False
    if "Traceback (most recent call last)" in stderr:
        return "traceback", False
    # Every line, warnings included: one printable line each, bounded (io/messages.hpp).
    for line in stderr.splitlines():
        if len(line.encode()) > MAX_MESSAGE_BYTES:
            return f"message line of {len(line.encode())} bytes", False
        if any(c < " " or c == "\x7f" or c == "\ufffd" for c in line):
            return "unprintable message", False
    # The message lines: without warnings, the run's banner ("slipstrip 0.1.0 (hash): CONFIG -> OUT") and
    # the run header `slipstrip run` prints before its set-up ("run: N steps of dt = ...", "  H = ...",
    # "  output up to ~...", config/resource_estimate.cpp), which state the cost, not an outcome.
    lines = [l for l in stderr.splitlines() if l.strip() and not l.lstrip().lower().startswith("warning")
             and not re.match(r"slipstrip \S+ \(([0-9a-f]+(-dirty)?|unknown)\): ", l)
             and not re.match(r"run: \S+ steps of dt = |  H = \S+ m, H/L = |  output up to ~", l)]
    if case.expect == "refused" and rc != 2:
        return f"not refused (exit {rc})", False
    if case.expect == "completed" and rc != 0:
        return f"valid input not completed (exit {rc})", False
    if rc == 0:
        return "completed", True
    if rc == 1 and len(lines) == 1 and "0 events kept" in lines[0]:
        return "nothing kept", True
    if rc == 2:
        if len(lines) != 1:
            return f"exit 2, {len(lines)} message lines", False
        line = lines[0]
        if any(n and n in line for n in case.names):
            return "input error", True
        path = subst.get(RUNFILE) or subst.get(CONFIG)
        if path and path in line and (case.path_ok or "invalid TOML" in line or not case.names):
            return "input error", True
        return "exit 2 naming no key or path", False
    if rc == 3:
        if "diverg" in stderr and "node" in stderr and "t = " in stderr:
            return "diverged", True
        return "exit 3 without a divergence diagnostic", False
    if rc == 4:
        return "output error", True
    return f"exit {rc}", False
