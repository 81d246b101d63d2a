"""Every checkable claim of the paper, at both material readings, side by side
with slipstrip (docs/reproduction.md).

    python3 -m slipstrip report RUNDIR [--printed PRINTED_RUNDIR] [--out docs/reproduction.md]
        [--figures docs/figures/reproduction] [--allow-missing] [--allow-incomplete]

RUNDIR holds one run file per case at the paper-as-run reading of Table S1
(E = 9 GPa, mu = 3.38 GPa; the configs as committed), named after its config:
RUNDIR/reference.h5 is `slipstrip run configs/reference.toml --out
RUNDIR/reference.h5` (then `slipstrip events RUNDIR/reference.h5`).
PRINTED_RUNDIR holds the same runs with Table S1 as printed (mu = 9 GPa:
`--set material.shear_modulus=9e9`).  The report reads them (never writes to
them), computes every slipstrip number from them or from the linear stability
of the bindings, and writes the Markdown table and the figures anew.

The claims, their places and the paper's words are `claims.CLAIMS`; no other
paper number is typed into the report.

Exit codes: 0 written; 2 a run file is missing, unreadable, incomplete or of
the other reading (without --allow-missing / --allow-incomplete), or bad
arguments.

One module per concept, every name re-exported here (`slipstrip.report.X`):
  runs          the run files and the two readings of Table S1
  measurements  what is measured on the runs (bootstrap errors, p(T) peaks,
                fronts, the Fig. 2 event hierarchy, fits)
  verdicts      the verdict rules and the formatting of values
  sections      Report: one method per section of the paper, one row per claim
  figures       the report's figures (drawn from measured data, returned to Report)
  document      the Markdown document of both readings
  command       `python3 -m slipstrip report`
"""
from .runs import (  # noqa: F401
    FIG3_FAMILY, FIG5_VOLUME_SOLVER_JSON, MissingRun, READINGS, REPO, RUNS, Reading, Run, STATISTICS_RUNS,
    catalog_of, fig5_volume_solver_text, material_label, open_run_file, run_description,
)
from .measurements import (  # noqa: F401
    EDGE_TOLERANCE, FIG2_T_BEGIN, FRONT_MIN_RATE, N_BOOTSTRAP, bootstrap, burst_onset, combined_error,
    example_event, fig2_hierarchy, fit_peak_scaling, friction_steady_state, local_peaks_of_pT,
    nucleation_event, peak_of_pT, ring_components, statistics_of, tip_zones_of_run, wave_speeds,
)
from .verdicts import (  # noqa: F401
    FACTOR_RULE, MAJORITY, ORDER_RULE, RELATIVE_RULE, SIGMA_RULE, fmt, shown, verdict_beats_chance,
    verdict_bool, verdict_class, verdict_factor, verdict_guide, verdict_majority, verdict_order,
    verdict_relative, verdict_sigma, verdict_xmin_sweep, xmin_sweep_cell,
)
from .sections import (  # noqa: F401
    PAPER, Report, Row,
)
from .document import (  # noqa: F401
    markdown, reading_conclusion,
)
from .command import (  # noqa: F401
    main,
)

__all__ = [
    "EDGE_TOLERANCE", "FACTOR_RULE", "FIG2_T_BEGIN", "FIG3_FAMILY", "FIG5_VOLUME_SOLVER_JSON",
    "FRONT_MIN_RATE", "MAJORITY", "MissingRun", "N_BOOTSTRAP", "ORDER_RULE", "PAPER", "READINGS",
    "RELATIVE_RULE", "REPO", "RUNS", "Reading", "Report", "Row", "Run", "SIGMA_RULE", "STATISTICS_RUNS",
    "bootstrap", "burst_onset", "catalog_of", "combined_error", "example_event", "fig2_hierarchy",
    "fig5_volume_solver_text", "fit_peak_scaling", "fmt", "friction_steady_state", "local_peaks_of_pT",
    "main", "markdown", "material_label", "nucleation_event", "open_run_file", "peak_of_pT",
    "reading_conclusion", "ring_components", "run_description", "shown", "statistics_of", "tip_zones_of_run",
    "verdict_beats_chance", "verdict_bool", "verdict_class", "verdict_factor", "verdict_guide",
    "verdict_majority", "verdict_order", "verdict_relative", "verdict_sigma", "verdict_xmin_sweep",
    "wave_speeds", "xmin_sweep_cell",
]
