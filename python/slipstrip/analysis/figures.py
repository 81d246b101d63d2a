"""Figures of `analyze` (paper Figs. 1b-e, 2a-d, S3-S9): matplotlib, Agg
backend, PNG (and PDF on request)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..runfile import open_h5, read_times
from .criteria import NodalSlipGroups
from .reading import RunInfo, _stride
from .statistics import _log_norm, log_binned_pdf, normalised_observables, observable_labels


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _save(fig, out_dir: Path, name: str, pdf: bool) -> list[str]:
    paths = [out_dir / f"{name}.png"]
    fig.savefig(paths[0], dpi=130, bbox_inches="tight")
    if pdf:
        paths.append(out_dir / f"{name}.pdf")
        fig.savefig(paths[1], bbox_inches="tight")
    _plt().close(fig)
    return [str(p) for p in paths]


def plot_space_time(path, info: RunInfo, out_dir: Path, pdf: bool = False) -> list[str]:
    """log10(|v|/v0) in the x/L -- t c_s/L plane from /snapshots (Figs. 2a, S3a):
    the figure of `slipstrip plot` (plots.spacetime_axes, same colour map),
    with the colour scale starting at most 3 decades below v0."""
    from .. import plots
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6, 5))
    mesh = plots.spacetime_axes(path, ax, floor=-3.0)
    fig.colorbar(mesh, ax=ax, label=r"$\log_{10}(v/v_0)$")
    return _save(fig, out_dir, "space_time", pdf)


def slip_rate_space_slip(crossing_time: np.ndarray, delta_th: float) -> np.ndarray:
    """v(x, delta) = delta_th / Delta t, Delta t = crossing_time[j] - crossing_time[j-1]
    (j = 0: from t = 0).  NaN where the level was not reached; inf for Delta t = 0."""
    ct = np.asarray(crossing_time, float)
    prev = np.vstack([np.zeros((1, ct.shape[1])), ct[:-1]])
    with np.errstate(divide="ignore", invalid="ignore"):
        return delta_th / (ct - prev)


def plot_space_slip(ct, x, info: RunInfo, out_dir: Path, pdf: bool = False, max_rows: int = 3000) -> list[str]:
    """v(x, delta)/v0 in the x/L -- delta/D plane (Figs. 1b, S3b)."""
    from .. import plots
    plt = _plt()
    v = slip_rate_space_slip(ct, info.delta_th)
    delta = (np.arange(ct.shape[0]) + 1) * info.delta_th / info.D
    fig, ax = plt.subplots(figsize=(6, 5))
    # The colour scale starts at most 4 decades below v0.
    im = plots.draw_log_rate(ax, x / info.L, delta, v, info.v0, floor=-4.0, max_cells=max_rows)
    fig.colorbar(im, ax=ax, label=r"$\log_{10}(v(x,\delta)/v_0)$")
    ax.set_xlabel("$x/L$")
    ax.set_ylabel(r"$\delta/D$")
    return _save(fig, out_dir, "space_slip", pdf)


def plot_event_map(groups: NodalSlipGroups, x, info: RunInfo, out_dir: Path, pdf: bool = False,
                   max_rows: int = 3000) -> list[str]:
    """Each nodal slip coloured by its (kept) event; grey: NS of removed events (Fig. S4b)."""
    plt = _plt()
    from matplotlib.colors import ListedColormap
    step = _stride(groups.label.shape[0], max_rows)
    lab = groups.label[::step]
    kept_index = np.cumsum(groups.kept) - 1  # colour index among kept events
    colour = np.full(lab.shape, np.nan)
    has = lab >= 0
    kept_ns = has.copy()
    kept_ns[has] = groups.kept[lab[has]]
    colour[kept_ns] = kept_index[lab[kept_ns]] % 20
    grey = has & ~kept_ns
    delta = (np.arange(0, groups.label.shape[0], step) + 1) * info.delta_th / info.D
    fig, ax = plt.subplots(figsize=(6, 5))
    ax.pcolormesh(x / info.L, delta, np.ma.masked_where(~grey, grey.astype(float)), shading="auto",
                  cmap=ListedColormap(["0.8"]), rasterized=True)
    ax.pcolormesh(x / info.L, delta, np.ma.masked_invalid(colour), shading="auto", cmap="tab20",
                  vmin=0, vmax=20, rasterized=True)
    ax.set_xlabel("$x/L$")
    ax.set_ylabel(r"$\delta/D$")
    ax.set_title(f"{int(groups.kept.sum())} events (alpha grouping re-done in numpy; grey: removed)",
                 fontsize=8)
    return _save(fig, out_dir, "event_map", pdf)


def _legend(ax) -> None:
    """A legend only for axes that show a labelled curve (matplotlib warns on an empty one)."""
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)


def _pdf_line(ax, x, label, **kw):
    c, p, _ = log_binned_pdf(x)
    m = p > 0
    if m.any():
        ax.loglog(c[m], p[m], label=label, **kw)


def plot_pdfs(catalog: dict, info: RunInfo, stats_: dict, out_dir: Path, pdf: bool = False) -> list[str]:
    """p(u/D), p(T v0/D), p(M0/(mu D L)) with the power-law and log-normal fits (Fig. 1c-e);
    on a 2D interface p(M0/(mu D L W)) and a fourth panel p(A/(L W))."""
    plt = _plt()
    from scipy import stats  # imported where used: most of the commands' start-up time
    obs = normalised_observables(catalog, info)
    large = obs["u"] >= 1.0
    labels = observable_labels(info)
    fig, axes = plt.subplots(1, len(obs), figsize=(14 * len(obs) / 3, 4.2))
    n_all = max(1, np.sum(np.isfinite(obs["u"]) & (obs["u"] > 0)))
    for ax, name in zip(axes, obs):
        _pdf_line(ax, obs[name], "all events", marker="o", ms=3, color="C1")
        c, p, _ = log_binned_pdf(obs[name][large])
        m = p > 0
        if m.any():  # large events, weighted by their share so that both curves are on one scale
            ax.loglog(c[m], p[m] * large.sum() / n_all, "--", color="green", label=r"$\bar u \geq D$")
        fit = stats_["_fits"][name]
        if np.isfinite(fit.exponent):
            xs = np.logspace(math.log10(fit.xmin), math.log10(fit.xmax), 50)
            small_share = fit.n / n_all
            norm = math.exp(-_log_norm(fit.exponent, fit.xmin, fit.xmax))
            ax.loglog(xs, small_share * norm * xs ** -fit.exponent, "k--",
                      label=f"power law {fit.exponent:.2f}$\\pm${fit.stderr:.2f}")
        lf = stats_["_lognormal_fits"][name]
        if np.isfinite(lf.mu):
            xs = np.logspace(lf.mu / math.log(10) - 3 * lf.sigma / math.log(10),
                             lf.mu / math.log(10) + 3 * lf.sigma / math.log(10), 80)
            ax.loglog(xs, stats.lognorm.pdf(xs, lf.sigma, 0, math.exp(lf.mu)) * large.sum() / n_all,
                      "-", color="gold", label=f"log-normal ($\\sigma$={lf.sigma:.2f})")
        if name == "u":
            ax.axvline(1.0, color="k", lw=1)
        ax.set_xlabel(labels[name])
        ax.set_ylabel("p")
        _legend(ax)
    return _save(fig, out_dir, "pdfs", pdf)


def plot_pdf_comparison(sets: dict, info: RunInfo, out_dir: Path, name: str, pdf: bool = False) -> list[str]:
    """PDFs of several catalogs (stationarity, Fig. S8; thresholds, Fig. S9)."""
    plt = _plt()
    labels = observable_labels(info)
    fig, axes = plt.subplots(1, len(labels), figsize=(14 * len(labels) / 3, 4.2))
    for label, catalog in sets.items():
        obs = normalised_observables(catalog, info)
        for ax, key in zip(axes, labels):
            _pdf_line(ax, obs[key], f"{label} (n={obs[key].size})")
    for ax, key in zip(axes, labels):
        ax.set_xlabel(labels[key])
        ax.set_ylabel("p")
        _legend(ax)
    return _save(fig, out_dir, name, pdf)


def plot_event_fields(path, catalog: dict, index: int, info: RunInfo, out_dir: Path, pdf: bool = False):
    """phi, tau/sigma0 and slip/D before and after event `index` (Fig. 2b-d):
    the last snapshot at or before t_start and the first at or after t_start + T."""
    plt = _plt()
    t0 = float(catalog["t_start"][index])
    t1 = t0 + float(catalog["T"][index])
    with open_h5(path) as f:
        ts = read_times(f, "snapshots/time")
        before = np.nonzero(ts <= t0)[0]
        after = np.nonzero(ts >= t1)[0]
        if before.size == 0 or after.size == 0:
            return [], None
        ib, ia = int(before[-1]), int(after[0])
        x = f["snapshots/x"][:]
        fields = {k: (f["snapshots"][k][ib], f["snapshots"][k][ia]) for k in ("slip", "state", "shear_stress")}
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    xs = x / info.L
    axes[0].plot(xs, (fields["slip"][1] - fields["slip"][0]) / info.D, "C0")
    axes[0].set_ylabel(r"$(\delta-\delta_{\rm before})/D$")
    for k, (ax, name, scale, lab) in enumerate(((axes[1], "state", 1.0, r"$\phi$ [s]"),
                                                 (axes[2], "shear_stress", info.sigma0, r"$\tau/\sigma_0$"))):
        ax.plot(xs, fields[name][0] / scale, "k", lw=1, label=f"before (t={ts[ib]:.4g} s)")
        ax.plot(xs, fields[name][1] / scale, "g", lw=1, label=f"after (t={ts[ia]:.4g} s)")
        ax.set_ylabel(lab)
        _legend(ax)
    axes[1].set_yscale("log")
    axes[2].set_xlabel("$x/L$")
    axes[0].set_title(f"event {index}: t_start={t0:.4g} s, T={t1 - t0:.3g} s, "
                      f"u_mean/D={catalog['u_mean'][index] / info.D:.3g}, L_s/L={catalog['L_s'][index] / info.L:.3g}",
                      fontsize=8)
    return _save(fig, out_dir, f"event_{index}_fields", pdf), (float(ts[ib]), float(ts[ia]))


def plot_hypocentres(catalog: dict, info: RunInfo, out_dir: Path, pdf: bool = False) -> list[str]:
    """A 2D interface: each event's hypocentre (x_start, z_start) over the
    interface, coloured by its start time, the marker's area proportional to
    the event's area A."""
    from .. import plots
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6, 6 * info.W / info.L + 1.0))
    area = np.asarray(catalog["A"], float)
    sizes = 4.0 + 400.0 * area / (info.L * info.W)
    sc = ax.scatter(catalog["x_start"], catalog["z_start"], s=sizes, c=np.asarray(catalog["t_start"], float),
                    cmap="viridis", edgecolors="k", linewidths=0.3)
    fig.colorbar(sc, ax=ax, label="t_start [s]")
    plots.interface_2d_frame(ax, info.L, info.W, f"{len(area)} events: hypocentres (marker area ~ event area)")
    return _save(fig, out_dir, "hypocentres", pdf)


def plot_space_time_2d(path, info: RunInfo, out_dir: Path, pdf: bool = False) -> list[str]:
    """A 2D interface in space and time (plots.interface_2d_spacetime_axes, the
    figure of `plot --kind spacetime`): |v| along x on the row of the largest
    slip rate, the largest |v| across z at each x and along x at each z."""
    from .. import plots
    plt = _plt()
    fig, axes = plt.subplots(1, 3, figsize=(13, 6), constrained_layout=True)
    drawn = plots.interface_2d_spacetime_axes(path, axes)
    fig.colorbar(drawn["meshes"][0], ax=axes.tolist(), label=r"log$_{10}$(|v| / $v_0$)")
    return _save(fig, out_dir, "space_time", pdf)


def plot_event_maps(path, catalog: dict, index: int, info: RunInfo, out_dir: Path, pdf: bool = False):
    """A 2D interface: slip-rate maps with the rupture front (plots.interface_2d_map_axes)
    at the snapshots nearest to the start, the middle and the end of event
    `index`; returns (paths, snapshot times)."""
    from .. import plots
    plt = _plt()
    t0 = float(catalog["t_start"][index])
    t1 = t0 + float(catalog["T"][index])
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.4), constrained_layout=True)
    maps = plots.interface_2d_map_axes(path, axes, [t0, 0.5 * (t0 + t1), t1])
    fig.colorbar(maps[0]["mesh"], ax=axes.tolist(), label=r"log$_{10}$(|v| / $v_0$)")
    fig.suptitle(f"event {index}: t_start={t0:.4g} s, T={t1 - t0:.3g} s, u_mean/D="
                 f"{catalog['u_mean'][index] / info.D:.3g}, A/(L W)={catalog['A'][index] / (info.L * info.W):.3g}",
                 fontsize=8)
    return _save(fig, out_dir, f"event_{index}_maps", pdf), [m["time"] for m in maps]
