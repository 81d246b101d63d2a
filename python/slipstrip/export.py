"""Export a run's station records as the plain-text station files of the SCEC
SEAS benchmarks (docs/output.md, "Stations and SEAS export"):

    python3 -m slipstrip export RUN.h5 --seas DIR [--overwrite]

writes, from /stations and /rupture_front of the run file,

* one file per station, ``station_x+0.5000.txt`` (x in m): ``#`` header lines
  (problem, code, version, git hash, date, element size, location, column
  descriptions), then the field-name line, then one row per record with
  t [s], slip [m], log10 slip rate [log10 m/s], shear stress [MPa],
  log10 state [log10 s] and normal stress [MPa], and for a pair of different
  in-plane bodies the opening (gap between the faces) [m], every value in
  ``%.15e``;
* ``global.txt``: t [s], log10 max slip rate [log10 m/s], moment rate
  [N/s per metre along the third direction, i.e. mu * integral of v dx];
* ``rupture.txt`` (if the run recorded fronts): x [m], arrival time [s] of the
  first slip rate above output.front_slip_rate, NaN where it never arrived.

DIR is created if missing; files of these names already in it are refused
(exit 2, naming the first) unless ``--overwrite`` is given.

As in the SEAS files, slip rate and state are written as log10 and stresses
in MPa; slip is the full slip (both strips), the shear stress is the total
traction on the interface (not its perturbation).

``read_seas(path)`` reads any of these files back (header, column names,
values as written).  With NumPy alone, drop the ``#`` lines and let the
field-name line name the columns:

    np.genfromtxt((l for l in open(path) if not l.startswith("#")), names=True)
"""
from __future__ import annotations

import argparse
import dataclasses
import datetime as _dt
import math
import os
import sys
from pathlib import Path

import numpy as np

from . import runfile
from .paths import OutputPathError, check_outputs, one_line

FMT = "%.15e"


def _header(f, run_attrs: dict, config: dict, title: str, columns: list[tuple[str, str]], extra: list[str]):
    geometry = config.get("geometry", {})
    n = geometry.get("nodes", 0)
    dx = geometry.get("length", math.nan) / n if n else math.nan
    lines = [
        f"# problem: slipstrip run ({title})",
        f"# code: slipstrip {run_attrs.get('code_version', '?')} (git {run_attrs.get('git_hash', '?')})",
        f"# modeler: slipstrip export",
        f"# date: {_dt.date.today().isoformat()} (run started {run_attrs.get('start_time', '?')})",
        f"# element_size: {dx:.6g} m (interface node spacing L/N)",
        f"# strip_height: {geometry.get('height', '?')} m, period L: {geometry.get('length', '?')} m",
        *extra,
        f"# columns: " + "; ".join(f"{name} [{unit}]" for name, unit in columns),
    ]
    f.write("\n".join(lines) + "\n")
    f.write(" ".join(name for name, _ in columns) + "\n")


def export_seas(run_path, out_dir, overwrite: bool = False,
                overwrite_flag: str = "overwrite=True") -> list[Path]:
    """Writes the SEAS files of ``run_path`` into ``out_dir`` (created if
    missing) and returns their paths.  The output-path rule
    (slipstrip.paths.check_outputs) is applied before anything is written:
    ``out_dir`` must not be the run file, and station files already in it
    are replaced only with ``overwrite``; else OutputPathError."""
    import tomllib
    out_dir = Path(out_dir)
    check_outputs(directories={"--seas": out_dir}, inputs=[run_path])
    written = []
    with runfile.open_h5(run_path) as h5:
        if "stations" not in h5:
            raise KeyError(f"{run_path}: no /stations (set [output] stations = [x1, ...] in the config)")
        if "z" in h5["stations"]:
            raise ValueError(f"{run_path}: stations of a 2D interface (x, z): the SEAS text files describe "
                             "stations of a one-dimensional interface only; read /stations with h5py")
        attrs = {k: str(runfile.decode_attr(v)) for k, v in h5.attrs.items() if k in
                 ("code_version", "git_hash", "start_time", "status")}
        config = tomllib.loads(str(runfile.decode_attr(h5.attrs["config"])))
        g = h5["stations"]
        x = g["x"][:]
        t = g["time"][:]
        fields = {k: g[k][:] for k in ("slip", "slip_rate", "shear_stress", "state", "normal_stress")}
        # In-plane pairs of different bodies also record the gap (docs/bodies.md §4).
        opening = g["opening"][:] if "opening" in g else None
        vmax = g["max_slip_rate"][:]
        moment_rate = g["moment_rate"][:]
        front = h5["rupture_front/arrival_time"][:] if "rupture_front" in h5 else None
        front_x = h5["rupture_front/x"][:] if front is not None else None
        front_threshold = float(h5["rupture_front"].attrs["slip_rate_threshold"]) if front is not None else None
    names = [f"station_x{xs:+.4f}.txt" for xs in x] + ["global.txt"] + (["rupture.txt"] if front is not None else [])
    check_outputs({f"--seas {name}": out_dir / name for name in names}, directories={"--seas": out_dir},
                  inputs=[run_path], overwrite=overwrite, overwrite_flag=overwrite_flag)
    out_dir.mkdir(parents=True, exist_ok=True)
    columns = [("t", "s"), ("slip", "m"), ("slip_rate", "log10 m/s"), ("shear_stress", "MPa"),
               ("state", "log10 s"), ("normal_stress", "MPa")] + ([("opening", "m")] if opening is not None else [])
    with np.errstate(divide="ignore"):
        for s, xs in enumerate(x):
            path = out_dir / names[s]
            with path.open("w") as f:
                _header(f, attrs, config, "station time series", columns,
                        [f"# location: x = {xs:.6g} m on the interface (y = 0)",
                         "# slip rate and state as log10, stresses in MPa (SEAS convention)"])
                table = np.column_stack([t, fields["slip"][:, s], np.log10(np.abs(fields["slip_rate"][:, s])),
                                         fields["shear_stress"][:, s] / 1e6, np.log10(fields["state"][:, s]),
                                         fields["normal_stress"][:, s] / 1e6]
                                        + ([opening[:, s]] if opening is not None else []))
                np.savetxt(f, table, fmt=FMT)
            written.append(path)
        path = out_dir / "global.txt"
        with path.open("w") as f:
            _header(f, attrs, config, "global time series",
                    [("t", "s"), ("max_slip_rate", "log10 m/s"), ("moment_rate", "N/s per m")],
                    ["# moment_rate = shear_modulus * sum over nodes of slip_rate * dx"])
            np.savetxt(f, np.column_stack([t, np.log10(vmax), moment_rate]), fmt=FMT)
        written.append(path)
    if front is not None:
        path = out_dir / "rupture.txt"
        with path.open("w") as f:
            _header(f, attrs, config, "rupture-front arrival times", [("x", "m"), ("t", "s")],
                    [f"# t: first time the slip rate exceeds {front_threshold:.6g} m/s (nan: never)"])
            np.savetxt(f, np.column_stack([front_x, front]), fmt=FMT)
        written.append(path)
    return written


@dataclasses.dataclass(frozen=True)
class SeasFile:
    """One exported SEAS text file: its `# key: value` header lines, its
    column names and its values as written (SEAS units: log10 slip rate,
    log10 state, stresses in MPa).  `f["slip"]` is one column."""
    header: dict[str, str]
    columns: tuple[str, ...]
    data: np.ndarray  # [rows, columns]

    def __getitem__(self, column: str) -> np.ndarray:
        if column not in self.columns:
            raise KeyError(f"no column {column!r}: the file has {', '.join(self.columns)}")
        return self.data[:, self.columns.index(column)]


def read_seas(path: str | os.PathLike) -> SeasFile:
    """Reads a file written by export_seas (station_x*.txt, global.txt, rupture.txt)."""
    header: dict[str, str] = {}
    with open(path) as f:
        line = f.readline()
        while line.startswith("#"):
            key, _, value = line[1:].partition(":")
            header[key.strip()] = value.strip()
            line = f.readline()
        columns = tuple(line.split())
        if not columns:
            raise ValueError(f"{os.fspath(path)}: no field-name line after the '#' header: not a SEAS file "
                             "written by `slipstrip export --seas`")
        data = np.loadtxt(f, ndmin=2)
    if data.size and data.shape[1] != len(columns):
        raise ValueError(f"{os.fspath(path)}: {data.shape[1]} values per row but {len(columns)} column names")
    return SeasFile(header, columns, data.reshape(-1, len(columns)))


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(prog="python3 -m slipstrip export",
                                description="Export a run's stations as SEAS-style text files.")
    p.add_argument("run", help="run file with /stations")
    p.add_argument("--seas", required=True, metavar="DIR",
                   help="directory for the station files (created if missing)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace files of the same names already in DIR (refused without it)")
    args = p.parse_args(argv)
    try:
        files = export_seas(args.run, args.seas, overwrite=args.overwrite, overwrite_flag="--overwrite")
    except (runfile.RunFileError, OutputPathError) as err:  # these name the path themselves
        print(f"export: {err}", file=sys.stderr)
        return 2
    except (OSError, KeyError, ValueError, TypeError, IndexError, UnicodeDecodeError) as err:
        # A missing, damaged or foreign run file (tomllib's TOMLDecodeError is a
        # ValueError): one line naming the file, never a traceback.
        print("export: " + one_line(f"{args.run}: {str(err) or type(err).__name__}"), file=sys.stderr)
        return 2
    print(f"wrote {len(files)} files to {args.seas}")
    return 0
