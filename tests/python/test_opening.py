"""Opening of an in-plane interface between different bodies (docs/bodies.md §4)
in the outputs: a strip on a softer, thicker strip under a strong shear-load
pulse opens and closes again within ~1500 steps
(tests/cpp/test_solver_interface_opening.cpp).

* slipstrip.open_run exposes `opening` (m) wherever it exposes `normal_stress`
  (the snapshots), and the normal stress is 0 exactly where the gap is open;
* /stations/opening (m) and the SEAS export's `opening` column;
* the Python Simulation's `opening` view;
* an interrupted run resumed from a restart point taken while the faces are
  open equals the uninterrupted run, every dataset bit for bit.
"""
import subprocess

import h5py
import numpy as np
import pytest

from test_restart import assert_files_identical

CONFIG = """
[geometry]
length = 1.0
height = 0.1
nodes = 64
[bottom]
body = "elastic"
shear_modulus = 3e9
height = 0.2
[interface]
load_pulse_amplitude = 5e6
pulse_center = 0.5
pulse_width = 0.05
profile = "bump"
rise_time = 1e-4
[time]
duration_transits = 6.0
[output]
snapshot_interval = 1e-5
stations = [0.375, 0.5, 0.625]
station_interval = 2e-6
"""


@pytest.fixture(scope="module")
def config_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("opening") / "opening.toml"
    path.write_text(CONFIG)
    return path


def run_cli(cli, *args):
    return subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def opening_run(cli, config_path, tmp_path_factory):
    out = tmp_path_factory.mktemp("opening_run") / "run.h5"
    r = run_cli(cli, "run", config_path, "--out", out, "--quiet")
    assert r.returncode == 0, r.stderr
    return out


def test_open_run_exposes_opening_with_the_normal_stress(opening_run, slipstrip_module):
    run = slipstrip_module.open_run(opening_run)
    assert run.status == "completed"
    snaps = run.snapshots
    gap = snaps["opening"][()]
    sigma = snaps["normal_stress"][()]
    assert gap.shape == sigma.shape == (len(snaps), run.nodes)
    with h5py.File(opening_run, "r") as f:
        assert f["snapshots/opening"].attrs["units"] == "m"
        assert f["snapshots/normal_stress"].attrs["units"] == "Pa"
    assert np.all(np.isfinite(gap)) and np.all(gap >= 0.0)
    assert gap.max() > 0.0                       # it opened ...
    assert np.all(sigma[gap > 0.0] == 0.0)       # ... with no normal traction while open
    assert np.all(gap[sigma > 0.0] == 0.0)       # in contact the gap is 0 exactly
    assert np.all(sigma >= 0.0)
    assert gap[-1].max() == 0.0 and sigma[-1].min() > 0.0   # and closed again by the end


def test_stations_and_seas_export_carry_opening(opening_run, tmp_path, slipstrip_module):
    with h5py.File(opening_run, "r") as f:
        g = f["stations"]
        assert g["opening"].attrs["units"] == "m"
        assert g["opening"].shape == g["normal_stress"].shape
        station_gap = g["opening"][:]
        assert station_gap.max() > 0.0
        assert np.all(g["normal_stress"][:][station_gap > 0.0] == 0.0)
    written = slipstrip_module.export.export_seas(opening_run, tmp_path / "seas")
    seas = slipstrip_module.read_seas(written[1])  # the station at x = 0.5
    assert seas.columns == ("t", "slip", "slip_rate", "shear_stress", "state", "normal_stress", "opening")
    # Metres written as %.15e (16 significant digits) and read back: to 1 in 1e15.
    assert np.allclose(seas["opening"], station_gap[:, 1], rtol=1e-15, atol=0.0)
    assert "opening [m]" in seas.header["columns"]


def test_simulation_view_of_opening(slipstrip_module, config_path):
    sim = slipstrip_module.Simulation(str(config_path))
    opened = 0.0
    for _ in range(400):
        sim.step()
        assert np.all(sim.opening >= 0.0)
        assert np.all(sim.normal_stress[sim.opening > 0.0] == 0.0)
        opened = max(opened, sim.opening.max())
    assert opened > 0.0
    assert sim.opening_rate.shape == sim.opening.shape == sim.normal_stress.shape


def test_resume_through_an_open_phase_is_bit_for_bit(cli, config_path, opening_run, tmp_path):
    # The first step with an open node, from the snapshots' times and the time step.
    with h5py.File(opening_run, "r") as f:
        gap = f["snapshots/opening"][:]
        times = f["snapshots/time"][:]
        t = f["timeseries/time"][:]
    first_open = times[np.argmax(gap.max(axis=1) > 0.0)]
    stop = int(np.searchsorted(t, first_open)) + 3   # a few steps into the open phase
    out = tmp_path / "resumed.h5"
    r = run_cli(cli, "run", config_path, "--out", out, "--quiet", "--stop-after-steps", stop)
    assert r.returncode == 143, r.stderr
    with h5py.File(str(out) + ".restart", "r") as c:
        assert c["simulation"].attrs["step_index"] == stop
        assert np.any(c["simulation/gap"][:] > 0.0)          # the restart point is inside an open phase
        assert np.any(c["simulation/opening_stress"][:] != 0.0)
    r = run_cli(cli, "run", "--resume", out, "--quiet")
    assert r.returncode == 0, r.stderr
    assert_files_identical(opening_run, out)
