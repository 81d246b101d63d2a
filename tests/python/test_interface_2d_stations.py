"""Stations on a 2D interface (geometry.nodes_z > 1, docs/3d.md): points
(x, z) given by output.stations and output.stations_z.  A tiny run records a
snapshot and a station row at every step; a station on a node equals the
snapshot values at that node exactly, a station between nodes is the bilinear
interpolation of its four neighbours, the global series are consistent with
the fields, every dataset carries its units.  Restart bit for bit with
stations is tested in test_interface_2d_restart.py.

Run: SLIPSTRIP_BUILD_DIR=$PWD/build PYTHONPATH=$PWD/python OMP_NUM_THREADS=1 \\
     /usr/bin/python3 -m pytest -q tests/python/test_interface_2d_stations.py
"""
import subprocess

import h5py
import numpy as np
import pytest

from conftest import REPO

TINY_3D = REPO / "configs" / "3d" / "tiny.toml"
NX, NZ, L, W = 16, 8, 0.25, 0.25
DX, DZ = L / NX, W / NZ
FIELDS = [("slip_x", "m"), ("slip_z", "m"), ("slip_rate_x", "m/s"), ("slip_rate_z", "m/s"), ("state", "s"),
          ("shear_stress_x", "Pa"), ("shear_stress_z", "Pa")]
# (x, z): three nodes (one on the last column and row), one mid-cell in both
# directions, one between two nodes along z only.
STATIONS = [(0.0, 0.0), (5 * DX, 3 * DZ), ((NX - 1) * DX, (NZ - 1) * DZ), (2.5 * DX, 4.25 * DZ), (7 * DX, 0.5 * DZ)]


def _list(values):
    return "[" + ", ".join(repr(v) for v in values) + "]"


def _run(cli, out, *extra):
    cmd = [str(cli), "run", str(TINY_3D), "--quiet", "--out", str(out),
           "--set", f"geometry.nodes={NX}", "--set", f"geometry.nodes_z={NZ}",
           "--set", "time.duration_transits=1",
           "--set", "output.snapshot_interval=1e-12",  # a snapshot every step
           "--set", f"output.stations={_list([x for x, _ in STATIONS])}",
           "--set", f"output.stations_z={_list([z for _, z in STATIONS])}", *extra]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def station_run(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("stations_2d") / "run.h5"
    r = _run(cli, out)
    assert r.returncode == 0, r.stderr
    return out


def test_station_series_equal_the_snapshots_at_their_nodes(station_run):
    with h5py.File(station_run, "r") as f:
        g = f["stations"]
        assert np.array_equal(g["x"][:], [x for x, _ in STATIONS]) and g["x"].attrs["units"] == "m"
        assert np.array_equal(g["z"][:], [z for _, z in STATIONS]) and g["z"].attrs["units"] == "m"
        t = g["time"][:]
        assert g["time"].attrs["units"] == "s"
        assert t.size > 30 and np.array_equal(t, f["snapshots/time"][:])  # a row per step, at the snapshot times
        assert "slip" not in g and "normal_stress" not in g  # the line's fields are not there
        for name, unit in FIELDS:
            st = g[name][:]
            assert st.shape == (t.size, len(STATIONS)) and g[name].attrs["units"] == unit, name
            field = f["snapshots"][name][:]  # (time, z, x)
            # On a node: the snapshot value, bit for bit.
            for s, (ix, iz) in [(0, (0, 0)), (1, (5, 3)), (2, (NX - 1, NZ - 1))]:
                assert np.array_equal(st[:, s], field[:, iz, ix]), name
            # Between nodes: bilinear in x and z (weights 1/2, 1/4: a few
            # roundings of a sum of four products, so 1e-14 of the largest
            # neighbour).
            scale = np.abs(field).max(axis=(1, 2)) + np.finfo(float).tiny
            fz = 0.75 * (0.5 * field[:, 4, 2] + 0.5 * field[:, 4, 3]) + 0.25 * (0.5 * field[:, 5, 2] + 0.5 * field[:, 5, 3])
            assert np.all(np.abs(st[:, 3] - fz) <= 1e-14 * scale), name
            between = 0.5 * field[:, 0, 7] + 0.5 * field[:, 1, 7]
            assert np.all(np.abs(st[:, 4] - between) <= 1e-14 * scale), name
        # Not a trivial record: the fields move at the stations.
        assert np.ptp(g["slip_rate_x"][:, 1]) > 1e-3 * 2e-3 and np.abs(g["slip_rate_z"][:]).max() > 0


def test_global_station_series(station_run):
    with h5py.File(station_run, "r") as f:
        g = f["stations"]
        vx = f["snapshots/slip_rate_x"][:]
        vz = f["snapshots/slip_rate_z"][:]
        mu = 9e9
        assert g["max_slip_rate"].attrs["units"] == "m/s"
        # max |v|: the solver's speed, sqrt(vx^2 + vz^2) to rounding.
        speed = np.sqrt(vx ** 2 + vz ** 2).max(axis=(1, 2))
        assert np.allclose(g["max_slip_rate"][:], speed, rtol=1e-15, atol=0)
        assert g["moment_rate"].attrs["units"] == "N m/s (mu * sum(v_x) dx dz)"
        # A sum of 128 values in another order: 1e-13 relative.
        assert np.allclose(g["moment_rate"][:], mu * DX * DZ * vx.sum(axis=(1, 2)), rtol=1e-13, atol=0)


def test_station_config_errors_name_the_key(cli, tmp_path):
    out = tmp_path / "x.h5"
    r = _run(cli, out, "--set", "output.stations_z=[0.1]")
    assert r.returncode == 2 and "output.stations_z has 1 positions and output.stations 5" in r.stderr, r.stderr
    r = _run(cli, out, "--set", "output.stations_z=[0.1, 0.1, 0.1, 0.1, 0.25]")
    assert r.returncode == 2 and "stations_z" in r.stderr and "0.25" in r.stderr, r.stderr
    # A line (nodes_z = 1) takes no z positions.
    r = subprocess.run([str(cli), "run", str(REPO / "configs/quickstart.toml"), "--out", str(out), "--quiet",
                        "--set", "output.stations=[0.1]", "--set", "output.stations_z=[0.1]"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "output.stations_z has 1 positions on a one-dimensional interface" in r.stderr, r.stderr
    assert not out.exists()


def test_seas_export_refuses_stations_of_a_2d_interface(cli, station_run, tmp_path):
    r = subprocess.run([str(cli), "export", str(station_run), "--seas", str(tmp_path / "seas")],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "stations of a 2D interface" in r.stderr, r.stderr
    assert not (tmp_path / "seas").exists()
