"""The report of one material reading: one method per section of the paper,
each adding one row per claim (claims.py) with a value, a verdict and its basis.

The figures (matplotlib) are imported by the methods that draw: loading the
runs, and refusing a missing one, needs no plotting library."""
from __future__ import annotations

import dataclasses
import math
import os
import shutil
import tempfile
import tomllib
from pathlib import Path

import numpy as np

from .. import analysis as an
from .. import hierarchy as hi
from .. import runfile
from ..claims import BY_ID, CLAIMS, MEASUREMENTS
from .measurements import (AGED_MIN_FRACTION, CRACK_MIN_R2, EDGE_TOLERANCE, EVENT5_MIN_EXTENT_H, FAST_SLIP_RATE,
                           FIG2_T_BEGIN, FIXED_EXTENT_FRACTION, MIN_SIDE_FRACTION, N_BOOTSTRAP, NUCLEATION_RADIUS_H,
                           PRECEDING_TRANSITS, PULSE_FRONT_WINDOW, QUIET_FRACTION, SMALL_EVENT_MIN_U,
                           STICK_SLIP_RATE, TIP_FRONT_WINDOW, _finite, bootstrap, combined_error, example_event,
                           fig2_hierarchy, fit_peak_scaling, friction_steady_state, nucleation_event, statistics_of,
                           tip_zones_of_run, wave_speeds, burst_onset)
from .runs import (FIG3_FAMILY, READINGS, REPO, STATISTICS_RUNS, RUNS, MissingRun, Reading, Run, catalog_of,
                   fig5_volume_solver_text, material_label, open_run_file)
from .verdicts import (FACTOR_RULE, LOGNORMAL_LEVEL, MAJORITY, RELATIVE_RULE, SIGMA_RULE, fmt, verdict_beats_chance, verdict_bool,
                       verdict_class, verdict_factor, verdict_guide, verdict_majority, verdict_order,
                       verdict_relative, verdict_sigma, xmin_sweep_cell)


PAPER = BY_ID  # claim id -> Claim (value, where, words)
# The Fig. 1b row: both kinds of cells, rapid slip and sticking, make at least
# this share of the map (a pattern, not a handful of cells).
MIN_PATTERN_SHARE = 0.1
# "the minimal size for propagating events": this quantile of L_s of the
# events with u >= D (the minimum itself is set by the detection filters).
MIN_SIZE_QUANTILE = 0.05
# A rupture growing both ways with its fronts at most at c_d has L_s/T <= 2 c_d.
BILATERAL_MAX_SPEED_CD = 2.0
# The power law of p(u) spans at least a decade below D: x_min <= this [D].
POWER_LAW_MAX_XMIN = 0.1
# Lc(H) is found by bisection to this relative tolerance (the default of
# stability/linear_stability.hpp's critical_wavelength, which the bindings use);
# two laws with the same linearisation give the same Lc to well within this:
LC_BISECTION_TOLERANCE = 1e-10
LC_SAME_TOLERANCE = 1e-6


def _pct(x: float) -> str:
    """A fraction as a percentage, as the rows print their criteria."""
    return f"{100 * x:g} %"


def _factor(f: float = FACTOR_RULE) -> str:
    return f"{f:g}"


@dataclasses.dataclass
class Row:
    id: str
    value: str
    verdict: str
    basis: str       # run(s) and material reading


class Report:
    def __init__(self, rundir: Path | None, figdir: Path, allow_missing: bool, allow_incomplete: bool,
                 doc_dir: Path, workdir: Path, n_bootstrap: int = N_BOOTSTRAP,
                 alphas=an.SENSITIVITY_ALPHAS, log=print, reading: Reading = READINGS["asrun"]):
        self.rundir = Path(rundir) if rundir is not None else None
        self.figdir, self.doc_dir, self.workdir = Path(figdir), Path(doc_dir), Path(workdir)
        self.allow_missing, self.allow_incomplete = allow_missing, allow_incomplete
        self.n_bootstrap, self.alphas, self.log = n_bootstrap, alphas, log
        self.reading = reading
        self.runs: dict[str, Run] = {}
        self.missing: dict[str, str] = {}
        self.rows: dict[str, Row] = {}
        self.figures: list[tuple[str, str]] = []  # (caption, relative path)
        self.stats: dict[str, dict] = {}
        self.stationarity_rows: list[list[str]] = []

    # -- inputs -------------------------------------------------------------
    def load(self):
        for name in RUNS:
            try:
                if self.rundir is None:
                    raise MissingRun(f"no run directory for the {self.reading.name} reading")
                run = open_run_file(self.rundir, name, self.allow_incomplete)
                label = material_label(run.config)
                if not label.startswith(self.reading.label):
                    raise MissingRun(f"RUNDIR/{name}.h5 is {label}, not the {self.reading.name} reading")
                self.runs[name] = run
            except MissingRun as err:
                if not self.allow_missing:
                    raise
                self.missing[name] = str(err)

    def not_run(self, *names) -> str | None:
        why = [self.missing[n] for n in names if n in self.missing]
        return f"not run ({'; '.join(why)})" if why else None

    def stat(self, name) -> dict | None:
        if name in self.missing:
            return None
        if name not in self.stats:
            self.log(f"report ({self.reading.key}): statistics of {name}")
            self.stats[name] = statistics_of(self.runs[name], self.workdir, self.n_bootstrap)
        return self.stats[name]

    def add(self, cid, value, verdict, basis):
        if cid not in BY_ID:
            raise KeyError(f"report row for an unknown claim id {cid!r} (claims.py)")
        self.rows[cid] = Row(cid, value, verdict, basis)

    def add_missing(self, cid, names):
        self.add(cid, self.not_run(*names) or "not computed", "not checkable (run missing)", ", ".join(names))

    def basis(self, *names) -> str:
        labels = {material_label(self.runs[n].config) for n in names if n in self.runs}
        return ", ".join(names) + ("; " + "; ".join(sorted(labels)) if labels else "")

    def figure(self, caption, name):
        rel = os.path.relpath(self.figdir / name, self.doc_dir)
        self.figures.append((caption, rel.replace(os.sep, "/")))

    def add_figure(self, fig, name, caption):
        """Writes `fig` as figdir/name (and closes it) and lists it with its caption."""
        self.figdir.mkdir(parents=True, exist_ok=True)
        from ..plots import plt
        fig.savefig(self.figdir / name, dpi=80, bbox_inches="tight")
        plt.close(fig)
        self.figure(caption, name)

    def guarded(self, method, cids):
        """Runs one section; an error that is not a missing run is re-raised
        unless --allow-missing, when its rows say what went wrong."""
        try:
            method()
        except MissingRun:
            raise
        except Exception as err:  # noqa: BLE001 - a section must not silently vanish
            if not self.allow_missing:
                raise
            for cid in cids:
                if cid not in self.rows:
                    self.add(cid, f"not computed ({type(err).__name__}: {str(err).splitlines()[0] if str(err) else ''})",
                             "not checkable (error)", "")

    # -- Fig. 1 -------------------------------------------------------------
    def fig1(self):
        s = self.stat("reference")
        for cid, obs in (("fig1c_exp_u", "u"), ("fig1d_exp_T", "T"), ("fig1e_exp_M0", "M0")):
            if s is None:
                self.add_missing(cid, ["reference"])
                continue
            st = s["stats"]
            a = st[f"small_exponent_{obs}"]
            e = combined_error(st[f"small_exponent_{obs}_err"], st[f"small_exponent_{obs}_bootstrap_err"])
            sweep = st.get(f"small_exponent_{obs}_xmin_sweep", [])
            value = (f"KS-optimal fit {fmt(a, e)} (MLE of a truncated power law, n = {st[f'small_exponent_{obs}_n']}, "
                     f"x_min = {fmt(st[f'small_exponent_{obs}_xmin'])}; error: larger of Fisher and bootstrap); "
                     f"x_min swept: " + xmin_sweep_cell(sweep))
            self.add(cid, value, verdict_guide(a, e, sweep, PAPER[cid].value), self.basis("reference"))
        for cid, obs in (("fig1d_lognormal_T", "T"), ("fig1e_lognormal_M0", "M0"), ("lognormal_u", "u")):
            if s is None:
                self.add_missing(cid, ["reference"])
                continue
            value, verdict = self._lognormal_cell(s["stats"][f"lognormal_{obs}"])
            self.add(cid, value, verdict if cid != "lognormal_u" else "—", self.basis("reference"))
        self._nonpropagating()
        cid = "small_slip_fraction"
        if s is None:
            self.add_missing(cid, ["reference"])
        else:
            u, Ls = np.asarray(s["kept"]["u_mean"]), np.asarray(s["kept"]["L_s"])
            D, L = s["run"].info.D, s["run"].info.L
            f = an.slip_fractions(u, Ls, D, L)["small"]
            err = bootstrap(np.column_stack([u, Ls]), lambda a: an.slip_fractions(a[:, 0], a[:, 1], D, L)["small"],
                            n=self.n_bootstrap)
            self.add(cid, f"{fmt(f, err)} (bootstrap over events)", verdict_sigma(f, err, PAPER[cid].value),
                     self.basis("reference"))
        cid = "fig1c_split_at_D"
        if s is None:
            self.add_missing(cid, ["reference"])
        else:
            sp = hi.density_split(s["obs"]["u"])
            err = bootstrap(s["obs"]["u"], lambda x: hi.density_split(x)["split"], n=min(self.n_bootstrap, 100))
            value = (f"minimum of the density of ln(u/D) between the power-law part and the hump at u = "
                     f"{fmt(sp['split'], err)} D (hump at {fmt(sp['hump'])} D, minimum/hump density "
                     f"{fmt(sp['depth'])}; kernel density, bootstrap error)")
            verdict = verdict_factor(sp["split"]) if _finite(sp["split"]) else "differs (no hump: no split)"
            self.add(cid, value, verdict, self.basis("reference"))
        cid = "reference_complex"
        if s is None:
            self.add_missing(cid, ["reference"])
        else:
            self.add(cid, self._regime_text(s) + f"; {s['stats']['n_events_small']} small / "
                     f"{s['stats']['n_events_large']} large events",
                     verdict_bool(s["complex"], f"state {s['regime']['state']}"), self.basis("reference"))
        cid = "fig1b_space_slip"
        if s is None:
            self.add_missing(cid, ["reference"])
        else:
            sm = self._space_slip_figure(s["run"], s["part"]["cut"]["t_cut"])
            if sm is None:
                self.add(cid, "no slip sampling", "no value", self.basis("reference"))
            else:
                # A cell of the map is one slip increment delta_th of one node: the share of cells
                # is a share of slip; a sticking node makes one long cell (a white line), so the
                # sticking is measured by the time its cells take.
                ok = sm["fast_slip"] >= MIN_PATTERN_SHARE and sm["stuck_time"] >= MIN_PATTERN_SHARE
                self.add(cid, f"over {fmt(sm['window_D'])} D of slip after the transient cut: {sm['fast_slip']:.0%} of "
                         f"the slip at v > {FAST_SLIP_RATE:g} v0 (rapid-slip patches), {sm['stuck_time']:.0%} of the "
                         f"time at v < {STICK_SLIP_RATE:g} v0 (sticking: the white lines); figure below",
                         verdict_bool(ok, f"both ≥ {_pct(MIN_PATTERN_SHARE)}" if ok else
                                      f"one of them < {_pct(MIN_PATTERN_SHARE)}"), self.basis("reference"))

    @staticmethod
    def _lognormal_cell(lf) -> tuple[str, str]:
        value = (f"mu = {fmt(lf['mu'])}, sigma = {fmt(lf['sigma'])}, n = {lf['n']}, KS = {fmt(lf['ks'])}, "
                 f"parametric-bootstrap p = {fmt(lf['ks_pvalue'])} (naive p = {fmt(lf['ks_pvalue_naive'])})")
        p = lf["ks_pvalue"]
        verdict = ("no value" if not _finite(p) else
                   f"agrees (not rejected at {_pct(LOGNORMAL_LEVEL)}, p = {p:.2g})" if p >= LOGNORMAL_LEVEL else
                   f"differs (rejected, p = {p:.2g})")
        return value, verdict

    def _nonpropagating(self):
        # The paper's statement is about the Fig. 1 run: small events have L_s/T well
        # above c_d (not constrained by causality).  Large events are "approximately"
        # propagating, i.e. constrained by causality: a bilateral rupture widens at both
        # ends, so its extent grows at most at 2 c_d, L_s/T <= 2 c_d (median).
        cid = "small_nonpropagating"
        parts, verdict = [], None
        bilateral = BILATERAL_MAX_SPEED_CD
        for name in ("reference", "fig2_L2"):
            s = self.stat(name)
            if s is None:
                parts.append(f"{name}: {self.not_run(name)}")
                continue
            k = s["kept"]
            cd = wave_speeds(s["run"].config)["c_d"]
            T, Ls = np.asarray(k["T"], float), np.asarray(k["L_s"], float)
            small = s["obs"]["u"] < 1.0
            ok = T > 0
            r = Ls / np.where(ok, T, 1.0)
            rs, rl = r[ok & small], r[ok & ~small]
            ms, ml = (float(np.median(rs)) if rs.size else math.nan), (float(np.median(rl)) if rl.size else math.nan)
            es, el = bootstrap(rs, np.median, n=self.n_bootstrap), bootstrap(rl, np.median, n=self.n_bootstrap)
            parts.append(f"{name} (L = {s['run'].info.L:g} m): median L_s/T of small events {fmt(ms / cd, es / cd)} c_d "
                         f"(n = {rs.size}, {np.mean(rs > cd):.0%} above c_d), of large events {fmt(ml / cd, el / cd)} c_d "
                         f"(n = {rl.size}, {np.mean(rl > bilateral * cd):.0%} above {bilateral:g} c_d); T = 0 events "
                         f"({int((~ok).sum())}) "
                         "left out")
            if name == "reference":
                good = None if not (_finite(ms) and _finite(ml)) else bool(ms - SIGMA_RULE * es > cd and
                                                                           ml + SIGMA_RULE * el <= bilateral * cd)
                verdict = verdict_bool(good, f"reference: small median above c_d, large median ≤ {bilateral:g} c_d, by "
                                             f"{SIGMA_RULE:g} σ")
        self.add(cid, "; ".join(parts), verdict or "not checkable (run missing)", self.basis("reference", "fig2_L2"))

    def _space_slip_figure(self, run, t_cut, window_D=400.0, max_rows=1500):
        """v(x, delta)/v0 over window_D of mean slip after the transient cut (Fig. 1b),
        and the fractions of its cells that slip fast and that stick."""
        from . import figures
        with runfile.open_h5(run.path) as f:
            if "slip_sampling" not in f:
                return None
            ct = f["slip_sampling/crossing_time"]
            n_levels = ct.shape[0]
            j0 = int(min(max(1, run.info.v0 * t_cut / run.info.delta_th), max(1, n_levels - 2)))
            j1 = int(min(n_levels, j0 + window_D * run.info.D / run.info.delta_th))
            if j1 - j0 < 2:
                return None
            step = max(1, (j1 - j0) // max_rows)
            rows = np.arange(j0, j1, step)
            cur = ct[rows.tolist()]
            prev = ct[(rows - 1).tolist()]
        with np.errstate(divide="ignore", invalid="ignore"):
            v = run.info.delta_th / (cur - prev) / run.info.v0
        self.add_figure(figures.space_slip_figure(rows * run.info.delta_th / run.info.D, v),
                        "reference_space_slip.png", f"Reference: space-slip map v(x, δ)/v0 over {window_D:g} D of "
                        "slip after the transient cut (Fig. 1b)")
        ok = np.isfinite(v) & (v > 0)
        fin = v[ok]
        dt = (cur - prev)[ok]
        return {"fast_slip": float(np.mean(fin > FAST_SLIP_RATE)) if fin.size else math.nan,
                "stuck_time": float(dt[fin < STICK_SLIP_RATE].sum() / dt.sum()) if fin.size and dt.sum() > 0 else math.nan,
                "window_D": (rows[-1] - rows[0]) * run.info.delta_th / run.info.D}

    # -- Fig. 2 -------------------------------------------------------------
    FIG2_IDS = ("fig2_event1_bilateral", "fig2_event1_vmax", "fig2_event1_duration", "fig2_event1_crack",
                "fig2_event1_arrest_minima", "fig2_event1_aging", "fig2_event1_stress_peaks", "fig2_events23_crack",
                "fig2_event4_from_arrest", "fig2_event5_bilateral_stage", "fig2_event5_pulses")

    def fig2(self):
        name = "fig2_events"
        if name in self.missing:
            for cid in self.FIG2_IDS:
                self.add_missing(cid, [name])
            return
        run = self.runs[name]
        res = fig2_hierarchy(run, catalog_of(run, an.DEFAULT_ALPHA, self.workdir))
        b = self.basis(name)
        tau = res["tau"]
        e1 = res["event1"]
        common = (f"{e1['n']} large (u ≥ D), arrested (L_s < {an.SPANNING_FRACTION:g} L), single-cluster events after "
                  f"{FIG2_T_BEGIN:g} L/c_s")
        self.add("fig2_event1_bilateral",
                 f"{common}: nucleation node at least {_pct(MIN_SIDE_FRACTION)} of L_s inside both arrest edges in "
                 f"{e1['bilateral']}; "
                 f"median distance to the nearer edge {fmt(e1['median_side_fraction'])} L_s",
                 verdict_majority(e1["bilateral"], e1["n"], "bilateral"), b)
        vmax = PAPER["fig2_event1_vmax"].value
        self.add("fig2_event1_vmax", f"{common}: median largest slip rate {fmt(e1['median_vmax'])} v0; > {vmax:g} v0 "
                 f"in {e1['vmax_ok']}", verdict_majority(e1["vmax_ok"], e1["n"], f"v > {vmax:g} v0"), b)
        self.add("fig2_event1_duration", f"{common}: median T = {fmt(e1['median_T_tau'])} (2H/c_s); within a factor "
                 f"{_factor()} of 2H/c_s in {e1['duration_ok']}",
                 verdict_majority(e1["duration_ok"], e1["n"], "T ~ 2H/c_s"), b)
        self.add("fig2_event1_crack", f"{common}: least squares of A sqrt(h² - (x - x_c)²) to the event's slip "
                 f"(from the slip sampling): median R² = {fmt(e1['median_r2'])}; R² ≥ {CRACK_MIN_R2:g} in "
                 f"{e1['crack_ok']}", verdict_majority(e1["crack_ok"], e1["n"], f"crack-like (R² ≥ {CRACK_MIN_R2:g})"), b)
        f = res["fields"]
        fields_note = (f"{f['n']} of the {e1['n']} events have snapshots within "
                       f"{fmt(f['max_gap'] / tau)} (2H/c_s) before and after them with no slip near them larger "
                       f"than {QUIET_FRACTION:g} of theirs in between")
        self.add("fig2_event1_arrest_minima",
                 f"{fields_note}; arrest edges within {EDGE_TOLERANCE} dx of a local minimum of the pre-event shear "
                 f"stress: {f['edge_minima']} of {f['n_edges']}",
                 verdict_beats_chance(f["edge_minima"], f["n_edges"], f["null_minima"], "edges at a stress minimum"), b)
        self.add("fig2_event1_aging",
                 f"{fields_note}; nodes within L_s/2 outside the slip zone that did not slip: φ grew at "
                 f"{fmt(f['aged_fraction'])} of them; at ≥ {_pct(AGED_MIN_FRACTION)} of them in {f['aging_ok']} events",
                 verdict_majority(f["aging_ok"], f["n"], "contact aging outside"), b)
        self.add("fig2_event1_stress_peaks",
                 f"{fields_note}; the largest post-event shear stress within L_s/4 of an arrest edge lies within "
                 f"{EDGE_TOLERANCE} dx of it at {f['edge_peaks']} of {f['n_edges']} edges",
                 verdict_beats_chance(f["edge_peaks"], f["n_edges"], f["null_peaks"], "stress peak at the edge")
                 if f["n_edges"] and f["edge_peaks"] / f["n_edges"] > MAJORITY else
                 verdict_majority(f["edge_peaks"], f["n_edges"], "stress peak at the edge"), b)
        e23 = res["events23"]
        self.add("fig2_events23_crack",
                 f"{e23['n']} small single-cluster events with {SMALL_EVENT_MIN_U:g} D ≤ u < D after "
                 f"{FIG2_T_BEGIN:g} L/c_s: L_s/T > c_d in {e23['nonprop']}; crack-like slip (R² ≥ {CRACK_MIN_R2:g}) in "
                 f"{e23['crack']}; slip zone at half the duration ≥ {_pct(FIXED_EXTENT_FRACTION)} of the final one in "
                 f"{e23['fixed']}; all three in {e23['all']}",
                 verdict_majority(e23["all"], e23["n"], "non-propagating, crack-like, fixed extent"), b)
        e4 = res["event4"]
        self.add("fig2_event4_from_arrest",
                 f"{e4['n']} large events with an arrest edge of a large event in the preceding "
                 f"{PRECEDING_TRANSITS:g} L/c_s: nucleated within {NUCLEATION_RADIUS_H:g} H of such an edge "
                 f"{e4['near']} times",
                 verdict_beats_chance(e4["near"], e4["n"], e4["null"], "nucleated at an earlier arrest edge"), b)
        e5 = res["event5"]
        common5 = (f"{e5['n']} large events of extent ≥ {EVENT5_MIN_EXTENT_H:g} H after {FIG2_T_BEGIN:g} L/c_s "
                   "(v(x, t) from the slip sampling)")
        self.add("fig2_event5_bilateral_stage",
                 f"{common5}: slip at the nucleation node lasts a median {fmt(e5['median_center_tau'])} (2H/c_s); "
                 f"within a factor {_factor()} of 2H/c_s in {e5['center_ok']}",
                 verdict_majority(e5["center_ok"], e5["n"], "bilateral stage ~ 2H/c_s"), b)
        self.add("fig2_event5_pulses",
                 f"{common5}: two pulses after the centre stops in {e5['two_pulses']} (median pulse width "
                 f"{fmt(e5['median_width_H'])} H); two pulses of width within a factor {_factor()} of H in "
                 f"{e5['pulses_ok']}",
                 verdict_majority(e5["pulses_ok"], e5["n"], "two pulses of size ~ H"), b)
        if res.get("example") is not None:
            self._event_figure(run, res["example"], "fig2_event_example.png",
                               f"Fig. 2 events: v(x, t)/v0 of the largest bilateral event after {FIG2_T_BEGIN:g} L/c_s, "
                               "reconstructed "
                               "from the slip sampling (as the paper's Fig. S5b), and its slip, shear stress and state "
                               "before (black) and after (green) it")

    def _event_figure(self, run, ex, fname, caption):
        from . import figures
        self.add_figure(figures.event_figure(run, ex), fname, caption)

    # -- Fig. 3a/b ----------------------------------------------------------
    def fig3ab(self):
        claims_by_run = {"fig3a": ("fig3a_duration",),
                         "fig3b": ("fig3b_center_stop", "fig3b_pulses", "fig3b_speed", "fig3b_width")}
        pulse_window = f"{PULSE_FRONT_WINDOW[0]:g}-{PULSE_FRONT_WINDOW[1]:g}"
        tips = {}
        for name, cids in claims_by_run.items():
            if name in self.missing:
                for cid in cids:
                    self.add_missing(cid, [name])
                continue
            run = self.runs[name]
            ws = wave_speeds(run.config)
            tau = 2 * run.info.H / run.info.c_s
            with runfile.open_h5(run.path) as f:
                t, x, v = f["snapshots/time"][:], f["snapshots/x"][:], f["snapshots/slip_rate"][:]
            x0 = float(run.config.get("initial", {}).get("local_center", run.info.L / 2))
            ev = nucleation_event(t, x, v, run.info.v0, x0, run.info.L, ws["c_d"])
            self._spacetime_figure(name, t, x, v, run, ws, ev, tau)
            if ev["found"]:
                tips[name] = tip_zones_of_run(run, t, x, v, ev, x0)
            if not ev["found"]:
                for cid in cids:
                    self.add(cid, f"no slip above {fmt(ev['v_th'] / run.info.v0)} v0 at x0", "no value",
                             self.basis(name))
                continue
            speed = (f"front speed {fmt(ev['front_speed'] / ws['c_d'], ev['front_speed_err'] / ws['c_d'])} c_d "
                     f"= {fmt(ev['front_speed'] / ws['c_s'], ev['front_speed_err'] / ws['c_s'])} c_s")
            common = (f"threshold v > {fmt(ev['v_th'] / run.info.v0)} v0; snapshots every "
                      f"{fmt(ev['snapshot_interval'] / tau)} (2H/c_s)")
            for cid in cids:
                if cid == "fig3a_duration":
                    r = ev["center_duration"] / tau
                    arrested = ev["end_reason"] == "arrest" and ev["max_extent"] < an.SPANNING_FRACTION * run.info.L
                    value = (f"duration at x0 {fmt(r, ev['snapshot_interval'] / tau)} (2H/c_s); event ends by "
                             f"{ev['end_reason']} after {fmt((ev['t_end'] - ev['t_start']) / tau)} (2H/c_s), extent "
                             f"{fmt(ev['max_extent'] / run.info.L)} L; {speed}; {common}")
                    v_ = verdict_factor(r)
                    verdict = v_ if arrested else f"differs (no arrest: {ev['end_reason']}); duration {v_}"
                elif cid == "fig3b_center_stop":
                    r = ev["center_duration"] / tau
                    value = (f"slip at x0 stops after {fmt(r, ev['snapshot_interval'] / tau)} (2H/c_s) "
                             f"= {fmt(ev['center_duration'] * 1e3)} ms; {common}")
                    verdict = verdict_factor(r)
                elif cid == "fig3b_pulses":
                    value = (f"{ev['n_pulses']} pulse(s) while the fronts are {pulse_window} L from x0; event ends by "
                             f"{ev['end_reason']} (extent {fmt(ev['max_extent'] / run.info.L)} L); {common}")
                    verdict = verdict_bool(ev["n_pulses"] == 2 and ev["end_reason"] == "traversal",
                                           f"{ev['n_pulses']} pulses, {ev['end_reason']}")
                elif cid == "fig3b_speed":
                    # "supershear, i.e., ... close to c_d": above c_s by 2 sigma, and nearer c_d than c_s.
                    value = f"{speed}; c_R = {fmt(ws['c_R'] / ws['c_d'])} c_d, c_s = {fmt(ws['c_s'] / ws['c_d'])} c_d"
                    sp, er = ev["front_speed"], ev["front_speed_err"]
                    supershear = _finite(sp) and _finite(er) and sp - SIGMA_RULE * er > ws["c_s"]
                    nearer = _finite(sp) and abs(sp - ws["c_d"]) < abs(sp - ws["c_s"])
                    verdict = verdict_bool(None if not _finite(sp) else (supershear and nearer),
                                           f"{'above' if supershear else 'not above'} c_s by {SIGMA_RULE:g} σ, nearer "
                                           f"{'c_d' if nearer else 'c_s'}")
                else:
                    r = ev["pulse_width"] / run.info.H
                    value = (f"width {fmt(r, ev['pulse_width_err'] / run.info.H)} H (median over snapshots with the "
                             f"fronts {pulse_window} L from x0; error: half inter-quartile range + dx); {common}")
                    verdict = verdict_factor(r)
                self.add(cid, value, verdict, self.basis(name))
        # The process zone: the breakdown zone at the tips of the nucleated ruptures.
        cid = "pz_resolved"
        if not tips:
            self.add_missing(cid, ["fig3a", "fig3b"])
        else:
            sizes = np.concatenate([t_["sizes"] for t_ in tips.values()]) if tips else np.array([])
            dx = next(iter(self.runs[n] for n in tips)).info.L / next(iter(self.runs[n] for n in tips)).info.n_nodes
            med = float(np.median(sizes)) if sizes.size else math.nan
            err = bootstrap(sizes, np.median, n=self.n_bootstrap) if sizes.size > 1 else math.nan
            parts = [f"{n}: median {fmt(np.median(t_['sizes']) / dx) if t_['sizes'].size else 'n/a'} dx over "
                     f"{t_['sizes'].size} snapshots" for n, t_ in tips.items()]
            self.add(cid, f"tip zone (peak shear stress to {_pct(hi.TIP_ZONE_DROP)} of its drop behind the tip, fronts "
                     f"{TIP_FRONT_WINDOW[0]:g}-{TIP_FRONT_WINDOW[1]:g} L from x0): {fmt(med / dx, err / dx if _finite(err) else None)} dx = {fmt(med * 1e3)} mm "
                     f"({'; '.join(parts)})", verdict_factor(med / dx / PAPER[cid].value) if _finite(med) else "no value",
                     self.basis(*tips))

    def _spacetime_figure(self, name, t, x, v, run, ws, ev, tau):
        from . import figures
        self.add_figure(figures.nucleation_figure(name, t, x, v, run, ws, ev, tau), f"{name}_spacetime.png",
                        f"{name}: space-time map of log10(v/v0), wave-speed lines from the nucleation point, "
                        f"bar 2H/c_s")

    # -- Figs. 3c/3d, S7 ------------------------------------------------------
    def fig3cd(self):
        fam = {n: self.stat(n) for n in FIG3_FAMILY}
        have = {n: s for n, s in fam.items() if s is not None and _finite(s["T_peak"]) and _finite(s["T_peak_err"])}
        # Where the peaks lie relative to the arrows (a measurement: the paper marks 2H/c_s, it does not put the peak there).
        parts = []
        for n in FIG3_FAMILY:
            s = fam[n]
            if s is None:
                parts.append(f"{n}: {self.not_run(n)}")
                continue
            parts.append(f"{n}: T_peak = {fmt(s['T_peak'] * 1e3, s['T_peak_err'] * 1e3)} ms = "
                         f"{fmt(s['T_peak'] / s['tau'], s['T_peak_err'] / s['tau'])} (2H/c_s), 2H/c_s = "
                         f"{fmt(s['tau'] * 1e3)} ms, {int(np.sum(s['obs']['u'] >= 1))} large events"
                         + self._local_peaks_text(s))
        self.add("fig3_peak_position", "; ".join(parts) + " (mode of a kernel density of ln T, bootstrap error)",
                 "—", self.basis(*FIG3_FAMILY))

        # The family's parameter as the runs have it (their configs), not as typed here.
        family_parameter = {"H": lambda run: f"{run.info.H:g} m",
                            "rho": lambda run: f"{float(run.config['material']['density']):g} kg/m³"}

        def order(names, cid, key, what, parameter, unit_scale, unit):
            if any(fam[n] is None for n in names):
                self.add_missing(cid, [n for n in names if fam[n] is None])
                return
            label = f"{what} ({parameter} = " + ", ".join(family_parameter[parameter](fam[n]["run"]) for n in names) + ")"
            vals = [(fam[n][key], fam[n][f"{key}_err"]) for n in names]
            z = [(b_[0] - a_[0]) / math.hypot(a_[1], b_[1]) if _finite(a_[1]) and _finite(b_[1]) else math.nan
                 for a_, b_ in zip(vals, vals[1:])]
            value = f"{label}: " + " < ".join(f"{fmt(v * unit_scale, e * unit_scale)} {unit}" for v, e in vals) + \
                "; steps " + ", ".join(f"{q:+.1f} σ" for q in z)
            ok = None if not all(_finite(q) for q in z) else all(q > 0 for q in z)
            self.add(cid, value, verdict_bool(ok, "each step > 0" if ok else "not increasing at every step"),
                     self.basis(*names))

        order(("fig3c_H005", "reference", "fig3c_H02"), "fig3c_shift", "T_peak", "T_peak", "H", 1e3, "ms")
        order(("fig3d_rho300", "reference", "fig3d_rho4800"), "fig3d_shift", "T_peak", "T_peak", "rho", 1e3, "ms")
        order(("fig3c_H005", "reference", "fig3c_H02"), "s7_shift_H", "u_peak", "large-event peak of p(u)", "H",
              1.0, "D")
        order(("fig3d_rho300", "reference", "fig3d_rho4800"), "s7_shift_cs", "u_peak", "large-event peak of p(u)",
              "rho", 1.0, "D")
        cid = "s7_peak_position"
        if any(fam[n] is None for n in FIG3_FAMILY):
            self.add_missing(cid, [n for n in FIG3_FAMILY if fam[n] is None])
        else:
            eta = PAPER[cid].value
            self.add(cid, "; ".join(f"{n}: u_peak = {fmt(fam[n]['u_peak'], fam[n]['u_peak_err'])} D = "
                                    f"{fmt(fam[n]['u_peak'] * fam[n]['run'].info.D / (eta * fam[n]['run'].info.v0 * fam[n]['tau']))}"
                                    f" ({eta:g} v0 2H/c_s)" for n in FIG3_FAMILY), "—", self.basis(*FIG3_FAMILY))
        cid = "fig3_collapse"
        pairs = (("fig3c_H005", "fig3d_rho300"), ("fig3c_H02", "fig3d_rho4800"))
        if any(fam[n] is None for p in pairs for n in p):
            self.add_missing(cid, [n for p in pairs for n in p if fam[n] is None])
        else:
            parts, zs = [], []
            for a_, b_ in pairs:
                sa, sb = fam[a_], fam[b_]
                z = (sa["T_peak"] - sb["T_peak"]) / math.hypot(sa["T_peak_err"], sb["T_peak_err"])
                zs.append(z)
                parts.append(f"{a_} vs {b_} (2H/c_s = {fmt(sa['tau'] * 1e3)} / {fmt(sb['tau'] * 1e3)} ms): "
                             f"{fmt(sa['T_peak'] * 1e3, sa['T_peak_err'] * 1e3)} vs "
                             f"{fmt(sb['T_peak'] * 1e3, sb['T_peak_err'] * 1e3)} ms ({z:+.1f} σ)")
            ok = None if not all(_finite(z) for z in zs) else all(abs(z) <= SIGMA_RULE for z in zs)
            self.add(cid, "; ".join(parts),
                     verdict_bool(ok, f"|Δ| ≤ {SIGMA_RULE:g} σ for both pairs" if ok else
                                  f"a pair differs by > {SIGMA_RULE:g} σ"),
                     self.basis(*FIG3_FAMILY))
        cid = "fig3_peak_fit"
        if len(have) < 3:
            if any(n in self.missing for n in FIG3_FAMILY):
                self.add_missing(cid, [n for n in FIG3_FAMILY if n not in have])
            else:
                self.add(cid, "fewer than 3 runs with a peak", "—", self.basis(*FIG3_FAMILY))
        elif len({round(have[n]["tau"], 12) for n in have}) < 2:
            self.add(cid, "no fit: every run has the same 2H/c_s", "—", self.basis(*FIG3_FAMILY))
        else:
            fit = fit_peak_scaling([have[n]["tau"] for n in have], [have[n]["T_peak"] for n in have],
                                   [have[n]["T_peak_err"] for n in have])
            self.fit = fit
            self.add(cid, f"beta = {fmt(fit['beta'], fit['beta_err'])}, k = {fmt(fit['k'], fit['k_err'])} "
                     f"({len(have)} runs, weighted least squares in log); proportional fit T_peak = k1 (2H/c_s): "
                     f"k1 = {fmt(fit['k1'], fit['k1_err'])}, chi2/dof = {fmt(fit['chi2_1'] / max(1, fit['dof_1']))}, "
                     f"p = {fmt(fit['p_1'])}", "—", self.basis(*FIG3_FAMILY))
        # Small events: the paper's Fig. 3c-d show p(T); "weakly dependent" is tested as the
        # guide-to-the-eye rule of Fig. 1: each run's small-event T exponent lies within the
        # reference's fit-range systematic widened by 2 sigma.
        cid = "fig3_small"
        if any(fam[n] is None for n in FIG3_FAMILY):
            self.add_missing(cid, [n for n in FIG3_FAMILY if fam[n] is None])
        else:
            sweep = fam["reference"]["stats"].get("small_exponent_T_xmin_sweep", [])
            lo = min((f["exponent"] - SIGMA_RULE * f["stderr"] for f in sweep), default=math.nan)
            hi_ = max((f["exponent"] + SIGMA_RULE * f["stderr"] for f in sweep), default=math.nan)
            ex = {n: (fam[n]["stats"]["small_exponent_T"],
                      combined_error(fam[n]["stats"]["small_exponent_T_err"],
                                     fam[n]["stats"]["small_exponent_T_bootstrap_err"])) for n in FIG3_FAMILY}
            inside = [n for n, (a_, e_) in ex.items() if _finite(a_) and lo <= a_ <= hi_]
            ok = None if not (_finite(lo) and all(_finite(a_) for a_, _ in ex.values())) else len(inside) == len(ex)
            self.add(cid, "small-event exponent of p(T v0/D) (KS-optimal fits): " +
                     "; ".join(f"{n} {fmt(a_, e_)}" for n, (a_, e_) in ex.items()) +
                     f"; reference fit-range systematic {fmt(lo)}-{fmt(hi_)}",
                     verdict_bool(ok, f"{len(inside)} of {len(ex)} within the reference's fit range"),
                     self.basis(*FIG3_FAMILY))
        self._pT_figure(fam)

    def _pT_figure(self, fam):
        from . import figures
        fig = figures.pT_figure(fam)
        if fig is not None:
            self.add_figure(fig, "pT_families.png", "Figs. 3c/3d and S7: p(T) and p(u/D) of the kept events, arrows at "
                            f"2H/c_s (T) and {PAPER['s7_peak_position'].value:g} v0 2H/c_s (u), dotted lines at the "
                            "large-event peaks")
        if getattr(self, "fit", None):
            self.add_figure(figures.tpeak_fit_figure(fam, self.fit), "tpeak_fit.png",
                            "T_peak of the large events against 2H/c_s, with the power-law fit")

    @staticmethod
    def _local_peaks_text(s) -> str:
        peaks = s.get("T_local_peaks") or []
        if len(peaks) < 2:
            return ""
        return "; local maxima of p(T) at " + ", ".join(
            f"{fmt(T / s['tau'])} (height {fmt(h)})" for T, h in peaks) + " (2H/c_s)"

    @staticmethod
    def _regime_text(s) -> str:
        r = s["regime"]
        return (f"state {r['state']} ({'converged' if r['converged'] else 'NOT converged'}, thirds "
                f"{'/'.join(r['states_by_third'])}, agreement {fmt(r['agreement'])}; docs/transition.md)")

    # -- robustness -----------------------------------------------------------
    def robustness(self):
        for name, pre in (("fig4_slip_law", "fig4"), ("s10_D_over_3", "s10"), ("s11_a_over_3", "s11"), ("s12", "s12")):
            s = self.stat(name)
            ids = (f"{pre}_complex", f"{pre}_exponents", f"{pre}_lognormal_T")
            if s is None:
                for cid in ids:
                    self.add_missing(cid, [name])
                continue
            st = s["stats"]
            self.add(f"{pre}_complex", self._regime_text(s) + f"; {st['n_events_small']} small / "
                     f"{st['n_events_large']} large events", verdict_bool(s["complex"], f"state {s['regime']['state']}"),
                     self.basis(name))
            parts, oks = [], []
            for key, obs in (("fig1c_exp_u", "u"), ("fig1d_exp_T", "T"), ("fig1e_exp_M0", "M0")):
                a = st[f"small_exponent_{obs}"]
                e = combined_error(st[f"small_exponent_{obs}_err"], st[f"small_exponent_{obs}_bootstrap_err"])
                sweep = st.get(f"small_exponent_{obs}_xmin_sweep", [])
                v = verdict_guide(a, e, sweep, PAPER[key].value)
                oks.append(verdict_class(v))
                lo = min((f["exponent"] for f in sweep), default=math.nan)
                hi_ = max((f["exponent"] for f in sweep), default=math.nan)
                parts.append(f"{obs}: KS-optimal {fmt(a, e)}, fit range {fmt(lo)}-{fmt(hi_)} vs "
                             f"{PAPER[key].value:g}: {v}")
            verdict = ("agrees (all three within their fit-range systematic)" if all(o == "agree" for o in oks) else
                       "differs (" + ", ".join(o for o, k in zip(("u", "T", "M0"), oks) if k == "differ") +
                       " outside the fit-range systematic)" if any(o == "differ" for o in oks) else "no value")
            self.add(f"{pre}_exponents", "; ".join(parts), verdict, self.basis(name))
            value, verdict = self._lognormal_cell(st["lognormal_T"])
            self.add(f"{pre}_lognormal_T", value, verdict, self.basis(name))
        cid = "fig4_larger"
        s4, sr = self.stat("fig4_slip_law"), self.stat("reference")
        if s4 is None or sr is None:
            self.add_missing(cid, ["fig4_slip_law", "reference"])
        else:
            def extents(s):
                return np.asarray(s["kept"]["L_s"], float)[s["obs"]["u"] >= 1] / s["run"].info.L
            a, b = extents(s4), extents(sr)
            ma, mb = (float(a.mean()) if a.size else math.nan), (float(b.mean()) if b.size else math.nan)
            ea, eb = bootstrap(a, np.mean, n=self.n_bootstrap), bootstrap(b, np.mean, n=self.n_bootstrap)
            ratio = ma / mb if _finite(ma) and _finite(mb) and mb > 0 else math.nan
            err = ratio * math.hypot(ea / ma, eb / mb) if _finite(ratio) else math.nan
            ok = None if not (_finite(ratio) and _finite(err)) else bool(ratio - 1 > SIGMA_RULE * err)
            self.add(cid, f"mean L_s/L of large events: slip law {fmt(ma, ea)}, aging {fmt(mb, eb)}; ratio {fmt(ratio, err)}",
                     verdict_bool(ok, f"ratio > 1 by > {SIGMA_RULE:g} σ" if ok else f"ratio not > 1 by {SIGMA_RULE:g} σ"),
                     self.basis("fig4_slip_law", "reference"))
        cid = "s10_min_propagating"
        s10 = self.stat("s10_D_over_3")
        if s10 is None or sr is None:
            self.add_missing(cid, ["s10_D_over_3", "reference"])
        else:
            # "minimal size for propagating events": the smallest extents of the events the
            # paper calls propagating (u >= D); a low quantile (MIN_SIZE_QUANTILE), as the
            # minimum itself is set by the detection filters.
            def q05(s):
                return np.asarray(s["kept"]["L_s"], float)[s["obs"]["u"] >= 1]
            a, b = q05(s10), q05(sr)
            qa = float(np.quantile(a, MIN_SIZE_QUANTILE)) if a.size else math.nan
            qb = float(np.quantile(b, MIN_SIZE_QUANTILE)) if b.size else math.nan
            ea = bootstrap(a, lambda x: np.quantile(x, MIN_SIZE_QUANTILE), n=self.n_bootstrap)
            eb = bootstrap(b, lambda x: np.quantile(x, MIN_SIZE_QUANTILE), n=self.n_bootstrap)
            z = (qb - qa) / math.hypot(ea, eb) if _finite(ea) and _finite(eb) and math.hypot(ea, eb) > 0 else math.nan
            ok = None if not _finite(z) else bool(z > SIGMA_RULE)
            self.add(cid, f"{_pct(MIN_SIZE_QUANTILE)} quantile of L_s of the events with u ≥ D: D / 3 "
                     f"{fmt(qa * 1e3, ea * 1e3)} mm "
                     f"(n = {a.size}, minimum {fmt(a.min() * 1e3) if a.size else 'n/a'} mm), reference "
                     f"{fmt(qb * 1e3, eb * 1e3)} mm (n = {b.size}, minimum {fmt(b.min() * 1e3) if b.size else 'n/a'} mm); "
                     f"difference {fmt(z, digits=2)} σ",
                     verdict_bool(ok, f"smaller by > {SIGMA_RULE:g} σ" if ok else f"not smaller by {SIGMA_RULE:g} σ"),
                     self.basis("s10_D_over_3", "reference"))

    # -- Fig. 5 and the friction curves ----------------------------------------
    def fig5(self):
        for name, cid in (("fig5", "fig5_pulse"), ("fig5_H02", "fig5_H02"), ("reference", "reference_no_pulse")):
            s = self.stat(name)
            if s is None:
                self.add_missing(cid, [name])
                continue
            p = s["pulse"]
            ps = p["periodic_pulse_spacetime"]
            tr = s["run"].length_transit_time
            value = f"periodic_pulse = {p['periodic_pulse']} (criterion: {p['periodic_pulse_basis']})"
            if ps.get("determined"):
                value += (f"; late half: min max-slip-rate {fmt(ps['min_max_slip_rate_v0'])} v0, slipping width "
                          f"{fmt(ps['median_width_fraction'])} L, shape correlation {fmt(ps['median_correlation'])}, "
                          f"moving one way {fmt(ps['moving_fraction'])}, travelled {fmt(ps['travelled_periods'])} L")
                if p["periodic_pulse"]:
                    value += (f"; speed {fmt(ps['speed_median'] / s['run'].info.c_s)} c_s "
                              f"(range {fmt(ps['speed_min'] / s['run'].info.c_s)}-"
                              f"{fmt(ps['speed_max'] / s['run'].info.c_s)}); pulse from t = "
                              f"{fmt(ps['onset_time'] / tr)} L/c_s (coarsening transient)")
            episodes = self._pulse_episodes(s)
            if episodes is not None:
                n_pulse = sum(episodes["flags"])
                value += (f"; same criterion in {fmt(an.PULSE_EPISODE_WINDOW_TRANSITS)} L/c_s windows: pulse in "
                          f"{n_pulse} of {len(episodes['flags'])}")
                if n_pulse:
                    value += (f", longest stretch t = {fmt(episodes['longest_start'] / tr)}-"
                              f"{fmt(episodes['longest_end'] / tr)} L/c_s")
            if name == "fig5":
                verdict = verdict_bool(p["periodic_pulse"])
                if not p["periodic_pulse"] and episodes is not None and sum(episodes["flags"]):
                    verdict = (f"differs (a pulse only for t = {fmt(episodes['longest_start'] / tr)}-"
                               f"{fmt(episodes['longest_end'] / tr)} L/c_s, not in the late half)")
                if not p["periodic_pulse"]:
                    verdict += fig5_volume_solver_text()
            elif name == "fig5_H02":
                verdict = verdict_bool(not s["complex"], f"state {s['regime']['state']}")
                value += "; " + self._regime_text(s) + f"; {s['stats']['n_events_small']} small / " \
                         f"{s['stats']['n_events_large']} large events"
            else:
                verdict = verdict_bool(not p["periodic_pulse"])
            self.add(cid, value, verdict, self.basis(name))
            if name == "fig5":
                self._fig5_figure(s)
        self.friction_rows()

    def friction_rows(self):
        """Steady-state friction of the configs (Eqs. S1-S2): independent of the material."""
        cfg = {n: tomllib.loads((REPO / "configs" / f"{n}.toml").read_text()) for n in ("reference", "fig5", "s12")}
        ss = {n: friction_steady_state(c["friction"], float(c["loading"]["driving_velocity"])) for n, c in cfg.items()}
        basis = "configs/reference.toml, fig5.toml, s12.toml (Eqs. S1-S2; no run)"
        p_ref, p_5 = PAPER["fss_slopes"].value
        v1, v2 = verdict_relative(ss["reference"]["slope"], p_ref), verdict_relative(ss["fig5"]["slope"], p_5)
        both = verdict_class(v1) == "agree" and verdict_class(v2) == "agree"
        self.add("fss_slopes", f"d f_ss/d ln v at v0: Table S1 {ss['reference']['slope']:.4g}, Fig. 5 "
                 f"{ss['fig5']['slope']:.4g} (ratio {ss['reference']['slope'] / ss['fig5']['slope']:.3g})",
                 verdict_bool(both, f"Table S1 {v1}; Fig. 5 {v2}"), basis)
        for cid, n in (("fig5_fss", "fig5"), ("s12_fss", "s12")):
            r = ss[n]["f_ss"] / ss["reference"]["f_ss"] - 1
            steeper = ss[n]["slope"] < ss["reference"]["slope"]
            ok = abs(r) <= RELATIVE_RULE and (steeper if n == "s12" else not steeper)
            self.add(cid, f"f_ss(v0) = {ss[n]['f_ss']:.4f} vs {ss['reference']['f_ss']:.4f} ({r:+.2%}); slope "
                     f"{ss[n]['slope']:.4g} vs {ss['reference']['slope']:.4g}",
                     verdict_bool(ok, f"f_ss within {RELATIVE_RULE:.0%}, slope "
                                  f"{'steeper' if steeper else 'shallower'}"), basis)

    def _pulse_episodes(self, s):
        """pulse_episodes of a run's snapshots (None without snapshots); cached per run."""
        cache = s.setdefault("_pulse_episodes", {})
        if "value" not in cache:
            st = an.read_spacetime(s["run"].path, max_rows=6000)
            cache["value"] = None if st is None else an.pulse_episodes(
                st[0], st[2], s["run"].info.v0, s["run"].info.L / st[2].shape[1],
                window=an.PULSE_EPISODE_WINDOW_TRANSITS * s["run"].length_transit_time)
        return cache["value"]

    def _fig5_figure(self, s):
        from . import figures
        st = an.read_spacetime(s["run"].path, max_rows=2000)
        if st is None:
            return
        t, x, v = st
        run = s["run"]
        episodes = self._pulse_episodes(s)
        onset = s["pulse"]["periodic_pulse_spacetime"].get("onset_time", math.nan)
        self.add_figure(figures.fig5_figure(t, x, v, run, episodes, onset), "fig5_spacetime.png",
                        "Fig. 5 friction: space-time map of log10(v/v0) (whole run); red bar at the right edge: "
                        "windows where the space-time pulse criterion holds")
        self.add_figure(figures.fig5_zoom_figure(t, x, v, run, episodes), "fig5_zoom.png",
                        f"Fig. 5 friction: {figures.FIG5_ZOOM_TRANSITS:g} L/c_s in the middle of the longest stretch "
                        f"where the pulse criterion holds, and the last {figures.FIG5_ZOOM_TRANSITS:g} L/c_s")

    # -- procedure: stationarity, threshold, clusters, counts ---------------------
    def procedure(self):
        for name in STATISTICS_RUNS:
            s = self.stat(name)
            if s is None:
                self.stationarity_rows.append([name, self.not_run(name)] + [""] * 11)
                continue
            part, run = s["part"], s["run"]
            st = part["stationarity"]
            cut = part["cut"]
            self.stationarity_rows.append([
                name, f"{fmt(cut['t_cut'])} s = {fmt(cut['t_cut'] / run.length_transit_time)} L/c_s "
                      f"({cut['batches_dropped_rate']}/{cut['batches_dropped_slip']} of {cut['n_batches']} batches)",
                f"{fmt(run.info.duration / run.length_transit_time)} L/c_s", str(len(part["catalog"]["t_start"])),
                f"{st['n_first']} / {st['n_last']}",
                *(fmt(st[k]["pvalue"], digits=2) for k in ("u", "T", "M0")),
                "yes" if part["stationary"] else "no",
                *(fmt(part["stationarity_blocks"][k]["pvalue"], digits=2) for k in ("u", "T", "M0")),
                "yes" if part["stationary_blocks"] else "no"])
        self._first_events()
        self._counts_and_example()
        self._noise()
        s = self.stat("reference")
        ids = ("stationary", "s9_power_law", "s9_crossover", "s9_lognormal", "s9_max_size", "clusters")
        if s is None:
            for cid in ids:
                self.add_missing(cid, ["reference"])
            return
        part, run = s["part"], s["run"]
        st, sb, cut = part["stationarity"], part["stationarity_blocks"], part["cut"]
        value = (f"cut {fmt(cut['t_cut'] / run.length_transit_time)} L/c_s of {fmt(run.info.duration / run.length_transit_time)}; "
                 "first vs last fifth of what is kept, block-permutation KS p (serially dependent events, "
                 f"{sb['n_blocks']} blocks): " + ", ".join(f"{k} {fmt(sb[k]['pvalue'], digits=2)}" for k in ("u", "T", "M0")) +
                 "; plain KS p (assumes independent events): " +
                 ", ".join(f"{k} {fmt(st[k]['pvalue'], digits=2)}" for k in ("u", "T", "M0")))
        level = an.STATIONARITY_LEVEL
        detail = (f"block-permutation p ≥ {level:g} for u, T, M0" if part["stationary_blocks"] else
                  f"some block-permutation p < {level:g}")
        if part["stationary_blocks"] and not part["stationary"]:
            detail += f"; the plain KS test, which assumes independent events, has some p < {level:g}"
        self.add("stationary", value, verdict_bool(part["stationary_blocks"], detail), self.basis("reference"))
        self._alpha_rows(s)
        self._cluster_row(s)
        self._reference_figures(s)

    def _alpha_rows(self, s):
        run = s["run"]
        t_cut = s["part"]["cut"]["t_cut"]
        res = {}
        for a in self.alphas:
            self.log(f"report ({self.reading.key}): reference at alpha = {a:g}")
            cat = s["catalog"] if float(a) == an.DEFAULT_ALPHA else catalog_of(run, a, self.workdir)
            kept = an.subset_catalog(cat, np.asarray(cat["t_start"], float) >= t_cut)
            st = an.catalog_statistics(kept, run.info, n_bootstrap=0)
            obs = an.normalised_observables(kept, run.info)
            res[a] = {"st": st, "split": hi.density_split(obs["u"])["split"], "max_u": float(np.max(obs["u"]))
                      if obs["u"].size else math.nan, "max_M0": float(np.max(obs["M0"])) if obs["M0"].size else math.nan,
                      "n": st["n_events"]}
        b = self.basis("reference")
        # Power law for every alpha: the KS-optimal fit of u < D spans at least a decade below D.
        spans = {a: r["st"]["small_exponent_u_xmin"] for a, r in res.items()}
        ok = all(_finite(x) and x <= POWER_LAW_MAX_XMIN for x in spans.values())
        self.add("s9_power_law", "; ".join(
            f"alpha {a:g}: exponent {fmt(r['st']['small_exponent_u'], r['st']['small_exponent_u_err'])} on "
            f"[{fmt(r['st']['small_exponent_u_xmin'])}, 1] D (KS {fmt(r['st']['small_exponent_u_ks'])}, n = "
            f"{r['st']['small_exponent_u_n']} of {r['n']})" for a, r in res.items()) + " (same transient cut; Fisher errors)",
                 verdict_bool(ok, f"every fit spans ≥ {-math.log10(POWER_LAW_MAX_XMIN):g} decade (x_min ≤ "
                              f"{POWER_LAW_MAX_XMIN:g} D)" if ok else
                              f"some fit spans < {-math.log10(POWER_LAW_MAX_XMIN):g} decade"), b)
        base = res.get(an.DEFAULT_ALPHA, {}).get("split", math.nan)
        ratios = {a: r["split"] / base for a, r in res.items() if _finite(r["split"]) and _finite(base)}
        ok = None if len(ratios) < len(res) else all(1 / FACTOR_RULE <= q <= FACTOR_RULE for q in ratios.values())
        self.add("s9_crossover", "split of p(u) (minimum of the density of ln u before the hump): " + "; ".join(
            f"alpha {a:g}: {fmt(r['split'])} D" for a, r in res.items()),
                 verdict_bool(ok, f"within a factor {_factor()} of alpha = {an.DEFAULT_ALPHA:g}'s" if ok else
                              f"not within a factor {_factor()} of alpha = {an.DEFAULT_ALPHA:g}'s (or no hump)"), b)
        lf = {a: r["st"]["lognormal_T"] for a, r in res.items()}
        ok = None if not all(_finite(x["ks_pvalue"]) for x in lf.values()) else all(
            x["ks_pvalue"] >= LOGNORMAL_LEVEL for x in lf.values())
        self.add("s9_lognormal", "log-normal of T (u ≥ D): " + "; ".join(
            f"alpha {a:g}: KS {fmt(x['ks'])}, p = {fmt(x['ks_pvalue'])} (n = {x['n']})" for a, x in lf.items()),
                 verdict_bool(ok, f"not rejected at {_pct(LOGNORMAL_LEVEL)} for any alpha" if ok else
                              f"rejected at {_pct(LOGNORMAL_LEVEL)} for some alpha"), b)
        alphas = sorted(res)
        mu = [res[a]["max_u"] for a in alphas]
        mm = [res[a]["max_M0"] for a in alphas]
        ok = None if not all(_finite(q) for q in mu + mm) else (
            all(b_ >= a_ for a_, b_ in zip(mu, mu[1:])) and all(b_ >= a_ for a_, b_ in zip(mm, mm[1:])))
        self.add("s9_max_size", "largest u/D and M0/(mu D L): " + "; ".join(
            f"alpha {a:g}: {fmt(res[a]['max_u'])}, {fmt(res[a]['max_M0'])}" for a in alphas),
                 verdict_bool(ok, "non-decreasing with alpha" if ok else "not non-decreasing with alpha"), b)

    def _cluster_row(self, s):
        # The paper: "most events are composed of a single cluster (note the semi-logarithmic
        # scale)" in Fig. S6, whose run is not stated (the section's example is an H = 0.2 m
        # run).  Tested as: n_c = 1 is the most common number of clusters, in the reference
        # and in the H = 0.2 m run; the single-cluster fraction is shown.
        parts, oks = [], []
        for name in ("reference", "fig3c_H02"):
            s_ = self.stat(name)
            if s_ is None:
                parts.append(f"{name}: {self.not_run(name)}")
                oks.append(None)
                continue
            nc = np.asarray(s_["kept"]["n_clusters"], int) if "n_clusters" in s_["kept"] else np.array([], int)
            if not nc.size:
                parts.append(f"{name}: no n_clusters")
                oks.append(None)
                continue
            counts = np.bincount(np.minimum(nc, 4), minlength=5)
            f1 = counts[1] / nc.size
            e1 = math.sqrt(f1 * (1 - f1) / nc.size)
            mode = int(np.argmax(counts))
            parts.append(f"{name}: " + ", ".join(f"n_c = {k}: {counts[k] / nc.size:.1%}" for k in range(4)) +
                         f", n_c ≥ 4: {counts[4] / nc.size:.1%} (n = {nc.size}); single-cluster fraction {fmt(f1, e1)}")
            oks.append(mode == 1)
        ok = None if any(o is None for o in oks) else all(oks)
        self.add("clusters", "; ".join(parts), verdict_bool(ok, "n_c = 1 is the most common value in both runs" if ok
                                                            else "n_c = 1 is not the most common value in both runs"),
                 self.basis("reference", "fig3c_H02"))

    def _first_events(self):
        cid = "first_event_spans"
        have = [n for n in STATISTICS_RUNS if n in self.runs]
        if not have:
            self.add_missing(cid, list(STATISTICS_RUNS))
            return
        ext = {}
        for n in have:
            fe = hi.first_event(self.runs[n].path, an.DEFAULT_ALPHA)
            ext[n] = fe
        spanning = [n for n in have if ext[n]["extent"] >= an.SPANNING_FRACTION]
        missing = [n for n in STATISTICS_RUNS if n not in have]
        value = (f"first detected event (alpha = {an.DEFAULT_ALPHA:g}, before the catalog drops it) covers " +
                 ", ".join(f"{n} {'≥ ' if not ext[n]['complete'] else ''}{ext[n]['extent']:.0%}" for n in have) +
                 " of the interface (≥: the event lasts beyond the first rows read; the nodes it reached there)"
                 + (f"; not run: {', '.join(missing)}" if missing else ""))
        self.add(cid, value, verdict_bool(len(spanning) == len(have),
                                          f"{len(spanning)} of {len(have)} runs span ≥ {an.SPANNING_FRACTION:.0%}"),
                 self.basis(*have))

    def _counts_and_example(self):
        name = "fig3c_H02"
        s = self.stat(name)
        for cid in ("ns_and_events", "s5_event"):
            if s is None:
                self.add_missing(cid, [name])
        if s is None:
            return
        attrs = s["catalog"]["attrs"]
        ns, nev = int(attrs.get("n_nodal_slips", 0)), int(len(s["catalog"]["t_start"]))
        run = s["run"]
        p_ns, p_ev = PAPER["ns_and_events"].value
        ratio = (ns / nev) if nev else math.nan
        self.add("ns_and_events", f"H = {run.info.H:g} m run of {fmt(run.info.duration)} s: {ns:.3g} nodal slips, {nev} events "
                 f"({ns / max(nev, 1):.3g} NS per event; the paper: O({p_ns / p_ev:.0e}) with a run length not stated, "
                 f"so the ratio is compared)", verdict_order(ratio / (p_ns / p_ev)) if _finite(ratio) else "no value",
                 self.basis(name))
        large = s["obs"]["u"] >= 1
        vmax = np.asarray(s["kept"]["max_slip_rate"], float)[large] / run.info.v0
        vmax = vmax[np.isfinite(vmax)]
        cd = wave_speeds(run.config)["c_d"]
        T, Ls = np.asarray(s["kept"]["T"], float)[large], np.asarray(s["kept"]["L_s"], float)[large]
        bilateral = BILATERAL_MAX_SPEED_CD
        prop = np.mean(Ls[T > 0] / T[T > 0] <= bilateral * cd) if np.any(T > 0) else math.nan
        med = float(np.median(vmax)) if vmax.size else math.nan
        v_ = verdict_order(med / PAPER["s5_event"].value) if _finite(med) else "no value"
        ok = verdict_class(v_) == "agree" and _finite(prop) and prop > MAJORITY
        self.add("s5_event", f"large events of the H = {run.info.H:g} m run: median largest slip rate {fmt(med)} v0 "
                 f"(n = {vmax.size}); {prop:.0%} with L_s/T ≤ {bilateral:g} c_d (causal: growing at wave speeds); figure of one "
                 "event's v(x, t) reconstructed from the slip sampling below",
                 verdict_bool(ok, f"slip rate {v_}; propagating in {prop:.0%}"), self.basis(name))
        ex = example_event(run, s["kept"], s["obs"])
        if ex is not None:
            self._event_figure(run, ex, "s5_event.png", "Fig. S5: v(x, t)/v0 of the median large event of the "
                               f"H = {run.info.H:g} m run, reconstructed from the slip sampling, and its slip")

    def _noise(self):
        # "Numerical noise" is tested with noise at the round-off level (1e-12 relative): a
        # spectral solver started exactly uniform stays uniform to round-off (configs/noise_tiny.toml).
        cid = "noise_transient"
        names = ("noise_tiny", "reference")
        if any(n in self.missing for n in names):
            self.add_missing(cid, [n for n in names if n in self.missing])
            return
        on = burst_onset(self.runs["reference"])
        off = burst_onset(self.runs["noise_tiny"])
        tr = self.runs["reference"].length_transit_time
        amp = self.runs["noise_tiny"].config.get("initial", {}).get("noise_amplitude", math.nan)
        amp_ref = self.runs["reference"].config.get("initial", {}).get("noise_amplitude", math.nan)
        value = (f"first time the largest slip rate exceeds {FAST_SLIP_RATE:g} v0: noise {amp_ref:g} (reference) "
                 f"{fmt(on['t'] / tr)} L/c_s; "
                 + (f"noise {amp:g} {fmt(off['t'] / tr)} L/c_s, when the slip rate is "
                    f"{'uniform' if off.get('uniform') else 'non-uniform'} along x (spread of log10 v over x "
                    f"{fmt(off.get('spread'))})" if _finite(off["t"]) else
                    f"noise {amp:g}: never in {fmt(off['duration'] / tr)} L/c_s (the largest slip rate stays within "
                    f"{off['max_deviation']:.1e} of v0)"))
        triggered = _finite(off["t"]) and not off.get("uniform", False)
        ok = triggered and _finite(on["t"]) and on["t"] < off["t"]
        self.add(cid, value, verdict_bool(ok, "round-off-level noise triggers it too, later" if ok else
                                          "round-off-level noise triggers no non-uniform burst" if not triggered else
                                          "the larger noise does not shorten the transient"), self.basis(*names))

    def _reference_figures(self, s):
        run = s["run"]
        tmp = Path(tempfile.mkdtemp(dir=self.workdir))
        for path in an.plot_pdfs(s["kept"], run.info, s["stats"], tmp):
            self.figdir.mkdir(parents=True, exist_ok=True)
            shutil.move(path, self.figdir / "reference_pdfs.png")
        self.figure("Reference: p(u/D), p(T v0/D), p(M0/(mu D L)) of the kept events, power-law fits of the small "
                    "events, log-normal fits of the large events", "reference_pdfs.png")
        k, t_cut, t_end = s["kept"], s["part"]["cut"]["t_cut"], run.info.duration
        t = np.asarray(k["t_start"], float)
        span = t_end - t_cut
        sets = {"kept": k, "first fifth": an.subset_catalog(k, t < t_cut + 0.2 * span),
                "last fifth": an.subset_catalog(k, t > t_cut + 0.8 * span)}
        for path in an.plot_pdf_comparison(sets, run.info, tmp, "stationarity"):
            shutil.move(path, self.figdir / "reference_stationarity.png")
        self.figure("Reference: PDFs of the kept events, of the first and of the last fifth of the kept time "
                    "(Fig. S8)", "reference_stationarity.png")

    # -- Lc(H) ----------------------------------------------------------------
    LC_IDS = ("Lc_01", "Lc_over_H_01", "Lc_ratio_005", "Lc_ratio_01", "Lc_ratio_02", "Lc5_01", "Lc5_02", "Lc_over_dx",
              "pz_formula", "fig4_Lc_same", "s10_Lc_smaller", "s11_Lc_smaller", "s12_Lc_smaller", "k0_mode")

    def lc_rows(self):
        over = dict(self.reading.overrides)
        cfg = tomllib.loads((REPO / "configs" / "reference.toml").read_text())
        m, fr = cfg["material"], cfg["friction"]
        mu = float(over.get("material.shear_modulus", float(m.get("youngs_modulus", 0)) / (2 * (1 + float(m["poisson_ratio"])))
                                                     if "youngs_modulus" in m else float(m["shear_modulus"])))
        nu = float(m["poisson_ratio"])
        pz = mu * float(fr["characteristic_slip"]) / (float(fr["b"]) * float(cfg["loading"]["normal_stress"]) * (1 - nu))
        dx = float(cfg["geometry"]["length"]) / int(cfg["geometry"]["nodes"])
        label = self.reading.label
        self.add("pz_formula", f"μD/(bσ0(1-ν)) = {pz:.3g} m with μ = {mu / 1e9:.3g} GPa (= {pz / dx:.3g} dx)",
                 verdict_relative(pz, PAPER["pz_formula"].value), "configs/reference.toml; " + label)
        try:
            import slipstrip as ss
        except ImportError as err:
            if not self.allow_missing:
                raise MissingRun(f"the slipstrip bindings (_slipstrip) are not importable: {err}")
            for cid in self.LC_IDS:
                if cid not in self.rows:
                    self.add(cid, f"not computed (bindings not importable: {err})", "not checkable (no bindings)", "")
            return

        def load(name, extra=None):
            return ss.load_config(str(REPO / "configs" / f"{name}.toml"), {**over, **(extra or {})})

        ref = load("reference")
        # The heights are the paper's (claims.CLAIMS); the other Lc rows (mesh,
        # slip law, Figs. S10-S12) are at the reference height of Lc_01.
        H1 = PAPER["Lc_01"].height
        ratio_ids = ("Lc_ratio_005", "Lc_ratio_01", "Lc_ratio_02")
        heights = sorted({H1, *(PAPER[cid].height for cid in ratio_ids)}) + [math.inf]
        lc_at = dict(zip(heights, ss.critical_wavelength_vs_height(ref, heights)))
        lc1, lc_inf = lc_at[H1], lc_at[math.inf]
        fig5_ids = ("Lc5_01", "Lc5_02")
        lc5 = ss.critical_wavelength_vs_height(load("fig5"), [PAPER[cid].height for cid in fig5_ids])
        tol = f"bisection to {LC_BISECTION_TOLERANCE:g} relative"
        basis = "configs/reference.toml; " + label
        self.add("Lc_01", f"{lc1:.4g} m ({tol})", verdict_relative(lc1, PAPER["Lc_01"].value), basis)
        H_ratio = PAPER["Lc_over_H_01"].height
        self.add("Lc_over_H_01", f"{lc_at[H_ratio] / H_ratio:.3g}",
                 verdict_relative(lc_at[H_ratio] / H_ratio, PAPER["Lc_over_H_01"].value), basis)
        for cid in ratio_ids:
            lc = lc_at[PAPER[cid].height]
            self.add(cid, f"{lc / lc_inf:.1%} (Lc = {lc:.4g} m, Lc(inf) = {lc_inf:.4g} m)",
                     verdict_relative(lc / lc_inf, PAPER[cid].value), basis)
        for cid, lc in zip(fig5_ids, lc5):
            self.add(cid, f"{lc:.4g} m, Lc/H = {lc / PAPER[cid].height:.3g}", verdict_relative(lc, PAPER[cid].value),
                     "configs/fig5.toml; " + label)
        self.add("Lc_over_dx", f"Lc({H1:g} m)/dx = {lc1 / dx:.3g} (dx = {dx * 1e3:g} mm)",
                 verdict_order(lc1 / dx / PAPER["Lc_over_dx"].value), basis)
        slip = ss.critical_wavelength_vs_height(load("reference", {"state.law": "slip"}), [H1])[0]
        r = slip / lc1 - 1
        self.add("fig4_Lc_same", f"Lc({H1:g} m): slip law {slip:.6g} m, aging law {lc1:.6g} m ({r:+.1e} relative)",
                 verdict_bool(abs(r) <= LC_SAME_TOLERANCE, f"equal to {LC_SAME_TOLERANCE:g} (the bisection "
                              f"tolerance is {LC_BISECTION_TOLERANCE:g})"),
                 "configs/reference.toml --set state.law=slip; " + label)
        for cid, name in (("s10_Lc_smaller", "s10_D_over_3"), ("s11_Lc_smaller", "s11_a_over_3"), ("s12_Lc_smaller", "s12")):
            v = ss.critical_wavelength_vs_height(load(name), [H1])[0]
            self.add(cid, f"Lc({H1:g} m) = {v:.4g} m vs {lc1:.4g} m ({v / lc1 - 1:+.0%})",
                     verdict_bool(v < lc1, "smaller" if v < lc1 else "not smaller"), f"configs/{name}.toml; {label}")
        try:
            g = ss.growth_rates(ref, [math.inf])
            rate = float(np.asarray(g["growth_rate"])[0])
            self.add("k0_mode", f"growth rate {rate:.4g} 1/s ({'unstable' if rate > 0 else 'stable'}; mu/(2H) vs the "
                     "critical stiffness, docs/stability.md)", "—", basis)
        except Exception as err:  # noqa: BLE001 - not a claim of the paper
            self.add("k0_mode", f"not computed ({err})", "—", basis)

    # -- build ----------------------------------------------------------------
    SECTIONS = ("fig1", "fig2", "fig3ab", "fig3cd", "robustness", "fig5", "procedure", "lc_rows")

    def build(self):
        section_ids = {}
        for c in CLAIMS + MEASUREMENTS:
            section_ids.setdefault(c.section, []).append(c.id)
        every = [c.id for c in CLAIMS + MEASUREMENTS]
        for name in self.SECTIONS:
            self.guarded(getattr(self, name), every)
        for cid in every:  # a claim no section wrote is a bug: say so in its row, never drop it
            if cid not in self.rows:
                self.add(cid, "no row computed (the report writes none for this claim)", "not checkable (no row)", "")

    def counts(self) -> dict:
        out = {"agree": 0, "differ": 0, "not checkable": 0}
        for c in CLAIMS:
            out[verdict_class(self.rows[c.id].verdict if c.id in self.rows else "")] += 1
        return out
