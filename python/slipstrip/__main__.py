"""python3 -m slipstrip <command> [...]

  plot     RUN.h5 [--out spacetime.png] [--kind spacetime|timeseries|maps] [--times T1,T2,...] [--z Z]
  plot-stability  TABLE.csv --out FIG.png   (the CSV of `slipstrip stability --out`)
  analyze  ...  (slipstrip.analysis.main)
  scan     ...  (slipstrip.scan.main)
  report   RUNDIR --printed PRINTED [--out docs/reproduction.md] [--figures DIR] [--allow-missing]  (slipstrip.report.main)
  transition  RUNS... [--csv F] [--plot PNG]  (slipstrip.transition.main: long-time state of each run)
  export   RUN.h5 --seas DIR [--overwrite]  (slipstrip.export.main: SEAS-style station files)
  pulse-episodes  RUN.h5 [--json F] [--plot PNG]  (slipstrip.episodes.main: the pulse criterion window by window)
  trajectory-divergence  A.h5 B.h5 [...] [--json F] [--plot PNG]  (slipstrip.divergence.main: when two runs part)
  rupture-fronts  RUN.h5 [RUN2.h5 ...] [--window D0,D1] [--json F] [--plot PNG]  (slipstrip.fronts.main: front speeds vs Rayleigh speeds)

Each command parses its own arguments (`python3 -m slipstrip <command> -h`).
"""
from __future__ import annotations

import argparse
import importlib
import sys

from .paths import OutputPathError, check_outputs, one_line

USAGE = __doc__


def _outputs_ok(outputs: dict, inputs: list, overwrite: bool) -> bool:
    """The output-path rule (slipstrip.paths); False after printing why not."""
    try:
        check_outputs(outputs, inputs=inputs, overwrite=overwrite)
    except OutputPathError as e:
        print(f"error: {e}", file=sys.stderr)
        return False
    return True


def plot_main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m slipstrip plot",
                                     description="Plot a run file (by default the space-time map of "
                                                 "log10(v/v0) of a line, the slip-rate maps of a 2D interface).")
    parser.add_argument("run", help="run file (HDF5) written by `slipstrip run`")
    parser.add_argument("--out", default=None,
                        help="output PNG (default: spacetime.png or timeseries.png in the current directory)")
    parser.add_argument("--kind", choices=("spacetime", "timeseries", "maps"), default=None,
                        help="spacetime (a line: log10(v/v0) over x and t, the default there; a 2D interface: "
                             "three panels over t, |v| along x on one row of nodes, the largest |v| across z "
                             "at each x and along x at each z), maps (a 2D interface: slip-rate maps over "
                             "(x, z) with the rupture front; the default there), timeseries (both)")
    parser.add_argument("--z", type=float, default=None,
                        help="spacetime of a 2D interface: the row of nodes nearest to this z [m] in the first "
                             "panel (default: the row that holds the largest slip rate)")
    parser.add_argument("--times", default=None,
                        help="maps: comma-separated times [s] of the maps (default: four snapshots spread "
                             "over the run)")
    parser.add_argument("--vmin", type=float, default=None, help="colour scale minimum of log10(v/v0)")
    parser.add_argument("--vmax", type=float, default=None, help="colour scale maximum of log10(v/v0)")
    parser.add_argument("--dpi", type=int, default=150)
    parser.add_argument("--overwrite", action="store_true", help="replace an existing --out file")
    args = parser.parse_args(argv)

    from .runfile import open_run

    try:
        plane = open_run(args.run).interface_2d
    except (ValueError, OSError, KeyError) as e:
        print(f"error: {one_line(e)}", file=sys.stderr)
        return 2
    kind = args.kind or ("maps" if plane else "spacetime")
    if args.z is not None and not (kind == "spacetime" and plane):
        print("error: --z applies to --kind spacetime of a 2D interface (geometry.nodes_z > 1) only",
              file=sys.stderr)
        return 2
    if kind == "maps" and not plane:
        print(f"error: --kind maps draws a 2D interface (geometry.nodes_z > 1); {args.run} is a line: "
              "use --kind spacetime", file=sys.stderr)
        return 2
    times = None
    if args.times is not None:
        try:
            times = [float(t) for t in args.times.split(",")]
        except ValueError:
            print(f"error: --times {args.times!r}: expected comma-separated times in s, e.g. 1e-3,2e-3",
                  file=sys.stderr)
            return 2
        if kind != "maps":
            print("error: --times applies to --kind maps only", file=sys.stderr)
            return 2
    out = args.out or f"{kind}.png"
    if not _outputs_ok({"--out": out}, [args.run], args.overwrite):
        return 2
    # matplotlib is imported only when plotting: it is most of the command's
    # start-up time, and the refusals above need none of it.
    from . import plots

    try:
        if kind == "maps":
            plots.interface_2d_maps(args.run, out, times=times, dpi=args.dpi)
        elif kind == "spacetime" and plane:
            plots.interface_2d_spacetime(args.run, out, z=args.z, vmin=args.vmin, vmax=args.vmax, dpi=args.dpi)
        elif kind == "spacetime":
            plots.spacetime(args.run, out, vmin=args.vmin, vmax=args.vmax, dpi=args.dpi)
        else:
            plots.timeseries(args.run, out, dpi=args.dpi)
    except (ValueError, OSError, KeyError) as e:
        print(f"error: {one_line(e)}", file=sys.stderr)
        return 2
    print(f"wrote {out}")
    return 0


def plot_stability_main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m slipstrip plot-stability",
                                     description="Plot the CSV written by `slipstrip stability --out` "
                                                 "(Lc(H) in the style of the supplement's Fig. S2, or "
                                                 "growth rate vs wavelength).")
    parser.add_argument("table", help="CSV from `slipstrip stability --out`")
    parser.add_argument("--out", required=True, help="output PNG")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing --out file")
    args = parser.parse_args(argv)
    from . import plots
    if not _outputs_ok({"--out": args.out}, [args.table], args.overwrite):
        return 2
    try:
        plots.stability(args.table, args.out)
    except (ValueError, OSError, KeyError) as e:
        print(f"error: {one_line(e)}", file=sys.stderr)
        return 2
    print(f"wrote {args.out}")
    return 0


def _delegate(module: str, argv: list[str]) -> int:
    try:
        mod = importlib.import_module(f"slipstrip.{module}")
    except ImportError as e:
        print(f"error: slipstrip.{module} is not available ({e})", file=sys.stderr)
        return 2
    result = mod.main(argv)
    return 0 if result is None else int(result)


COMMANDS = {
    "plot": plot_main,
    "plot-stability": plot_stability_main,
    "analyze": lambda argv: _delegate("analysis", argv),
    "scan": lambda argv: _delegate("scan", argv),
    "report": lambda argv: _delegate("report", argv),
    "transition": lambda argv: _delegate("transition", argv),
    "export": lambda argv: _delegate("export", argv),
    "pulse-episodes": lambda argv: _delegate("episodes", argv),
    "trajectory-divergence": lambda argv: _delegate("divergence", argv),
    "rupture-fronts": lambda argv: _delegate("fronts", argv),
}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] in ("-h", "--help"):
        print(USAGE.strip())
        return 0 if argv else 2
    command, rest = argv[0], argv[1:]
    if command not in COMMANDS:
        print(f"error: unknown command '{command}': allowed are {', '.join(COMMANDS)}\n\n{USAGE.strip()}",
              file=sys.stderr)
        return 2
    return COMMANDS[command](rest)


if __name__ == "__main__":
    sys.exit(main())
