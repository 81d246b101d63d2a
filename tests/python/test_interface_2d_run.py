"""`slipstrip run` of a 2D interface (geometry.nodes_z > 1, docs/3d.md) end to
end: the run file holds the 2D snapshots ([snapshots, nodes_z, nodes_x] per
field) and a time series, readable with h5py; the XDMF sidecar points at
exactly those snapshots (read back with an XML parser and resolved in the HDF5
file, hyperslabs included)."""
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
        for name in FIELDS:
            dataset = f["snapshots"][name]
            # [snapshots, nodes_z, nodes_x], one chunk per snapshot: a map reads in one call.
            assert dataset.shape == (len(times), 8, 16) and dataset.chunks == (1, 8, 16)
            assert np.all(np.isfinite(dataset[:]))
        snapshots = f["snapshots"]
        # t = 0: no history, so the slip rate is along x everywhere; the
        # state carries white noise node by node (varies along z).
        assert np.all(snapshots["slip_rate_z"][0] == 0.0)
        assert np.all(snapshots["slip_rate_x"][0] > 0)
        assert np.ptp(snapshots["state"][0], axis=0).max() > 0
        assert np.all(snapshots["slip_x"][-1] > 0)
        assert np.abs(snapshots["slip_rate_z"][-1]).max() > 0  # slip across x is excited
        series = f["timeseries"]
        assert series["time"].shape == series["max_slip_rate"].shape == series["mean_slip"].shape
        # The mean slip along x, of the snapshots' slip_x where they coincide.
        assert np.all(np.diff(series["mean_slip"][:]) > 0)
        last = np.searchsorted(series["time"][:], times[-1])
        assert series["time"][last] == times[-1]
        assert series["mean_slip"][last] == pytest.approx(snapshots["slip_x"][-1].mean(), rel=1e-14)


def _resolve(item, f, run_file):
    """The array an XDMF DataItem stands for: an HDF dataset, or (XDMF 3's
    "file:/dataset|start:stride:count:dimensions") a hyperslab of one."""
    file, dataset = item.text.strip().split(":", 1)
    assert file == run_file.name
    if "|" in dataset:
        dataset, slab = dataset.split("|")
        start, stride, count, dims = (np.array(part.split(), dtype=int) for part in slab.split(":"))
        assert tuple(dims) == f[dataset].shape
        index = tuple(slice(a, a + s * c, s) for a, s, c in zip(start, stride, count))
        data = f[dataset][index]
        assert data.shape == tuple(int(d) for d in item.get("Dimensions").split())
        return data
    data = f[dataset]
    assert data.shape == tuple(int(d) for d in item.get("Dimensions").split())
    return data[()]


def test_xdmf_sidecar_points_at_the_snapshots(run_3d):
    sidecar = run_3d.with_suffix(".xdmf")
    root = ET.parse(sidecar).getroot()
    collection = root.find("Domain/Grid")
    assert collection.get("CollectionType") == "Temporal"
    grids = collection.findall("Grid")
    with h5py.File(run_3d, "r") as f:
        times = f["snapshots/time"][:]
        assert collection.find("Time") is None  # times are per grid (XDMF 3 has no time list)
        assert len(grids) == len(times)
        for s, grid in enumerate(grids):
            assert float(grid.find("Time").get("Value")) == times[s]  # 17 digits: the double exactly
            topology = grid.find("Topology")
            assert topology.get("TopologyType") == "2DRectMesh"
            assert topology.get("Dimensions") == "8 16"
            vx, vy = grid.findall("Geometry/DataItem")
            assert np.array_equal(_resolve(vx, f, run_3d), f["grid/x"][:])
            assert np.array_equal(_resolve(vy, f, run_3d), f["grid/z"][:])
            names = set()
            for attribute in grid.findall("Attribute"):
                name = attribute.get("Name")
                values = _resolve(attribute.find("DataItem"), f, run_3d)
                # Snapshot s of the field, as the HyperSlab's Dimensions say.
                assert values.shape == (1, 8, 16)
                assert np.array_equal(values[0], f["snapshots"][name][s])
                names.add(name)
            assert names == set(FIELDS)


def test_paraview_reads_the_xdmf_collection_as_the_hdf5_data(run_3d):
    # ParaView's XDMF 3 reader, from Debian's python3-paraview (optional: a
    # large package; .ci/run installs it): its time steps are the snapshot
    # times and, at each, its arrays are the snapshot's fields [N_z, N], x fastest.
    xdmf3 = pytest.importorskip("vtkmodules.vtkIOXdmf3", reason="python3-paraview not installed")
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline
    reader = xdmf3.vtkXdmf3Reader()
    reader.SetFileName(str(run_3d.with_suffix(".xdmf")))
    reader.UpdateInformation()
    steps = reader.GetOutputInformation(0).Get(vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    with h5py.File(run_3d, "r") as f:
        times = f["snapshots/time"][:]
        assert len(times) >= 3 and np.array_equal(np.asarray(steps), times)
        for s in (0, len(times) // 2, len(times) - 1):
            reader.UpdateTimeStep(times[s])
            grid = reader.GetOutputDataObject(0)
            assert grid.GetDimensions() == (16, 8, 1)
            assert np.array_equal(vtk_to_numpy(grid.GetXCoordinates()), f["grid/x"][:])
            assert np.array_equal(vtk_to_numpy(grid.GetYCoordinates()), f["grid/z"][:])
            for name in FIELDS:
                values = vtk_to_numpy(grid.GetPointData().GetArray(name))
                assert np.array_equal(values, f["snapshots"][name][s].ravel()), (name, s)


def test_unsupported_2d_interface_config_is_refused(cli, tmp_path):
    r = subprocess.run([str(cli), "run", str(REPO / "configs" / "3d" / "tiny.toml"), "--set", "material.plane=stress",
                        "--out", str(tmp_path / "x.h5"), "--quiet"], capture_output=True, text=True, timeout=120)
    assert r.returncode != 0
    assert "material.plane" in r.stderr and "strain" in r.stderr
