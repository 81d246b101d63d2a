"""[output] stations, /rupture_front and `slipstrip export --seas`
(docs/output.md): a tiny run records stations on nodes and between nodes at every
step; node stations equal the snapshot values exactly, a mid-cell station is
the mean of its two nodes, the global series are consistent with the fields,
and the exported text files have the SEAS layout (# header, field-name line,
%.15e columns, log10 slip rate and state, stresses in MPa) and round-trip the
HDF5 values."""
import subprocess

import h5py
import numpy as np
import pytest

N, L = 64, 0.8
DX = L / N


@pytest.fixture(scope="module")
def station_run(cli, repo, tmp_path_factory):
    out = tmp_path_factory.mktemp("stations") / "run.h5"
    stations = [0.0, 10 * DX, 20.5 * DX, L - DX]
    cmd = [str(cli), "run", str(repo / "configs/reference.toml"), "--quiet", "--out", str(out),
           "--set", f"geometry.nodes={N}", "--set", f"geometry.length={L}",
           "--set", "time.duration_transits=2", "--set", "initial.noise_amplitude=1e-2",
           "--set", "output.snapshot_interval=1e-12",   # a snapshot every step
           "--set", "output.timeseries_interval=0",
           "--set", f"output.stations=[{', '.join(repr(x) for x in stations)}]",
           "--set", "output.front_slip_rate=2.002e-3"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return out, stations


def test_station_datasets_match_the_fields(station_run):
    path, stations = station_run
    with h5py.File(path, "r") as f:
        g = f["stations"]
        assert np.allclose(g["x"][:], stations, rtol=0, atol=1e-15)
        t = g["time"][:]
        snap_t = f["snapshots/time"][:]
        assert t.size == snap_t.size and np.array_equal(t, snap_t)
        for name, unit in [("slip", "m"), ("slip_rate", "m/s"), ("shear_stress", "Pa"), ("state", "s"),
                           ("normal_stress", "Pa")]:
            assert g[name].shape == (t.size, len(stations))
            assert g[name].attrs["units"] == unit
        for name in ("slip", "slip_rate", "shear_stress", "state"):
            field = f["snapshots"][name][:]
            st = g[name][:]
            for s, node in [(0, 0), (1, 10), (3, N - 1)]:
                assert np.array_equal(st[:, s], field[:, node]), name   # on a node: exact
            assert np.allclose(st[:, 2], 0.5 * (field[:, 20] + field[:, 21]), rtol=1e-14, atol=0)
        assert np.all(g["normal_stress"][:] == 1e6)
        v = f["snapshots/slip_rate"][:]
        assert np.array_equal(g["max_slip_rate"][:], v.max(axis=1))
        config_mu = 9e9 / (2 * 1.33)
        assert np.allclose(g["moment_rate"][:], config_mu * DX * v.sum(axis=1), rtol=1e-12)


def test_rupture_front_arrival_times(station_run):
    path, _ = station_run
    with h5py.File(path, "r") as f:
        arrival = f["rupture_front/arrival_time"][:]
        threshold = f["rupture_front"].attrs["slip_rate_threshold"]
        t = f["snapshots/time"][:]
        v = f["snapshots/slip_rate"][:]
    assert threshold == pytest.approx(2.002e-3)
    for node in range(N):
        above = np.nonzero(np.abs(v[:, node]) > threshold)[0]
        if above.size:
            assert arrival[node] == t[above[0]]
        else:
            assert np.isnan(arrival[node])
    assert np.isfinite(arrival).any()


def test_seas_export_layout_and_round_trip(cli, station_run, tmp_path):
    path, stations = station_run
    out = tmp_path / "seas"
    r = subprocess.run([str(cli), "export", str(path), "--seas", str(out)], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    files = sorted(out.glob("station_x*.txt"))
    assert len(files) == len(stations)
    with h5py.File(path, "r") as f:
        g = f["stations"]
        data = {k: g[k][:] for k in ("time", "slip", "slip_rate", "shear_stress", "state", "normal_stress",
                                     "max_slip_rate", "moment_rate")}
    for s, x in enumerate(stations):
        name = out / f"station_x{x:+.4f}.txt"
        lines = name.read_text().splitlines()
        header = [l for l in lines if l.startswith("#")]
        assert any(l.startswith("# code: slipstrip") for l in header)
        assert any(l.startswith("# element_size: ") for l in header)
        assert any(l.startswith("# location: x = ") for l in header)
        assert any("slip_rate [log10 m/s]" in l and "shear_stress [MPa]" in l for l in header)
        body = lines[len(header):]
        assert body[0].split() == ["t", "slip", "slip_rate", "shear_stress", "state", "normal_stress"]
        assert all(len(row.split()) == 6 for row in body[1:])
        assert all("e" in token and len(token.split("e")[0].lstrip("-")) == 17 for token in body[1].split())
        table = np.loadtxt(body[1:])
        # %.15e keeps 16 significant digits: equal to within half a unit of the 16th
        assert np.allclose(table[:, 0], data["time"], rtol=1e-15, atol=0)
        assert np.allclose(table[:, 1], data["slip"][:, s], rtol=1e-14, atol=0)
        assert np.allclose(10 ** table[:, 2], np.abs(data["slip_rate"][:, s]), rtol=1e-13)
        assert np.allclose(table[:, 3] * 1e6, data["shear_stress"][:, s], rtol=1e-14)
        assert np.allclose(10 ** table[:, 4], data["state"][:, s], rtol=1e-13)
        assert np.allclose(table[:, 5], 1.0)
    glob = np.loadtxt([l for l in (out / "global.txt").read_text().splitlines() if not l.startswith("#")][1:])
    assert np.allclose(10 ** glob[:, 1], data["max_slip_rate"], rtol=1e-13)
    assert np.allclose(glob[:, 2], data["moment_rate"], rtol=1e-14)
    rupture = (out / "rupture.txt").read_text().splitlines()
    assert rupture[[i for i, l in enumerate(rupture) if not l.startswith("#")][0]].split() == ["x", "t"]


def test_seas_files_read_back(cli, station_run, tmp_path):
    """slipstrip.read_seas and the NumPy one-liner of export.py's docstring
    (and docs/output.md) give back what export wrote."""
    from slipstrip import read_seas
    path, stations = station_run
    out = tmp_path / "seas"
    r = subprocess.run([str(cli), "export", str(path), "--seas", str(out)], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    with h5py.File(path, "r") as f:
        t, slip = f["stations/time"][:], f["stations/slip"][:]
    name = out / f"station_x{stations[1]:+.4f}.txt"
    seas = read_seas(name)
    assert seas.columns == ("t", "slip", "slip_rate", "shear_stress", "state", "normal_stress")
    assert seas.header["location"].startswith("x = ")
    assert seas.header["code"].startswith("slipstrip")
    assert seas.data.shape == (t.size, 6)
    # %.15e keeps 16 significant digits: equal to within half a unit of the 16th
    assert np.allclose(seas["t"], t, rtol=1e-15, atol=0)
    assert np.allclose(seas["slip"], slip[:, 1], rtol=1e-14, atol=0)
    table = np.genfromtxt((l for l in open(name) if not l.startswith("#")), names=True)
    assert table.dtype.names == seas.columns
    assert np.array_equal(table["slip_rate"], seas["slip_rate"])
    g = read_seas(out / "global.txt")
    assert g.columns == ("t", "max_slip_rate", "moment_rate") and g.data.shape[0] == t.size
    with pytest.raises(KeyError, match="no column 'v'"):
        seas["v"]


def test_station_rows_fall_on_the_first_step_after_each_interval(cli, repo, tmp_path):
    """docs/output.md, /stations: with station_interval > 0 the rows are at
    t = 0 and at the first time step reaching each multiple k * interval;
    they are not interpolated, so their spacing varies by up to one dt."""
    out = tmp_path / "r.h5"
    r = subprocess.run([str(cli), "run", str(repo / "configs/quickstart.toml"), "--quiet", "--out", str(out),
                        "--set", "geometry.nodes=32", "--set", "time.duration_transits=2",
                        "--set", "output.timeseries_interval=0", "--set", "output.stations=[0.1]",
                        "--set", "output.station_interval=4.7e-6"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    with h5py.File(out, "r") as f:
        steps = f["timeseries/time"][:]  # every step's time (timeseries_interval = 0)
        rows = f["stations/time"][:]
    interval = 4.7e-6
    dt = steps[1] - steps[0]
    assert not np.isclose(interval / dt, round(interval / dt))  # not a multiple of dt: the interesting case
    expected = [0.0]
    k = 1
    for t in steps[1:]:
        if t >= k * interval * (1 - 1e-12):  # the solver's test (core/run.cpp), relative 1e-12 for round-off
            expected.append(t)
            k += 1
    assert np.array_equal(rows, expected)
    gaps = np.diff(rows)
    assert np.all(gaps > interval - dt) and np.all(gaps < interval + dt)
    assert gaps.min() < interval < gaps.max()  # the spacing really varies


def test_stations_outside_the_interface_are_a_config_error(cli, repo, tmp_path):
    r = subprocess.run([str(cli), "run", str(repo / "configs/reference.toml"), "--out", str(tmp_path / "x.h5"),
                        "--set", "output.stations=[0.5, 4.5]"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert "output.stations" in r.stderr and "4.5" in r.stderr


def test_export_without_stations_fails_cleanly(cli, repo, tmp_path):
    out = tmp_path / "plain.h5"
    r = subprocess.run([str(cli), "run", str(repo / "configs/quickstart.toml"), "--quiet", "--out", str(out),
                        "--set", "geometry.nodes=32", "--set", "time.duration_transits=0.2"],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    r = subprocess.run([str(cli), "export", str(out), "--seas", str(tmp_path / "s")], capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 2 and "no /stations" in r.stderr
