"""A 2D interface (geometry.nodes_z > 1, docs/3d.md) from Python and through
`slipstrip events`: slipstrip.run writes it, slipstrip.open_run reads its
snapshots as (time, z, x) arrays, its grid, time series and rupture front;
`slipstrip events RUN.h5` writes a catalog of (x, z) events, and with
`--min-slip-rate K` records K and the ignored nodal slips in it (0: the
same catalog bit for bit; a bad K refused in one line); the slip-rate
maps with rupture-front contours are checked for what they draw (arrays,
axis ranges, contours) and for the pixels of the PNG.

Run: SLIPSTRIP_BUILD_DIR=$PWD/build PYTHONPATH=$PWD/python OMP_NUM_THREADS=1 \\
     /usr/bin/python3 -m pytest -q tests/python/test_interface_2d_python.py
"""
import subprocess
import sys

import h5py
import matplotlib.image
import numpy as np
import pytest

from conftest import REPO

TINY_3D = REPO / "configs" / "3d" / "tiny.toml"
NX, NZ = 32, 16


@pytest.fixture(scope="module")
def run_2d(tmp_path_factory, slipstrip_module):
    out = tmp_path_factory.mktemp("interface_2d_python") / "tiny.h5"
    # 32 x 16 nodes over 0.25 m x 0.125 m, 6 transits (~ 750 steps): a few seconds.
    slipstrip_module.run(TINY_3D, out, overrides={
        "geometry.nodes_z": NZ, "geometry.width": 0.125, "time.duration_transits": 6.0,
        "output.snapshot_interval": 2e-6, "output.front_slip_rate": 4e-3, "output.delta_th": 1e-8})
    return out


def test_open_run_reads_a_2d_interface(run_2d, slipstrip_module):
    run = slipstrip_module.open_run(run_2d)
    assert run.interface_2d and run.nodes == NX and run.nodes_z == NZ
    assert run.length == 0.25 and run.width == 0.125
    snaps = run.snapshots
    with h5py.File(run_2d, "r") as f:
        n = len(f["snapshots/time"])
        assert n >= 10
        for name in ("slip_x", "slip_z", "slip_rate_x", "slip_rate_z", "state", "shear_stress_x", "shear_stress_z"):
            assert snaps[name].shape == (n, NZ, NX)  # (time, z, x)
        assert np.array_equal(snaps["slip_rate_z"][3], f["snapshots/slip_rate_z"][3])
        assert np.array_equal(snaps.x, f["grid/x"][:]) and np.array_equal(snaps.z, f["grid/z"][:])
    assert snaps.x.shape == (NX,) and snaps.z.shape == (NZ,)
    assert snaps.x[1] == pytest.approx(0.25 / NX, rel=1e-15) and snaps.z[1] == pytest.approx(0.125 / NZ, rel=1e-15)
    series = run.timeseries
    assert set(series) == {"time", "max_slip_rate", "mean_slip", "mean_shear_stress"}
    # Every snapshot time is a time-series row; the mean slip there is the map's mean.
    k = np.searchsorted(series["time"], snaps.time[-1])
    assert series["mean_slip"][k] == pytest.approx(snaps["slip_x"][-1].mean(), rel=1e-14)
    front = run.rupture_front
    assert front.shape == (NZ, NX)
    reached = np.isfinite(front)
    assert reached.any() and np.all(front[reached] >= 0) and np.all(front[reached] <= series["time"][-1])


def test_events_of_a_2d_interface_run(run_2d, cli, slipstrip_module):
    r = subprocess.run([str(cli), "events", str(run_2d)], capture_output=True, text=True, timeout=120)
    assert r.returncode in (0, 1), r.stderr
    with h5py.File(run_2d, "r") as f:
        events = f["events"]
        assert events.attrs["nodes_z"] == NZ
        assert events["M0"].attrs["units"] == "N m" and events["A"].attrs["units"] == "m^2"
        n = int(events.attrs["n_events"])
        cell = (0.25 / NX) * (0.125 / NZ)
        if n:
            # Areas are whole numbers of cells; M0 = mu A u_mean with the bodies' shear modulus.
            assert np.allclose(events["A"][:] / cell, np.round(events["A"][:] / cell), rtol=0, atol=1e-9)
            assert np.allclose(events["M0"][:], 9e9 * events["A"][:] * events["u_mean"][:], rtol=1e-14)
            assert np.all((events["z_start"][:] >= 0) & (events["z_start"][:] < 0.125))
    catalog = slipstrip_module.open_run(run_2d).events
    assert catalog["nodes_z"] == NZ and len(catalog["area"]) == n
    print(f"{n} events kept: {r.stdout.strip()}")


def test_events_min_slip_rate_is_recorded_and_zero_changes_nothing(run_2d, cli, slipstrip_module, tmp_path):
    from slipstrip.analysis import catalog_for
    paths = {k: tmp_path / f"events_{k}.h5" for k in ("default", "zero", "filtered")}
    for key, extra in (("default", []), ("zero", ["--min-slip-rate", "0"]), ("filtered", ["--min-slip-rate", "1.5"])):
        r = subprocess.run([str(cli), "events", str(run_2d), "--out", str(paths[key]), *extra],
                           capture_output=True, text=True, timeout=120)
        assert r.returncode in (0, 1), r.stderr
    with h5py.File(paths["default"], "r") as a, h5py.File(paths["zero"], "r") as b, h5py.File(paths["filtered"], "r") as c:
        ga, gb, gc = a["events"], b["events"], c["events"]
        # --min-slip-rate 0 is the default: every dataset and attribute the same bits.
        assert set(ga) == set(gb) and all(np.array_equal(ga[k][:], gb[k][:], equal_nan=True) for k in ga)
        assert set(ga.attrs) == set(gb.attrs)
        assert all(np.array_equal(ga.attrs[k], gb.attrs[k]) for k in ga.attrs)
        assert ga.attrs["min_slip_rate_v0"] == 0.0 and ga.attrs["min_slip_rate"] == 0.0
        assert ga.attrs["n_nodal_slips_below_min_slip_rate"] == 0
        # The filter's value and what it removed are in the catalog (this run
        # slides at about v0: 1.5 v0 drops some of its nodal slips, not all).
        v0 = float(gc.attrs["v0"])
        assert gc.attrs["min_slip_rate_v0"] == 1.5 and gc.attrs["min_slip_rate"] == 1.5 * v0
        assert gc.attrs["n_nodal_slips"] == ga.attrs["n_nodal_slips"]
        assert 0 < gc.attrs["n_nodal_slips_below_min_slip_rate"] < gc.attrs["n_nodal_slips"]
        n_ignored = int(gc.attrs["n_nodal_slips_below_min_slip_rate"])
    # The Python API: the same counts as the CLI, and analyze's catalog_for
    # does not take an unfiltered catalog for a filtered one.
    api = slipstrip_module.open_run(run_2d).detect_events(min_slip_rate_v0=1.5)
    assert api["options"]["min_slip_rate_v0"] == 1.5 and api["n_nodal_slips_below_min_slip_rate"] == n_ignored
    filtered = catalog_for(run_2d, 15.0, workdir=tmp_path, min_slip_rate_v0=1.5)
    assert filtered["attrs"]["min_slip_rate_v0"] == 1.5
    assert filtered["attrs"]["n_nodal_slips_below_min_slip_rate"] == n_ignored
    assert (tmp_path / "events_alpha15_rate1.5.h5").is_file()
    # A bad value: one line naming the option, the value and what is allowed.
    for bad in ("-1", "nan", "inf"):
        r = subprocess.run([str(cli), "events", str(run_2d), "--out", str(tmp_path / "bad.h5"), "--min-slip-rate", bad],
                           capture_output=True, text=True, timeout=60)
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
        assert f"--min-slip-rate {bad} is invalid: must be a finite number >= 0" in r.stderr
        r = subprocess.run([sys.executable, "-m", "slipstrip", "analyze", str(run_2d), "--out-dir",
                            str(tmp_path / "analysis"), "--min-slip-rate", bad], capture_output=True, text=True,
                           timeout=120)
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
        assert "--min-slip-rate" in r.stderr and "is invalid: must be a finite number >= 0" in r.stderr


def test_slip_rate_maps_with_rupture_front_contours(run_2d, slipstrip_module, tmp_path):
    from slipstrip import plots
    import matplotlib.pyplot as plt

    run = slipstrip_module.open_run(run_2d)
    series = run.timeseries
    # The snapshot nearest to the largest slip rate: the front crosses it.
    t_peak = series["time"][np.argmax(series["max_slip_rate"])]
    times = [0.0, t_peak]
    fig, axes = plt.subplots(1, 2)
    maps = plots.interface_2d_map_axes(run, axes, times)
    assert [m["index"] for m in maps][0] == 0
    for ax, m in zip(axes, maps):
        assert ax.get_xlim() == (0.0, 0.25) and ax.get_ylim() == (0.0, 0.125)
        assert m["speed"].shape == (NZ, NX)
        expected = np.hypot(run.snapshots["slip_rate_x"][m["index"]], run.snapshots["slip_rate_z"][m["index"]])
        assert np.array_equal(m["speed"], expected)
        assert m["mesh"].get_array().size == NZ * NX
    assert maps[1]["front_slip_rate"] == 4e-3  # the run's output.front_slip_rate
    assert maps[1]["speed"].max() > 4e-3 > maps[1]["speed"].min()
    # The front contour lies inside the interface and separates faster from slower nodes.
    segments = [seg for seg in maps[1]["front"].allsegs[0] if len(seg)]
    assert segments
    points = np.concatenate(segments)
    assert np.all((points[:, 0] >= 0) & (points[:, 0] <= 0.25) & (points[:, 1] >= 0) & (points[:, 1] <= 0.125))
    assert maps[0]["front"] is None  # t = 0: steady sliding, no node above the threshold
    plt.close(fig)

    png = tmp_path / "maps.png"
    assert plots.interface_2d_maps(run, png, times=times) == str(png)
    image = matplotlib.image.imread(png)
    height, width = image.shape[:2]
    assert width > 2 * height  # two square-ish panels side by side and a colour bar
    rgb = image[..., :3].reshape(-1, 3)
    colours = np.unique((rgb * 255).round().astype(int), axis=0)
    assert len(colours) > 50  # colour maps, not a blank canvas
    white = np.all(rgb > 0.98, axis=1).mean()
    assert 0.1 < white < 0.9
    # Cyan front pixels are drawn (the contour colour).
    cyan = np.all(np.abs(rgb - np.array([0.0, 1.0, 1.0])) < 0.1, axis=1).sum()
    assert cyan > 20


def test_space_time_view_of_a_2d_interface(run_2d, slipstrip_module, tmp_path):
    """The three space-time fields against a direct reading of the run file:
    the row of nodes (chosen by z, or by default the one with the largest
    speed), the largest speed across z at each x and along x at each z; the
    subsampling of long runs; the PNG's pixels; a z outside the width refused."""
    from slipstrip import plots
    import matplotlib.pyplot as plt

    run = slipstrip_module.open_run(run_2d)
    with h5py.File(run_2d, "r") as f:
        speed = np.hypot(f["snapshots/slip_rate_x"][:], f["snapshots/slip_rate_z"][:])  # (n, N_z, N)
        t = f["snapshots/time"][:]
        z = f["grid/z"][:]
    n = len(t)
    fig, axes = plt.subplots(1, 3)
    drawn = plots.interface_2d_spacetime_axes(run, axes)
    assert np.array_equal(drawn["indices"], np.arange(n)) and np.array_equal(drawn["time"], t)
    peak_row = np.unravel_index(np.argmax(speed), speed.shape)[1]
    assert drawn["row_index"] == peak_row and drawn["row_z"] == z[peak_row]
    assert np.array_equal(drawn["row"], speed[:, peak_row, :])
    assert np.array_equal(drawn["max_over_z"], speed.max(axis=1))
    assert np.array_equal(drawn["max_over_x"], speed.max(axis=2))
    # The fronts vary across z in this run (white noise node by node), so the
    # largest speed across z is above one row's somewhere.
    assert np.any(drawn["max_over_z"] > drawn["row"])
    assert axes[0].get_xlim() == (0.0, 0.25) and axes[2].get_xlim() == (0.0, 0.125)
    plt.close(fig)

    fig, axes = plt.subplots(1, 3)
    chosen = plots.interface_2d_spacetime_axes(run, axes, z=0.06, max_cells=7)
    step = -(-n // 7)
    assert np.array_equal(chosen["indices"], np.arange(0, n, step))
    row = int(np.argmin(np.abs(z - 0.06)))
    assert chosen["row_index"] == row
    assert np.array_equal(chosen["row"], speed[::step, row, :])
    assert np.array_equal(chosen["max_over_x"], speed[::step].max(axis=2))
    with pytest.raises(ValueError, match="outside the interface's width"):
        plots.interface_2d_spacetime_axes(run, axes, z=0.2)
    plt.close(fig)

    png = tmp_path / "spacetime_2d.png"
    assert plots.interface_2d_spacetime(run, png) == str(png)
    image = matplotlib.image.imread(png)
    height, width = image.shape[:2]
    assert width > 1.5 * height  # three panels side by side and a colour bar
    rgb = image[..., :3].reshape(-1, 3)
    assert len(np.unique((rgb * 255).round().astype(int), axis=0)) > 50


def test_maps_of_a_line_are_refused(slipstrip_module, tmp_path):
    from slipstrip import plots

    out = tmp_path / "line.h5"
    slipstrip_module.run(REPO / "configs" / "quickstart.toml", out,
                         overrides={"geometry.nodes": 32, "time.duration_transits": 0.2})
    with pytest.raises(ValueError, match="not a 2D interface"):
        plots.interface_2d_maps(out, tmp_path / "x.png")
