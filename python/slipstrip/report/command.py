"""`python3 -m slipstrip report`: the command line of the report."""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

from ..claims import CLAIMS
from ..paths import OutputPathError, check_outputs
from .document import markdown
from .measurements import N_BOOTSTRAP
from .runs import READINGS, MissingRun
from .sections import Report


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m slipstrip report",
                                     description="Every checkable claim of the paper at both material readings, side "
                                                 "by side with slipstrip (docs/reproduction.md), from directories of "
                                                 "run files.")
    parser.add_argument("rundir", help="run files RUNDIR/<config name>.h5 at the paper-as-run reading (configs as "
                                       "committed)")
    parser.add_argument("--printed", default=None, help="run files PRINTED/<config name>.h5 with Table S1 as printed "
                                                        "(--set material.shear_modulus=9e9); without it that column "
                                                        "says not run")
    parser.add_argument("--out", default="docs/reproduction.md", help="Markdown output (default docs/reproduction.md)")
    parser.add_argument("--figures", default="docs/figures/reproduction",
                        help="directory of the PNG figures (one subdirectory per reading)")
    parser.add_argument("--allow-missing", action="store_true",
                        help="a missing or unreadable run gives 'not run' rows instead of an error")
    parser.add_argument("--allow-incomplete", action="store_true",
                        help="use runs whose status is not 'completed' (marked preliminary)")
    parser.add_argument("--bootstrap", type=int, default=N_BOOTSTRAP, help="bootstrap resamples (default 200)")
    parser.add_argument("--jobs", type=int, default=1, help="build the two readings in parallel processes (2)")
    parser.add_argument("--quiet", action="store_true")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace an existing --out file and the PNG figures in --figures")
    args = parser.parse_args(list(argv[1:] if argv and argv[0] == "report" else argv))
    dirs = {"asrun": Path(args.rundir), "printed": Path(args.printed) if args.printed else None}
    for key, d in dirs.items():
        if d is not None and not d.is_dir():
            print(f"report: run directory {d} ({READINGS[key].name}) not found", file=sys.stderr)
            return 2
    if dirs["printed"] is None and not args.allow_missing:
        print("report: no --printed run directory (Table S1 as printed); give one, or --allow-missing to report that "
              "column as not run", file=sys.stderr)
        return 2
    out, figdir = Path(args.out), Path(args.figures)
    # The figures of an earlier report are replaced as a whole (below), so each is an output.
    old_figures = sorted(figdir.glob("*.png")) + sorted(figdir.glob("*/*.png")) if figdir.is_dir() else []
    try:
        check_outputs({"--out": out, **{f"--figures {p.relative_to(figdir)}": p for p in old_figures}},
                      directories={"--figures": figdir, "the directory of --out": out.parent},
                      inputs=[f for d in dirs.values() if d is not None for f in sorted(d.glob("*.h5"))],
                      overwrite=args.overwrite)
    except OutputPathError as err:
        print(f"report: {err}", file=sys.stderr)
        return 2
    log = (lambda *a: None) if args.quiet else (lambda *a: print(*a, file=sys.stderr))
    with tempfile.TemporaryDirectory() as work:
        reports = {key: Report(dirs[key], figdir / key, args.allow_missing, args.allow_incomplete, out.parent,
                               Path(work) / key, n_bootstrap=args.bootstrap, log=log, reading=READINGS[key])
                   for key in READINGS}
        for rep in reports.values():
            rep.workdir.mkdir(parents=True, exist_ok=True)
            try:
                rep.load()
            except MissingRun as err:
                d = "RUNDIR" if rep.reading.key == "asrun" else "PRINTED"
                print(f"report: {str(err).replace('RUNDIR', d)} ({d} = {dirs[rep.reading.key]}; use --allow-missing "
                      "to report it as not run)", file=sys.stderr)
                return 2
        # Never a stale number: old figures go before anything is written.
        if figdir.is_dir():
            for p in list(figdir.glob("*.png")) + list(figdir.glob("*/*.png")):
                p.unlink()
        try:
            if args.jobs > 1:
                # One process per reading (they share nothing but the figure directory's parent).
                import concurrent.futures
                import multiprocessing
                ctx = multiprocessing.get_context("fork")
                with concurrent.futures.ProcessPoolExecutor(max_workers=args.jobs, mp_context=ctx) as pool:
                    futures = {key: pool.submit(_build_in_child, dirs[key], figdir / key, args.allow_missing,
                                                args.allow_incomplete, out.parent, Path(work) / key, args.bootstrap,
                                                args.quiet, key) for key in reports}
                    for key, fut in futures.items():
                        reports[key].rows, reports[key].figures, reports[key].stationarity_rows = fut.result()
            else:
                for rep in reports.values():
                    rep.build()
        except MissingRun as err:
            print(f"report: {err}", file=sys.stderr)
            return 2
        command = ("python3 -m slipstrip report RUNDIR --printed PRINTED --out " + _rel(out) + " --figures "
                   + _rel(figdir) + " --overwrite" + (" --allow-missing" if args.allow_missing else "")
                   + (" --allow-incomplete" if args.allow_incomplete else ""))
        text = markdown(reports, command, {k: (d.name if d is not None else None) for k, d in dirs.items()})
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(out.suffix + ".tmp")
    tmp.write_text(text)
    tmp.replace(out)
    counts = {k: r.counts() for k, r in reports.items()}
    print(f"wrote {out} ({len(CLAIMS)} claims; " + "; ".join(
        f"{READINGS[k].name}: {c['agree']} agree, {c['differ']} differ, {c['not checkable']} not checkable"
        for k, c in counts.items()) + ")")
    return 0


def _build_in_child(rundir, figdir, allow_missing, allow_incomplete, doc_dir, workdir, n_bootstrap, quiet, key):
    """Builds one reading's report in a worker process; returns its rows, figures
    and stationarity rows (the parent holds the runs it loaded itself)."""
    log = (lambda *a: None) if quiet else (lambda *a: print(*a, file=sys.stderr))
    rep = Report(rundir, figdir, allow_missing, allow_incomplete, doc_dir, workdir, n_bootstrap=n_bootstrap,
                 log=log, reading=READINGS[key])
    rep.load()
    rep.build()
    return rep.rows, rep.figures, rep.stationarity_rows


def _rel(p: Path) -> str:
    try:
        return str(Path(p).resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return Path(p).name
