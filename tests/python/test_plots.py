"""Tests of python/slipstrip/plots.py, runfile.py and `python3 -m slipstrip plot`.

A tiny run (quickstart, 64 nodes, 4 L/c_s, ~1000 steps, well under a second)
is written once; the figures are checked against the data read with plain h5py.

Run: /usr/bin/python3 -m pytest tests/python/test_plots.py
"""
import math
import os
import subprocess
import sys
import tomllib

import h5py
import numpy as np
import pytest

from conftest import PYTHON_DIR, REPO
from figure_checks import assert_figure, distinct_colours

QUICKSTART = REPO / "configs" / "quickstart.toml"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def ss(slipstrip_module):
    return slipstrip_module


@pytest.fixture(scope="module")
def tiny_run(ss, tmp_path_factory):
    path = tmp_path_factory.mktemp("run") / "tiny.h5"
    result = ss.run(QUICKSTART, path, overrides={"geometry.nodes": 64, "time.duration_transits": 4.0,
                                                 "output.snapshot_interval": 1e-5})
    assert result.status == "completed"
    return path


def test_open_run_matches_h5py(ss, tiny_run):
    run = ss.open_run(tiny_run)
    with h5py.File(tiny_run, "r") as f:
        assert run.status == f.attrs["status"] == "completed"
        assert run.config == tomllib.loads(f.attrs["config"])
        assert run.git_hash == f.attrs["git_hash"]
        for k in ("time", "max_slip_rate", "mean_slip", "mean_shear_stress"):
            np.testing.assert_array_equal(run.timeseries[k], f["timeseries"][k][:])
        np.testing.assert_array_equal(run.snapshots.time, f["snapshots/time"][:])
        np.testing.assert_array_equal(run.snapshots["slip_rate"][-1], f["snapshots/slip_rate"][-1])
        assert run.snapshots["slip"].shape == f["snapshots/slip"].shape
        assert run.snapshots.trigger == f["snapshots"].attrs["trigger"]
        assert run.slip_sampling.attrs["delta_th"] == f["slip_sampling"].attrs["delta_th"]
        assert run.slip_sampling.crossing_time.shape == f["slip_sampling/crossing_time"].shape
    assert run.units["timeseries/time"] == "s"
    assert run.units["snapshots/slip_rate"] == "m/s"
    assert run.snapshots["shear_stress"].units == "Pa"
    assert run.events is None
    # L / c_s from the config: c_s = sqrt(mu / rho).
    m = run.config["material"]
    assert run.length_transit_time == pytest.approx(run.length / math.sqrt(m["shear_modulus"] / m["density"]), rel=1e-15)


def test_open_run_does_not_hold_the_file(ss, tiny_run):
    # The writer defers flushes while a reader holds the file; RunFile must not.
    # An exclusive (write) open fails while any other handle holds a lock.
    run = ss.open_run(tiny_run)
    _ = run.snapshots["slip"][0]
    with h5py.File(tiny_run, "r+"):
        pass


def test_spacetime_png_shows_the_snapshot_data(ss, tiny_run, tmp_path):
    import matplotlib.pyplot as plt
    from slipstrip import plots

    with h5py.File(tiny_run, "r") as f:
        v = f["snapshots/slip_rate"][:]
        t = f["snapshots/time"][:]
        x = f["snapshots/x"][:]
        cfg = tomllib.loads(f.attrs["config"])
    v0 = cfg["loading"]["driving_velocity"]
    L = cfg["geometry"]["length"]
    cs = math.sqrt(cfg["material"]["shear_modulus"] / cfg["material"]["density"])

    # What is drawn is log10(v / v0) on x/L and t c_s/L (small run: no subsampling).
    fig, ax = plt.subplots()
    mesh = plots.spacetime_axes(tiny_run, ax)
    np.testing.assert_allclose(np.asarray(mesh.get_array()).reshape(v.shape), np.log10(v / v0), rtol=1e-12)
    # Cell corners: with shading="nearest" the interior cell edges lie halfway
    # between neighbouring samples (snapshot times are not exactly uniform).
    coords = mesh.get_coordinates()
    xs, ts = x / L, t * cs / L
    np.testing.assert_allclose(coords[0, 1:-1, 0], 0.5 * (xs[1:] + xs[:-1]), rtol=1e-12)
    np.testing.assert_allclose(coords[1:-1, 0, 1], 0.5 * (ts[1:] + ts[:-1]), rtol=1e-12)
    assert ax.get_xlabel() == "x / L"
    plt.close(fig)

    out = tmp_path / "spacetime.png"
    assert plots.spacetime(tiny_run, out) == str(out)
    data = out.read_bytes()
    assert data[:8] == PNG_SIGNATURE
    image = plt.imread(out)
    # A non-trivial picture: many distinct colours (the colormap, labels,
    # colorbar) and not a blank canvas.
    assert distinct_colours(image) > 100
    assert image[..., :3].std() > 0.05


def test_spacetime_without_snapshots_names_the_key(ss, tmp_path):
    path = tmp_path / "nosnap.h5"
    ss.run(QUICKSTART, path, overrides={"geometry.nodes": 32, "time.duration_transits": 0.5,
                                        "output.snapshot_interval": 0.0})
    from slipstrip import plots
    with pytest.raises(ValueError, match="snapshot_interval"):
        plots.spacetime(path, tmp_path / "x.png")


def test_timeseries_png(ss, tiny_run, tmp_path):
    from slipstrip import plots
    out = plots.timeseries(tiny_run, tmp_path / "ts.png")
    assert_figure(out)


def test_module_cli_plot(tiny_run, tmp_path):
    env = dict(os.environ, PYTHONPATH=str(PYTHON_DIR))
    out = tmp_path / "cli.png"
    p = subprocess.run([sys.executable, "-m", "slipstrip", "plot", str(tiny_run), "--out", str(out)],
                       capture_output=True, text=True, env=env, timeout=120)
    assert p.returncode == 0, p.stderr
    assert_figure(out)

    p = subprocess.run([sys.executable, "-m", "slipstrip", "frobnicate"], capture_output=True, text=True,
                       env=env, timeout=60)
    assert p.returncode == 2 and "unknown command 'frobnicate'" in p.stderr


def test_draw_log_rate_draws_the_data_range(tmp_path):
    """The one plotter of log10(v/v0) maps: a field of two levels, a stuck node
    and a block without data, saved without axes so that every pixel is a cell.
    The picture has the size asked for, is not blank, shows the low level in
    the colour map's first colour and the high level in its last (the data
    range is the colour range), the stuck node at the bottom of the scale and
    the missing data as background."""
    import matplotlib.pyplot as plt
    from matplotlib import colormaps
    from slipstrip import plots

    v0 = 1e-3
    rows, cols = 40, 64
    v = np.full((rows, cols), 1e-2 * v0)
    v[:, cols // 2:] = 10.0 * v0            # log10(v/v0) = -2 on the left, 1 on the right
    v[:, 5] = 0.0                           # a stuck node
    v[30:, 40:50] = np.nan                  # no data
    x, y = (np.arange(cols) + 0.5) / cols, np.arange(rows) + 0.5
    fig = plt.figure(figsize=(3.2, 2.0), dpi=100)
    ax = fig.add_axes([0, 0, 1, 1])
    ax.set_axis_off()
    mesh = plots.draw_log_rate(ax, x, y, v, v0)
    assert mesh.get_cmap().name == plots.SPACETIME_CMAP
    assert mesh.get_clim() == pytest.approx((-2.0, 1.0), rel=1e-12)
    drawn = np.ma.asarray(mesh.get_array()).reshape(rows, cols)
    assert drawn[0, 5] == pytest.approx(-2.0, rel=1e-12)        # stuck: bottom of the scale
    assert drawn.mask[35, 45] and not drawn.mask[35, 35]
    ax.set_xlim(0, 1)
    ax.set_ylim(0, rows)
    out = tmp_path / "levels.png"
    fig.savefig(out)
    plt.close(fig)
    image = assert_figure(out, min_drawn=0.5)
    assert image.shape[:2] == (200, 320)
    cmap = colormaps[plots.SPACETIME_CMAP]
    low, high = np.asarray(cmap(0.0)[:3]), np.asarray(cmap(1.0)[:3])
    # 8-bit PNG: a colour is read back within 1/255 per channel (2/255 allowed).
    tol = 2.0 / 255.0
    rgb = image[..., :3]
    # 5 px per column and per row; image row 0 is the top (y = 40).
    assert np.all(np.abs(rgb[20:180, 40:150] - low) <= tol)      # left half
    assert np.all(np.abs(rgb[100:180, 260:310] - high) <= tol)   # right half
    assert np.all(np.abs(rgb[5:45, 205:245] - 1.0) <= tol)       # the NaN block (rows 30-39, columns 40-49): background
    assert np.all(np.abs(rgb[100, 26:29] - low) <= tol)          # the stuck node (column 5: 25-30 px)


def test_draw_log_rate_keeps_a_one_node_pulse_when_reducing():
    """Above max_cells the field is reduced by block maxima, so a pulse one
    node wide and one row long still sets the top of the colour scale."""
    import matplotlib.pyplot as plt
    from slipstrip import plots

    v = np.ones((3000, 2048))
    v[1234, 777] = 1e3
    fig, ax = plt.subplots()
    mesh = plots.draw_log_rate(ax, np.arange(2048) / 2048, np.arange(3000), v, 1.0, max_cells=500)
    plt.close(fig)
    drawn = np.asarray(mesh.get_array())
    assert drawn.size <= 500 * 500
    assert mesh.get_clim() == pytest.approx((0.0, 3.0), abs=1e-12)
    assert np.count_nonzero(np.abs(drawn - 3.0) <= 1e-12) == 1


def test_every_log_rate_map_uses_the_one_plotter():
    """No module draws a colour map of its own: imshow/pcolormesh are called
    only by plots.draw_log_rate and by the event-coloured map of analyze
    (categorical colours of events, not a slip rate)."""
    import ast
    allowed = {("plots.py", "draw_log_rate"), ("analysis/figures.py", "plot_event_map")}
    found = set()
    package = PYTHON_DIR / "slipstrip"
    for path in package.rglob("*.py"):
        tree = ast.parse(path.read_text())
        for func in (n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)):
            for call in (n for n in ast.walk(func) if isinstance(n, ast.Call)):
                if isinstance(call.func, ast.Attribute) and call.func.attr in ("imshow", "pcolormesh"):
                    found.add((path.relative_to(package).as_posix(), func.name))
    assert found == allowed


def test_analysis_and_pulse_episodes_draw_with_the_one_plotter(ss, tiny_run, tmp_path, monkeypatch):
    from slipstrip import analysis, episodes, plots
    calls = []
    original = plots.draw_log_rate

    def spy(*args, **kwargs):
        calls.append(kwargs)
        return original(*args, **kwargs)

    monkeypatch.setattr(plots, "draw_log_rate", spy)
    info = analysis.read_run_info(tiny_run)
    assert_figure(analysis.plot_space_time(tiny_run, info, tmp_path)[0])
    ct, x = analysis.reading._read_crossing_time(tiny_run)
    assert_figure(analysis.plot_space_slip(ct, x, info, tmp_path)[0])
    summary = episodes.pulse_summary(str(tiny_run), window_transits=1.0)
    episodes.plot(str(tiny_run), summary, tmp_path / "episodes.png")
    assert_figure(tmp_path / "episodes.png")
    assert len(calls) == 3
