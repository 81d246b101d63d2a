"""Friction that varies over a 2D interface (docs/3d.md, docs/config.md
"Parameters along x"): a run with `a` along z and `b` along x writes the
per-node parameters to /friction ([N*N_z], x fastest) equal to the profiles'
formula at every node, and the resolved config keeps the profile along z;
a pair of dissimilar bodies (configs/3d/tiny_bodies.toml) with `a` along z
runs and writes the same;
configs/3d/band.toml (slow tier) with `slipstrip events --min-slip-rate 12`
gives events that stay in the rate-weakening band: every kept event is
narrower in z than the width and nucleates in the band.

Run: SLIPSTRIP_BUILD_DIR=$PWD/build PYTHONPATH=$PWD/python OMP_NUM_THREADS=1 \\
     /usr/bin/python3 -m pytest -q tests/python/test_interface_2d_friction.py
"""
import subprocess

import h5py
import numpy as np
import pytest

from conftest import REPO

TINY_3D = REPO / "configs" / "3d" / "tiny.toml"
TINY_BODIES = REPO / "configs" / "3d" / "tiny_bodies.toml"
BAND = REPO / "configs" / "3d" / "band.toml"
NX, NZ, LX, LZ = 32, 16, 0.25, 0.125


def test_friction_profiles_along_z_and_x_reach_every_node(tmp_path, slipstrip_module):
    out = tmp_path / "profiles.h5"
    a_z, a_v = [0.0, 0.03, 0.05, 0.09, 0.125], [0.03, 0.03, 0.005, 0.005, 0.03]
    # Profiles as TOML inline tables (the --set form, docs/config.md).
    slipstrip_module.run(TINY_3D, out, overrides=[
        f"geometry.nodes_z={NZ}", f"geometry.width={LZ}", "time.duration_transits=1.0",
        'friction.a={ profile = "piecewise_linear", z = [0.0, 0.03, 0.05, 0.09, 0.125], '
        'values = [0.03, 0.03, 0.005, 0.005, 0.03] }',
        'friction.b={ profile = "piecewise_constant", x = [0.0, 0.1], values = [0.075, 0.06] }'])
    with h5py.File(out, "r") as f:
        x, z = f["friction/x"][:], f["friction/z"][:]
        a, b = f["friction/a"][:], f["friction/b"][:]
        config = f.attrs["config"]
        config = config.decode() if isinstance(config, bytes) else config
    assert a.shape == (NX * NZ,)
    # Node i = ix + NX iz at (ix dx, iz dz), x fastest.
    i = np.arange(NX * NZ)
    assert np.array_equal(x, (i % NX) * (LX / NX)) and np.array_equal(z, (i // NX) * (LZ / NZ))
    # np.interp is the piecewise-linear formula with constant ends; 1e-15
    # absolute (a ~ 0.03): a few roundings of another evaluation order.
    assert np.max(np.abs(a - np.interp(z, a_z, a_v))) <= 1e-15
    assert np.array_equal(b, np.where(x < 0.1, 0.075, 0.06))
    assert "z = [0.0, 0.03, 0.05, 0.09, 0.125]" in config


def test_dissimilar_bodies_run_with_a_profile_along_z(tmp_path, slipstrip_module):
    # The pair of configs/3d/tiny_bodies.toml (32 x 32, 0.25 m x 0.25 m) with a
    # band in a along z: the run file's /friction is the formula at every node
    # and the normal-stress fields are written (the pair's path ran).
    out = tmp_path / "bodies.h5"
    a_z, a_v = [0.0, 0.05, 0.07, 0.18, 0.2, 0.25], [0.03, 0.03, 0.005, 0.005, 0.03, 0.03]
    slipstrip_module.run(TINY_BODIES, out, overrides=[
        "time.duration_transits=0.5",
        'friction.a={ profile = "piecewise_linear", z = [0.0, 0.05, 0.07, 0.18, 0.2, 0.25], '
        'values = [0.03, 0.03, 0.005, 0.005, 0.03, 0.03] }'])
    with h5py.File(out, "r") as f:
        z, a = f["friction/z"][:], f["friction/a"][:]
        sigma = f["snapshots/normal_stress"][-1]
        assert f["snapshots/slip_rate_x"].shape[1:] == (32, 32)
    assert a.shape == (32 * 32,)
    # np.interp is the piecewise-linear formula; 1e-15 absolute (a ~ 0.03):
    # a few roundings of another evaluation order.
    assert np.max(np.abs(a - np.interp(z, a_z, a_v))) <= 1e-15
    assert np.all(np.isfinite(sigma)) and np.all(sigma > 0.0)


def test_a_profile_along_z_on_a_line_is_refused_by_name(tmp_path, cli):
    r = subprocess.run([str(cli), "run", str(REPO / "configs" / "quickstart.toml"), "--out", str(tmp_path / "x.h5"),
                        "--set", 'friction.a = { profile = "piecewise_linear", z = [0.0, 1.0], values = [0.01, 0.02] }'],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode != 0
    assert "friction.a = {...}: a profile along z (z = [...]) on a one-dimensional interface" in r.stderr
    assert "expected a profile along x (x = [...]) or a number" in r.stderr


# configs/3d/band.toml (H = 0.1 m: the band sticks between events at ~30-40
# v0) with its documented command: the rate-strengthening rows creep at
# about v0 under the outer-face drive, so only with the nodal slips slower
# than 12 v0 ignored does the stream pause between events (without it: 1
# event detected, 0 kept; docs/notes/2026-11-27-band-events-filter.md).
@pytest.mark.slow
def test_band_config_events_stay_in_the_band(tmp_path, cli, slipstrip_module):
    out = tmp_path / "band.h5"
    subprocess.run([str(cli), "run", str(BAND), "--out", str(out), "--quiet"], check=True, timeout=1800)
    subprocess.run([str(cli), "events", str(out), "--min-slip-rate", "12"], check=True, capture_output=True,
                   timeout=600)
    run = slipstrip_module.open_run(out)
    events = run.events
    width = run.width
    assert len(events["t_start"]) >= 1
    # Localised in z: every kept event is narrower than the width, and its
    # hypocentre lies in the rate-weakening band (a < f0 b, 0.08 < z < 0.42).
    # run.events is the catalog dict of the bindings: the file's L_z is its extent_z.
    assert np.all(events["extent_z"] < width)
    assert np.all((events["z_start"] > 0.08) & (events["z_start"] < 0.42))
