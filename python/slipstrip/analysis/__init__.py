"""Slip-event statistics, criteria and figures of run files (paper Figs. 1b-e,
2a-d, 5, S3-S9; docs/analysis.md).

Input is one run file (docs/output.md) with a slip-event catalog in group
/events (docs/events.md).  The catalog is produced by the C++ detector, called
in this process through the bindings (`run_event_detection`, the same calls as
`slipstrip events`); this package never re-derives catalog numbers itself.  The
one exception is the event-coloured space-slip map (Fig. S4b), whose colours
come from `group_nodal_slips`, a numpy re-implementation of the grouping used
for plotting only (a test checks that it finds the same number of events as
the C++ detector).

One module per concept, every name re-exported here (`slipstrip.analysis.X`):
  reading     run scales (RunInfo), the event catalog, snapshots, slip sampling
  statistics  normalised observables, PDFs, power-law and log-normal fits,
              slip fractions, transient cut, stationarity tests
  criteria    the periodic-pulse criteria (events, time series, space-time,
              window by window) and the waiting-time grouping of nodal slips
  figures     the figures of `analyze`
  command     analyze(), summarize_run() and `python3 -m slipstrip analyze`

Conventions (see docs/analysis.md):
  * normalisations: u_mean / D, T v0 / D, M0 / (mu D L)   (Figs. S8 captions);
  * small events: u_mean < D, large events: u_mean >= D;
  * exponents are reported positive: p(x) ~ x^(-exponent).

Command line (dispatched by `python3 -m slipstrip analyze ...`):
    analyze RUN.h5 [--out-dir DIR] [--pdf] [--alpha 15] [--event INDEX]
"""
from .reading import (  # noqa: F401
    CATALOG_FIELDS, DEFAULT_ALPHA, RunInfo, catalog_for, read_catalog, read_run_info, read_spacetime,
    run_event_detection,
)
from .statistics import (  # noqa: F401
    EXPONENT_XMIN_FACTORS, LognormalFit, MIN_FIT_EVENTS, POWER_LAW_CAUTION_EVENTS, PowerLawFit,
    SPANNING_FRACTION, STATIONARITY_BLOCKS, STATIONARITY_LEVEL, STATIONARITY_PERMUTATIONS, TRANSIENT_BATCHES,
    TRANSIENT_MAX_FRACTION, block_permutation_stationarity, catalog_statistics, exponent_xmin_sweep,
    fit_lognormal, fit_power_law, log_binned_pdf, mser_truncation, normalised_observables, slip_fractions,
    stationarity, stationary_part, subset_catalog, transient_cut,
)
from .criteria import (  # noqa: F401
    NodalSlipGroups, PULSE_EPISODE_WINDOW_TRANSITS, PULSE_LATE_FRACTION, PULSE_MAX_CV,
    PULSE_MAX_WIDTH_FRACTION, PULSE_MIN_CORRELATION, PULSE_MIN_MOVING_FRACTION, PULSE_MIN_RATE,
    PULSE_MIN_SNAPSHOTS, PULSE_MIN_SPANNING_EVENTS, PULSE_MIN_SPANNING_SLIP, PULSE_MIN_TRAVEL,
    group_nodal_slips, periodic_pulse_decision, periodic_pulse_from_catalog, periodic_pulse_from_spacetime,
    periodic_pulse_from_timeseries, periodic_pulse_of_run, pulse_episodes,
)
from .figures import (  # noqa: F401
    plot_event_fields, plot_event_map, plot_pdf_comparison, plot_pdfs, plot_space_slip, plot_space_time,
    slip_rate_space_slip,
)
from .command import (  # noqa: F401
    EmptyCatalog, FIGURE_NAMES, SENSITIVITY_ALPHAS, analysis_outputs, analyze, empty_catalog_reason,
    format_summary, main, summarize_run,
)

__all__ = [
    "CATALOG_FIELDS", "DEFAULT_ALPHA", "EXPONENT_XMIN_FACTORS", "EmptyCatalog", "FIGURE_NAMES",
    "LognormalFit", "MIN_FIT_EVENTS", "NodalSlipGroups", "POWER_LAW_CAUTION_EVENTS",
    "PULSE_EPISODE_WINDOW_TRANSITS", "PULSE_LATE_FRACTION", "PULSE_MAX_CV", "PULSE_MAX_WIDTH_FRACTION",
    "PULSE_MIN_CORRELATION", "PULSE_MIN_MOVING_FRACTION", "PULSE_MIN_RATE", "PULSE_MIN_SNAPSHOTS",
    "PULSE_MIN_SPANNING_EVENTS", "PULSE_MIN_SPANNING_SLIP", "PULSE_MIN_TRAVEL", "PowerLawFit", "RunInfo",
    "SENSITIVITY_ALPHAS", "SPANNING_FRACTION", "STATIONARITY_BLOCKS", "STATIONARITY_LEVEL",
    "STATIONARITY_PERMUTATIONS", "TRANSIENT_BATCHES", "TRANSIENT_MAX_FRACTION", "analysis_outputs",
    "analyze", "block_permutation_stationarity", "catalog_for", "catalog_statistics", "empty_catalog_reason",
    "exponent_xmin_sweep", "fit_lognormal", "fit_power_law", "format_summary", "group_nodal_slips",
    "log_binned_pdf", "main", "mser_truncation", "normalised_observables", "periodic_pulse_decision",
    "periodic_pulse_from_catalog", "periodic_pulse_from_spacetime", "periodic_pulse_from_timeseries",
    "periodic_pulse_of_run", "plot_event_fields", "plot_event_map", "plot_pdf_comparison", "plot_pdfs",
    "plot_space_slip", "plot_space_time", "pulse_episodes", "read_catalog", "read_run_info",
    "read_spacetime", "run_event_detection", "slip_fractions", "slip_rate_space_slip", "stationarity",
    "stationary_part", "subset_catalog", "summarize_run", "transient_cut",
]
