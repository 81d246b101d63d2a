"""The report's figures: each function draws one figure from measured data and
returns it; Report.add_figure writes it and lists it with its caption.  Every
map of log10(v/v0) is drawn by plots.draw_log_rate."""
from __future__ import annotations

import math

import numpy as np

from .. import analysis as an
from .. import plots
from ..plots import plt
from ..claims import BY_ID as PAPER
from .measurements import _finite
from .runs import FIG3_FAMILY


def space_slip_figure(delta_over_D, v_over_v0):
    """v(x, delta)/v0 over x/L and delta/D (Fig. 1b): rows at delta_over_D."""
    fig, ax = plt.subplots(figsize=(4.6, 3.8))
    n = v_over_v0.shape[1]
    im = plots.draw_log_rate(ax, np.arange(n) / n, delta_over_D, v_over_v0, 1.0, floor=-4.0, max_cells=500)
    fig.colorbar(im, ax=ax, label=r"$\log_{10}(v(x,\delta)/v_0)$")
    ax.set_xlabel("$x/L$")
    ax.set_ylabel(r"$\delta/D$")
    return fig


def event_figure(run, ex):
    """v(x, t)/v0 of one event (from the slip sampling), its slip, and the shear
    stress and state before (black) and after (green) it, arrest edges marked."""
    info = run.info
    fig, axes = plt.subplots(1, 4, figsize=(16, 3.4), gridspec_kw={"wspace": 0.45})
    x = ex["x"] / info.L  # unwrapped: may pass 1 when the window crosses the periodic boundary
    im = plots.draw_log_rate(axes[0], x, ex["t"] * info.c_s / info.L, ex["v"], info.v0, floor=-2.0)
    fig.colorbar(im, ax=axes[0], label=r"$\log_{10}(v/v_0)$")
    axes[0].set(xlabel="$x/L$", ylabel="$t c_s/L$", title="slip rate (from slip sampling)")
    axes[1].plot(x, ex["slip"] / info.D, "g")
    axes[1].set(xlabel="$x/L$", ylabel=r"$\Delta\delta/D$", title="slip of the event")
    if ex.get("tau_before") is not None:
        for ax, key, scale, lab in ((axes[2], "tau", info.sigma0, r"$\tau/\sigma_0$"), (axes[3], "phi", 1.0, r"$\phi$ [s]")):
            ax.plot(x, ex[f"{key}_before"] / scale, "k", lw=1)
            ax.plot(x, ex[f"{key}_after"] / scale, "g", lw=1)
            for e in ex["edges"]:
                ax.axvline(e / info.L, color="k", lw=0.6)
            ax.set(xlabel="$x/L$", ylabel=lab)
        axes[3].set_yscale("log")
    return fig


def nucleation_figure(name, t, x, v, run, ws, ev, tau):
    """Space-time map of a controlled nucleation (Fig. 3a/b), with the lines of
    c_R, c_s and c_d from the nucleation point, a bar of 2H/c_s (and of H for
    fig3b)."""
    L, cs = run.info.L, run.info.c_s
    fig, ax = plt.subplots(figsize=(4.6, 3.8))
    im = plots.draw_log_rate(ax, np.asarray(x) / L, t * cs / L, v, run.info.v0, floor=-2.0, max_cells=500)
    fig.colorbar(im, ax=ax, label=r"$\log_{10}(v/v_0)$")
    if ev.get("found"):
        x0 = float(run.config.get("initial", {}).get("local_center", L / 2)) / L
        t0 = ev["t_start"] * cs / L
        dt = np.linspace(0, (t[-1] - ev["t_start"]) * cs / L, 2)
        for key, style in (("c_R", ":"), ("c_s", "--"), ("c_d", "-")):
            c = ws[key] / cs
            for sgn in (1, -1):
                ax.plot(x0 + sgn * c * dt, t0 + dt, "w" + style, lw=0.8, label=key if sgn > 0 else None)
        ax.plot([x0, x0], [t0, t0 + tau * cs / L], "w-", lw=3, label="2H/c_s")
        if name == "fig3b":
            ax.plot([0.8, 0.8 + run.info.H / L], [t0 + 0.3, t0 + 0.3], "r-", lw=3, label="H")
        ax.set_xlim(0, 1)
        ax.set_ylim(t[0] * cs / L, t[-1] * cs / L)
        ax.legend(fontsize=6, loc="upper left")
    ax.set_xlabel("$x/L$")
    ax.set_ylabel("$t c_s/L$")
    ax.set_title(f"{name}: H = {run.info.H:g} m", fontsize=8)
    return fig


def pT_figure(fam):
    """p(T) and p(u/D) of the kept events of the H and c_s families (Figs.
    3c/3d, S7), arrows at 2H/c_s and eta v0 2H/c_s (eta of the Fig. S7 caption), dotted lines at the
    large-event peaks; None when no run has a PDF to draw."""
    fig, axes = plt.subplots(2, 2, figsize=(9, 7))
    groups = ((("fig3c_H005", "reference", "fig3c_H02"), "H family"),
              (("fig3d_rho300", "reference", "fig3d_rho4800"), "c_s family"))
    drawn = False
    eta = PAPER["s7_peak_position"].value
    for col, (names, title) in enumerate(groups):
        for row, (key, arrow, xlabel) in enumerate((("T", lambda s: s["tau"], "T [s]  (arrows: 2H/c_s)"),
                                                    ("u", lambda s: eta * s["run"].info.v0 * s["tau"] / s["run"].info.D,
                                                     f"u/D  (arrows: {eta:g} v0 2H/c_s, Fig. S7)"))):
            ax = axes[row, col]
            for i, n in enumerate(names):
                s = fam[n]
                if s is None:
                    continue
                xs = np.asarray(s["kept"]["T"], float) if key == "T" else s["obs"]["u"]
                c, p, _ = an.log_binned_pdf(xs)
                m = p > 0
                if m.any():
                    drawn = True
                    label = f"{n}: H = {s['run'].info.H:g} m, c_s = {s['run'].info.c_s:.0f} m/s"
                    ax.loglog(c[m], p[m], "-o", ms=2, color=f"C{i}", label=label)
                    ax.annotate("", xy=(arrow(s), p[m].min()), xytext=(arrow(s), p[m].min() * 0.1),
                                arrowprops=dict(arrowstyle="->", color=f"C{i}"))
                    peak = s["T_peak"] if key == "T" else s["u_peak"]
                    if _finite(peak):
                        ax.axvline(peak, color=f"C{i}", lw=0.6, ls=":")
            ax.set_xlabel(xlabel + "; dotted: large-event peak")
            ax.set_title(title, fontsize=8)
            ax.legend(fontsize=6)
    axes[0, 0].set_ylabel("p(T)")
    axes[1, 0].set_ylabel("p(u/D)")
    if drawn:
        return fig
    plt.close(fig)
    return None


def tpeak_fit_figure(fam, fit):
    """T_peak of the large events against 2H/c_s, with the power-law fit."""
    fig, ax = plt.subplots(figsize=(4.2, 3.4))
    for i, n in enumerate(FIG3_FAMILY):
        s = fam[n]
        if s is not None and _finite(s["T_peak"]):
            ax.errorbar(s["tau"], s["T_peak"], yerr=s["T_peak_err"], fmt="o", color=f"C{i}", label=n, ms=4)
    g = np.logspace(math.log10(min(s["tau"] for s in fam.values() if s) / 1.5),
                    math.log10(max(s["tau"] for s in fam.values() if s) * 1.5), 20)
    ax.loglog(g, fit["k"] * g ** fit["beta"], "k-", lw=0.8, label=f"beta = {fit['beta']:.2f}")
    ax.loglog(g, g, "k:", lw=0.8, label="T = 2H/c_s")
    ax.set_xlabel("2H/c_s [s]")
    ax.set_ylabel("T_peak [s]")
    ax.legend(fontsize=6)
    return fig


def fig5_figure(t, x, v, run, episodes, onset):
    """Space-time map of the whole Fig. 5 run; a red bar at the right edge over
    the windows where the pulse criterion holds, the criterion's onset dashed."""
    fig, ax = plt.subplots(figsize=(4.6, 3.8))
    im = plots.draw_log_rate(ax, np.asarray(x) / run.info.L, t / run.length_transit_time, v, run.info.v0,
                             floor=-2.0, max_cells=500)
    fig.colorbar(im, ax=ax, label=r"$\log_{10}(v/v_0)$")
    for (t0, t1), flag in zip(episodes["windows"] if episodes else [], episodes["flags"] if episodes else []):
        if flag:  # windows where the space-time pulse criterion holds
            ax.axvspan(0.97, 1.0, ymin=(t0 - t[0]) / (t[-1] - t[0]), ymax=(t1 - t[0]) / (t[-1] - t[0]),
                       color="r")
    if _finite(onset):
        ax.axhline(onset / run.length_transit_time, color="w", ls="--", lw=0.8, label="pulse onset (criterion)")
        ax.legend(fontsize=6)
    ax.set_xlabel("$x/L$")
    ax.set_ylabel("$t c_s/L$")
    return fig


FIG5_ZOOM_TRANSITS = 10.0  # [L/c_s] the length of each panel of fig5_zoom_figure


def fig5_zoom_figure(t, x, v, run, episodes):
    """FIG5_ZOOM_TRANSITS L/c_s in the middle of the longest pulse stretch (if
    any) and the last FIG5_ZOOM_TRANSITS L/c_s of the Fig. 5 run, on one colour scale."""
    zooms = []
    span = FIG5_ZOOM_TRANSITS * run.length_transit_time
    if episodes and _finite(episodes["longest_start"]):
        mid = 0.5 * (episodes["longest_start"] + episodes["longest_end"])
        zooms.append(("pulse stretch", mid - 0.5 * span, mid + 0.5 * span))
    zooms.append(("end of the run", t[-1] - span, t[-1]))
    fig, axes = plt.subplots(1, len(zooms), figsize=(4.2 * len(zooms), 3.6), squeeze=False)
    im = None
    for ax, (label, t0, t1) in zip(axes[0], zooms):
        rows = (t >= t0) & (t <= t1)
        if np.count_nonzero(rows) < 2:
            continue
        # One colour scale for both panels.
        im = plots.draw_log_rate(ax, np.asarray(x) / run.info.L, t[rows] / run.length_transit_time, v[rows],
                                 run.info.v0, vmin=-2.0, vmax=1.5, max_cells=400)
        ax.set(xlabel="$x/L$", ylabel="$t c_s/L$", title=label)
    if im is not None:
        fig.colorbar(im, ax=axes[0, -1], label=r"$\log_{10}(v/v_0)$")
    return fig
