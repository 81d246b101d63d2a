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
from figure_checks import assert_figure

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
    colours = np.unique(image.reshape(-1, image.shape[-1]), axis=0)
    assert len(colours) > 100
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
