"""loading.drive = "mean_slip_rate" in a run file (docs/transition.md, "Driving
the mean slip rate"): the uniform shear stress tau_0(t) is recorded as
/timeseries/loading_shear_stress with its unit, and it is the mean shear stress
(the history has no uniform part, the mean slip rate is v0); the default drive
writes no such record."""
import subprocess

import h5py
import numpy as np
import pytest

from conftest import REPO

TINY = ["--set", "geometry.length=0.25", "--set", "geometry.nodes=64", "--set", "geometry.height=inf",
        "--set", "time.duration_transits=20", "--set", "output.timeseries_interval=0",
        "--set", "output.snapshot_interval=0", "--set", "initial.sine_amplitude=0.5"]


def run(cli, out, *extra):
    r = subprocess.run([str(cli), "run", str(REPO / "configs" / "reference.toml"), *TINY, *extra,
                        "--out", str(out), "--quiet"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return h5py.File(out, "r")


def test_run_file_records_the_loading_shear_stress(cli, tmp_path):
    with run(cli, tmp_path / "driven.h5", "--set", "loading.drive=mean_slip_rate") as f:
        assert f.attrs["status"] == "completed"
        load = f["timeseries/loading_shear_stress"]
        units = load.attrs["units"]
        assert (units.decode() if isinstance(units, bytes) else units) == "Pa"
        load = load[:]
        mean = f["timeseries/mean_shear_stress"][:]
        assert load.shape == mean.shape and np.all(np.isfinite(load))
        # mean(tau) = tau_0 - eta (mean v - v0): with |mean v - v0| <= 1e-9 v0
        # (the root find's tolerance) and eta v0 ~ 3e3 Pa that is <= 3e-6 Pa,
        # plus the rounding of a mean of 64 stresses of ~3e5 Pa (~4e-9 Pa).
        assert np.max(np.abs(load - mean)) < 1e-5
        # The sine perturbation moves tau_0 by kPa: the record is not a constant.
        assert np.ptp(load) > 100.0


def test_default_drive_writes_no_loading_record(cli, tmp_path):
    with run(cli, tmp_path / "default.h5") as f:
        assert "loading_shear_stress" not in f["timeseries"]
        assert set(f["timeseries"]) == {"time", "max_slip_rate", "mean_slip", "mean_shear_stress"}


@pytest.mark.slow
def test_half_space_is_reloaded_where_the_outer_faces_leave_it_locked(cli, tmp_path):
    """Two half-spaces, L = 1 m, N = 400, reference friction, 30 L/c_s: with the
    outer-face drive the interface locks (v_max = 0 from ~17 L/c_s on, nothing
    reloads the uniform mode); with the mean slip rate held at v0 it keeps
    slipping.  The criterion is the transition map's `arrested` one
    (docs/transition.md): v_max < 0.1 v0 throughout the last third."""
    common = ["--set", "geometry.length=1", "--set", "geometry.nodes=400", "--set", "geometry.height=inf",
              "--set", "time.duration_transits=30", "--set", "output.snapshot_interval=0",
              "--set", "output.timeseries_interval=1e-5", "--set", "output.delta_th=0"]
    v0 = 2e-3  # loading.driving_velocity of configs/reference.toml
    last_third = {}
    for drive in ("outer_faces", "mean_slip_rate"):
        out = tmp_path / f"{drive}.h5"
        r = subprocess.run([str(cli), "run", str(REPO / "configs" / "reference.toml"), *common,
                            "--set", f"loading.drive={drive}", "--out", str(out), "--quiet"],
                           capture_output=True, text=True, timeout=1800)
        assert r.returncode == 0, r.stderr
        with h5py.File(out, "r") as f:
            t = f["timeseries/time"][:]
            v_max = f["timeseries/max_slip_rate"][:]
        last_third[drive] = v_max[t >= 2.0 * t[-1] / 3.0]
    assert np.all(last_third["outer_faces"] < 0.1 * v0)      # arrested
    assert np.all(last_third["mean_slip_rate"] > 0.1 * v0)   # never locked
