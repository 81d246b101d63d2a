"""`slipstrip run` of a 2D interface (geometry.nodes_z > 1, docs/3d.md) end to
end: the run file holds the 2D snapshots ([nodes_z, nodes_x] per field) and a
time series, readable with h5py; the XDMF sidecar points at exactly those
datasets (read back with an XML parser and resolved in the HDF5 file)."""
import subprocess
import xml.etree.ElementTree as ET

import h5py
import numpy as np
import pytest

from conftest import REPO

FIELDS = ("slip_x", "slip_z", "slip_rate_x", "slip_rate_z", "state", "shear_stress_x", "shear_stress_z")


@pytest.fixture(scope="module")
def run_3d(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("interface_2d") / "tiny.h5"
    r = subprocess.run([str(cli), "run", str(REPO / "configs" / "3d" / "tiny.toml"), "--set", "geometry.nodes=16",
                        "--set", "geometry.nodes_z=8", "--set", "time.duration_transits=0.5",
                        "--out", str(out), "--quiet"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return out


def test_run_file_holds_2d_snapshots(run_3d):
    with h5py.File(run_3d, "r") as f:
        assert f.attrs["status"] == "completed"
        assert f.attrs["format"] == "slipstrip interface_2d"
        assert "nodes_z = 8" in f.attrs["config"]
        x, z = f["grid/x"][:], f["grid/z"][:]
        assert x.shape == (16,) and z.shape == (8,)
        times = f["snapshots/time"][:]
        assert len(times) >= 2 and np.all(np.diff(times) > 0)
        for s in range(len(times)):
            group = f["snapshots/%06d" % s]
            assert group.attrs["time"] == times[s]
            for name in FIELDS:
                values = group[name][:]
                assert values.shape == (8, 16)
                assert np.all(np.isfinite(values))
        first = f["snapshots/000000"]
        # t = 0: no history, so the slip rate is along x everywhere; the
        # state carries white noise node by node (varies along z).
        assert np.all(first["slip_rate_z"][:] == 0.0)
        assert np.all(first["slip_rate_x"][:] > 0)
        assert np.ptp(first["state"][:], axis=0).max() > 0
        last = f["snapshots/%06d" % (len(times) - 1)]
        assert np.all(last["slip_x"][:] > 0)
        assert np.abs(last["slip_rate_z"][:]).max() > 0  # slip across x is excited
        series = f["timeseries"]
        assert series["time"].shape == series["max_slip_rate"].shape == series["mean_slip_x"].shape
        assert np.all(np.diff(series["mean_slip_x"][:]) > 0)


def test_xdmf_sidecar_points_at_the_snapshots(run_3d):
    sidecar = run_3d.with_suffix(".xdmf")
    root = ET.parse(sidecar).getroot()
    collection = root.find("Domain/Grid")
    assert collection.get("CollectionType") == "Temporal"
    grids = collection.findall("Grid")
    with h5py.File(run_3d, "r") as f:
        times = f["snapshots/time"][:]
        assert len(grids) == len(times)
        for grid, t in zip(grids, times):
            assert float(grid.find("Time").get("Value")) == pytest.approx(t, rel=1e-15)
            topology = grid.find("Topology")
            assert topology.get("TopologyType") == "2DCoRectMesh"
            assert topology.get("Dimensions") == "8 16"
            names = set()
            for attribute in grid.findall("Attribute"):
                item = attribute.find("DataItem")
                file, dataset = item.text.strip().split(":", 1)
                assert file == run_3d.name
                assert f[dataset].shape == (8, 16)
                names.add(attribute.get("Name"))
            assert names == set(FIELDS)


def test_unsupported_2d_interface_config_is_refused(cli, tmp_path):
    r = subprocess.run([str(cli), "run", str(REPO / "configs" / "3d" / "tiny.toml"), "--set", "material.plane=stress",
                        "--out", str(tmp_path / "x.h5"), "--quiet"], capture_output=True, text=True, timeout=120)
    assert r.returncode != 0
    assert "material.plane" in r.stderr and "strain" in r.stderr
