"""The XDMF sidecar RUN.xdmf (docs/output.md, "ParaView and VisIt"): a run
writes it next to RUN.h5 after each write-out of snapshots, and it describes
the snapshots exactly as they are in the HDF5 file.

Checked by reading it back with an XML parser and resolving every data item
in the HDF5 file (dimensions, and the values the reader would get), and, when
Debian's python3-paraview is installed, by ParaView's own XDMF 3 reader, whose arrays must equal the HDF5 datasets.
"""
import subprocess
import xml.etree.ElementTree as ET

import h5py
import numpy as np
import pytest

from conftest import REPO

FIELDS = ("slip", "slip_rate", "state", "shear_stress")


@pytest.fixture(scope="module")
def run_with_sidecar(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("xdmf") / "tiny.h5"
    subprocess.run([str(cli), "run", str(REPO / "configs" / "quickstart.toml"), "--set", "geometry.nodes=64",
                    "--set", "time.duration_transits=3", "--set", "output.snapshot_interval=2e-5",
                    "--out", str(out), "--quiet"], check=True, capture_output=True, timeout=300)
    return out, out.with_suffix(".xdmf")


def data_items(sidecar):
    """{role: (dims, file, dataset)} for the sidecar's geometry and attributes."""
    root = ET.parse(sidecar).getroot()
    grid = root.find("Domain/Grid")
    topology = grid.find("Topology")
    assert topology.get("TopologyType") == "2DRectMesh"
    items = {}
    geometry = grid.find("Geometry")
    assert geometry.get("GeometryType") == "VXVY"
    for role, item in zip(("x", "time"), geometry.findall("DataItem")):
        file, dataset = item.text.strip().split(":", 1)
        items[role] = (tuple(int(d) for d in item.get("Dimensions").split()), file, dataset)
    for attribute in grid.findall("Attribute"):
        item = attribute.find("DataItem")
        file, dataset = item.text.strip().split(":", 1)
        items[attribute.get("Name")] = (tuple(int(d) for d in item.get("Dimensions").split()), file, dataset)
    return tuple(int(d) for d in topology.get("Dimensions").split()), items


def test_sidecar_describes_the_snapshots_as_stored(run_with_sidecar):
    h5_path, sidecar = run_with_sidecar
    assert sidecar.is_file()
    topology, items = data_items(sidecar)
    assert set(items) == {"x", "time", *FIELDS}
    with h5py.File(h5_path, "r") as f:
        n_snap, n = f["snapshots/slip"].shape
        assert n_snap > 10 and n == 64
        assert topology == (n_snap, n)
        for role, (dims, file, dataset) in items.items():
            assert file == h5_path.name  # relative: the pair can be moved together
            assert f[dataset].shape == dims, role
            assert np.all(np.isfinite(f[dataset][()])), role
        assert items["x"][2] == "/snapshots/x" and items["time"][2] == "/snapshots/time"


def test_vtk_reads_the_sidecar_as_the_hdf5_data(run_with_sidecar):
    # ParaView's XDMF 3 reader, from Debian's python3-paraview (optional: a
    # large package, so the test runs where it is installed).
    vtk = pytest.importorskip("vtkmodules.vtkIOXdmf3", reason="python3-paraview not installed")
    from vtkmodules.util.numpy_support import vtk_to_numpy
    h5_path, sidecar = run_with_sidecar
    reader = vtk.vtkXdmf3Reader()
    reader.SetFileName(str(sidecar))
    reader.Update()
    grid = reader.GetOutputDataObject(0)
    with h5py.File(h5_path, "r") as f:
        n_snap, n = f["snapshots/slip"].shape
        assert grid.GetNumberOfPoints() == n_snap * n
        for name in FIELDS:
            values = vtk_to_numpy(grid.GetPointData().GetArray(name))
            np.testing.assert_array_equal(values, f["snapshots"][name][()].ravel())
