"""`mpirun -np 2 slipstrip-mpi run` against `slipstrip run` (docs/3d.md, "Across machines").

Run by ctest in an MPI build (test_parallel_run_np2, CMakeLists.txt), which
sets SLIPSTRIP_BIN, SLIPSTRIP_MPI_BIN and MPIEXEC; not part of the serial
pytest suite (tests/python).

The same config runs on one process and split over two; the run files are
compared dataset by dataset and attribute by attribute.  Expected: every
dataset bit for bit, except the time series' two means (mean slip and mean
shear stress along x), which each process sums over its own rows before the
sum over processes (MPI_Allreduce), so they add the same values in another
order.  For n values of one sign the two orders differ by at most
2 (n - 1) u of the value (u = 2^-53, the bound of recursive summation taken
for each order; the shear stress along x is positive, the slip along x too,
once it is not exactly 0).  The other fields are bit for bit because FFTW's
MPI transform happens to add in the same order as the one-process transform at
these sizes (the distributed step's test, tests/cpp/test_parallel_interface_2d.cpp,
allows 1e-11 for its fields; this test would report a change of FFTW's order
as a failure to look at).  Not compared: start_time and end_time (wall clock),
and `processes`, which only the MPI file has (2).

Stations: each process interpolates along x in the stations' rows it holds
and rank 0 combines the two rows of each station along z, so a station
between rows held by two processes is taken as on one process; the moment
rate's sum of v_x runs through the processes in row order.  Expected: the
station records of two processes, of one process through MPI and of
`slipstrip run` bit for bit.

Restart points: a run of two processes stopped (--stop-after-steps, SIGTERM
to both processes) and resumed with `slipstrip-mpi run --resume` on two
processes writes the file of the uninterrupted run of two processes, bit for
bit but start_time and end_time.  Its restart point holds the history
operator state in the one-process layout (each process's Fourier modes
merged by global mode), so it is also resumed on one process (slipstrip-mpi
or `slipstrip run --resume`), and a restart point of `slipstrip run` on two
processes.  Expected: the file of the uninterrupted run on the resuming
process count, bit for bit, but for the two means' rows up to the restart
point, which are those of the process count that wrote them (bit for bit
the uninterrupted run's there), and `processes`, which the file keeps from
the run that created it.
"""
import os
import shutil
import signal
import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
TINY = REPO / "configs" / "3d" / "tiny.toml"
SERIAL = os.environ.get("SLIPSTRIP_BIN")
MPI = os.environ.get("SLIPSTRIP_MPI_BIN")
MPIEXEC = os.environ.get("MPIEXEC") or shutil.which("mpirun")

pytestmark = pytest.mark.skipif(not (SERIAL and MPI and MPIEXEC),
                                reason="needs SLIPSTRIP_BIN, SLIPSTRIP_MPI_BIN and MPIEXEC (an MPI build's ctest)")

# 20 transits of the 32 x 32 demo: one kept event, the rupture front reached
# at some nodes, 19 snapshots (under 1 s on one process).
EVENTS_RUN = ["--set", "time.duration_transits=20",
              "--set", "output.front_slip_rate=4e-3", "--set", "output.snapshot_interval=1e-4"]
WALL_CLOCK = {"start_time", "end_time"}
MEANS = {"timeseries/mean_slip", "timeseries/mean_shear_stress"}


def mpi_env():
    env = dict(os.environ, OMP_NUM_THREADS="1")
    # OpenMPI refuses to start as root (containers) without this consent.
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    return env


def run_serial(out, *args, check=True):
    """out None: `args` name the run (--resume RUN.h5)."""
    command = [SERIAL, "run", *([] if out is None else [str(TINY), "--out", str(out)]), "--quiet", *args]
    return subprocess.run(command, env=mpi_env(), capture_output=True, text=True, check=check, timeout=300)


def run_mpi(out, *args, processes=2, check=True, config=TINY):
    """out None: `args` name the run (--resume RUN.h5)."""
    command = [MPIEXEC, "-np", str(processes), "--oversubscribe", MPI, "run",
               *([] if out is None else [str(config), "--out", str(out)]), "--quiet", *args]
    return subprocess.run(command, env=mpi_env(), capture_output=True, text=True, check=check, timeout=300)


def assert_attributes_equal(one, split, name, skip=()):
    assert set(one.attrs) - set(skip) == set(split.attrs) - set(skip), name
    for key in set(one.attrs) - set(skip):
        assert np.array_equal(np.asarray(one.attrs[key]), np.asarray(split.attrs[key])), (name, key)


def assert_files_identical(reference, resumed):
    """Two files of two processes: every dataset and attribute bit for bit
    but the wall-clock dates."""
    with h5py.File(reference, "r") as a, h5py.File(resumed, "r") as b:
        names, other = [], []
        a.visit(names.append)
        b.visit(other.append)
        assert names == other
        for name in [""] + names:
            x, y = (a[name], b[name]) if name else (a, b)
            assert set(x.attrs) == set(y.attrs), name
            for key in set(x.attrs) - WALL_CLOCK:
                assert np.asarray(x.attrs[key]).tobytes() == np.asarray(y.attrs[key]).tobytes(), (name, key)
            if isinstance(x, h5py.Dataset):
                assert x.dtype == y.dtype and x[()].tobytes() == y[()].tobytes(), name


def refusal_line(completed):
    """slipstrip-mpi's one line "rank 0: ...", or slipstrip's last line."""
    lines = [line for line in completed.stderr.splitlines() if line.strip()]
    ranks = [line for line in lines if line.startswith("rank ")]
    if ranks:
        assert len(ranks) == 1, completed.stderr
        return ranks[0]
    return lines[-1] if lines else ""


def assert_runs_equal(one_path, split_path, nodes):
    """The files of one process and of two: every dataset and attribute."""
    bound = 2 * (nodes - 1) * 2.0**-53
    with h5py.File(one_path, "r") as one, h5py.File(split_path, "r") as split:
        assert "processes" not in one.attrs
        assert split.attrs["processes"] == 2
        assert_attributes_equal(one, split, "/", skip=WALL_CLOCK | {"processes"})
        names = []
        one.visit(names.append)
        other = []
        split.visit(other.append)
        assert sorted(names) == sorted(other)
        for name in names:
            a, b = one[name], split[name]
            assert_attributes_equal(a, b, name)
            if not isinstance(a, h5py.Dataset):
                continue
            assert a.shape == b.shape and a.dtype == b.dtype, name
            x, y = a[()], b[()]
            if name in MEANS:
                assert np.all(np.abs(x - y) <= bound * np.abs(x)), (name, np.max(np.abs(x - y) / np.abs(x)))
            else:
                assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), name


def test_two_processes_write_the_one_process_run_file(tmp_path):
    (tmp_path / "one").mkdir()
    (tmp_path / "two").mkdir()
    one, two = tmp_path / "one" / "run.h5", tmp_path / "two" / "run.h5"
    run_serial(one, *EVENTS_RUN)
    done = run_mpi(two, *EVENTS_RUN)
    assert "completed after 2600 steps" in done.stderr
    assert_runs_equal(one, two, 32 * 32)
    with h5py.File(two, "r") as f:
        assert f.attrs["status"] == "completed"
        assert f["snapshots/time"].shape[0] == 19
        front = f["rupture_front/arrival_time"][()]
        assert 0 < np.count_nonzero(np.isfinite(front)) < front.size
    # The sidecar names the file by its name (the same in both directories).
    assert (one.with_suffix(".xdmf")).read_text() == (two.with_suffix(".xdmf")).read_text()
    assert not Path(str(two) + ".restart").exists()
    # The event catalog of the MPI file, by the unchanged `slipstrip events`.
    for path in (one, two):
        subprocess.run([SERIAL, "events", str(path)], env=mpi_env(), capture_output=True, text=True, check=True)
    with h5py.File(one, "r") as a, h5py.File(two, "r") as b:
        assert b["events"].attrs["n_events"] >= 1
        names = []
        a["events"].visit(names.append)
        assert names
        assert_attributes_equal(a["events"], b["events"], "events")
        for name in names:
            x, y = a["events"][name], b["events"][name]
            assert_attributes_equal(x, y, name)
            if isinstance(x, h5py.Dataset):
                assert np.array_equal(x[()], y[()], equal_nan=x.dtype.kind == "f"), name


def test_uneven_slabs_and_snapshots_by_slip(tmp_path):
    # 32 x 15 nodes: slabs of 8 and 7 rows, Fourier columns 9 and 8; the
    # snapshots taken by mean slip (rank 0's sum decides, the one its file holds).
    args = ["--set", "geometry.nodes_z=15",
            "--set", "geometry.width=0.1171875", "--set", "time.duration_transits=3",
            "--set", "output.snapshot_interval=0", "--set", "output.snapshot_slip_increment=5e-8"]
    (tmp_path / "one").mkdir()
    (tmp_path / "two").mkdir()
    one, two = tmp_path / "one" / "run.h5", tmp_path / "two" / "run.h5"
    run_serial(one, *args)
    run_mpi(two, *args)
    assert_runs_equal(one, two, 32 * 15)
    with h5py.File(two, "r") as f:
        assert f["snapshots"].attrs["trigger"] == "slip_increment"
        assert f["snapshots/time"].shape[0] > 3


@pytest.mark.parametrize("config", ["tiny_bodies.toml", "tiny_half_space.toml"])
def test_dissimilar_bodies(tmp_path, config):
    # A strip on a clamped strip of another material, and on a half-space of
    # another material (32 x 32, 2 transits, 320 steps): the normal stress and
    # the opening are two more snapshot fields; the distributed step carries
    # the pair operators of each process's modes and the normal stress's
    # transforms.  Compared as above.
    path = REPO / "configs" / "3d" / config
    args = ["--quiet", "--set", "output.checkpoint_interval=0", "--set", "output.front_slip_rate=4e-3"]
    (tmp_path / "one").mkdir()
    (tmp_path / "two").mkdir()
    one, two = tmp_path / "one" / "run.h5", tmp_path / "two" / "run.h5"
    subprocess.run([SERIAL, "run", str(path), "--out", str(one), *args], env=mpi_env(), capture_output=True,
                   text=True, check=True, timeout=300)
    subprocess.run([MPIEXEC, "-np", "2", "--oversubscribe", MPI, "run", str(path), "--out", str(two), *args],
                   env=mpi_env(), capture_output=True, text=True, check=True, timeout=300)
    assert_runs_equal(one, two, 32 * 32)
    with h5py.File(two, "r") as f:
        assert f.attrs["status"] == "completed"
        sigma = f["snapshots/normal_stress"][()]
        assert f["snapshots/opening"].shape == sigma.shape
        # The normal stress really varies (the comparison is not of constants).
        assert np.ptp(sigma[-1]) > 1e-6 * np.max(np.abs(sigma[-1]))
    assert one.with_suffix(".xdmf").read_text() == two.with_suffix(".xdmf").read_text()


def station_args(x, z, interval):
    return ["--set", "output.stations=[" + ", ".join(repr(v) for v in x) + "]",
            "--set", "output.stations_z=[" + ", ".join(repr(v) for v in z) + "]",
            "--set", f"output.station_interval={interval!r}"]


# Stations on the 32 x 32 demo (dx = dz = L/32; on two processes rows 0-15 and
# 16-31): on node (0, 0); between rows 15 and 16 (one process each); between
# row 31 and row 0 (the periodic wrap: the last process and the first); on row
# 16 at the last column; on row 15 (weight 0 along z, row 16 on the other
# process still read, as one process reads it); mid-cell inside rank 1's rows.
D = 0.25 / 32
STATIONS = station_args([0.0, 0.1, 2.5 * D, 31 * D, 9 * D, 0.13],
                        [0.0, 15.5 * D, 31.5 * D, 16 * D, 15 * D, 0.2], 1e-6)
# 32 x 15 nodes (slabs of 8 and 7 rows, dz = W/15): between rows 7 and 8, and
# between row 14 and row 0.
DZ15 = 0.1171875 / 15
STATIONS_15 = ["--set", "geometry.nodes_z=15", "--set", "geometry.width=0.1171875",
               *station_args([0.05, 0.2], [7.25 * DZ15, 14.5 * DZ15], 2e-6)]


def assert_stations_identical(reference, other):
    """/stations of two run files: every dataset and attribute bit for bit."""
    with h5py.File(reference, "r") as a, h5py.File(other, "r") as b:
        x, y = a["stations"], b["stations"]
        assert sorted(x) == sorted(y)
        assert_attributes_equal(x, y, "stations")
        for name in x:
            assert_attributes_equal(x[name], y[name], name)
            assert x[name].dtype == y[name].dtype and x[name][()].tobytes() == y[name][()].tobytes(), name


STATION_CASES = {
    # 3 transits: 390 steps, 274 station rows.
    "strips": (TINY, ["--set", "time.duration_transits=3", *STATIONS]),
    "uneven slabs": (TINY, ["--set", "time.duration_transits=3", *STATIONS_15]),
    # 320 steps; nine fields (the normal stress and the opening).
    "dissimilar bodies": (REPO / "configs" / "3d" / "tiny_bodies.toml", STATIONS),
}


@pytest.mark.parametrize("case", list(STATION_CASES))
def test_stations_on_two_processes_equal_one_process(tmp_path, case):
    config, args = STATION_CASES[case]
    runs = {name: tmp_path / name / "run.h5" for name in ("serial", "one", "two")}
    for path in runs.values():
        path.parent.mkdir()
    subprocess.run([SERIAL, "run", str(config), "--out", str(runs["serial"]), "--quiet", *args], env=mpi_env(),
                   capture_output=True, text=True, check=True, timeout=300)
    run_mpi(runs["one"], *args, processes=1, config=config)
    run_mpi(runs["two"], *args, config=config)
    # The whole file of two processes as `slipstrip run`'s (the stations
    # bit for bit among the rest), and the stations of one process through MPI.
    nodes_z = 15 if case == "uneven slabs" else 32
    assert_runs_equal(runs["serial"], runs["two"], 32 * nodes_z)
    assert_stations_identical(runs["serial"], runs["one"])
    assert_stations_identical(runs["serial"], runs["two"])
    with h5py.File(runs["two"], "r") as f:
        g = f["stations"]
        fields = 9 if case == "dissimilar bodies" else 7
        assert len(g) == 5 + fields and g["slip_x"].attrs["units"] == "m"
        assert g["time"].shape[0] > 100 and g["slip_rate_x"].shape == (g["time"].shape[0], g["x"].shape[0])
        # The fields vary from station to station (the comparison is not of constants).
        assert np.all(np.ptp(g["state"][-1:], axis=1) > 0)


def test_stations_stopped_and_resumed_equal_uninterrupted(tmp_path):
    # Station rows every 3 us (about every 4.3 steps of dt = 0.70 us), so the
    # trigger at the stop (step 133) lies between steps: the restart point
    # carries it (run/next_station) and the resumed run takes the rows the
    # uninterrupted one takes.  Also against `slipstrip run` uninterrupted.
    args = ["--set", "time.duration_transits=6", *station_args(
        [0.0, 0.1, 2.5 * D, 0.13], [0.0, 15.5 * D, 31.5 * D, 0.2], 3e-6)]
    (tmp_path / "serial").mkdir()
    serial = tmp_path / "serial" / "reference.h5"
    reference, resumed = tmp_path / "reference.h5", tmp_path / "resumed.h5"
    run_serial(serial, *args)
    run_mpi(reference, *args)
    stopped = run_mpi(resumed, *args, "--stop-after-steps", "133", check=False)
    assert stopped.returncode == 143, stopped.stderr
    restart = Path(str(resumed) + ".restart")
    with h5py.File(restart, "r") as f:
        rows = int(f["output"].attrs["station_rows"])
        next_station = float(f["run"].attrs["next_station"])
    with h5py.File(resumed, "r") as f:
        assert f["stations/time"].shape[0] == rows
        assert rows == 32  # t = 0 and every 3 us up to step 133
        assert f["stations/time"][-1] < next_station <= f["stations/time"][-1] + 3e-6 * (1 + 1e-9)
    done = run_mpi(None, "--resume", str(resumed))
    assert "resumed from step 133" in done.stderr and "completed after" in done.stderr
    assert_files_identical(reference, resumed)
    assert_stations_identical(serial, resumed)
    with h5py.File(resumed, "r") as f:
        assert f["stations/time"].shape[0] > 2 * rows


# 6 transits (780 steps) of the demo; the block operator, half-spaces and
# dissimilar bodies (tiny_bodies.toml, tiny_half_space.toml: 320 steps; the
# normal stress, its opening and the pair operators) restore their own states.
RESTART_CASES = {
    "modal strips": (TINY, ["--set", "time.duration_transits=6"]),
    "block strips": (TINY, ["--set", "time.duration_transits=6", "--set", "time.history=block"]),
    "half-spaces": (TINY, ["--set", "time.duration_transits=6", "--set", 'geometry.height="inf"',
                           "--set", "time.beta=0.24"]),
    "dissimilar bodies": (REPO / "configs" / "3d" / "tiny_bodies.toml", []),
    "dissimilar half-space": (REPO / "configs" / "3d" / "tiny_half_space.toml", []),
}


@pytest.mark.parametrize("case", list(RESTART_CASES))
def test_stopped_after_steps_and_resumed_equals_uninterrupted(tmp_path, case):
    config, extra = RESTART_CASES[case]
    args = ["--set", "output.front_slip_rate=2.01e-3", "--set", "output.snapshot_interval=1e-4", *extra]
    reference, resumed = tmp_path / "reference.h5", tmp_path / "resumed.h5"
    run_mpi(reference, *args, config=config)
    assert not Path(str(reference) + ".restart").exists()  # a completed run leaves none
    stopped = run_mpi(resumed, *args, "--stop-after-steps", "133", config=config, check=False)
    assert stopped.returncode == 143, stopped.stderr
    restart = Path(str(resumed) + ".restart")
    assert restart.exists() and f"--resume {resumed}" in stopped.stderr
    with h5py.File(resumed, "r") as f:
        assert f.attrs["status"] == "interrupted"
        assert f["timeseries/time"].shape[0] == 134
    with h5py.File(restart, "r") as f:
        assert f["history"].attrs["kind"] == "interface 2d"  # the one-process layout
        assert f["simulation/slip"].shape == (32 * 32,)  # the one-process layout
        assert ("normal_stress" in f["simulation"]) == case.startswith("dissimilar")
    done = run_mpi(None, "--resume", str(resumed))
    assert "resumed from step 133" in done.stderr and "completed after" in done.stderr
    assert not restart.exists()
    assert_files_identical(reference, resumed)
    # A completed run: nothing to resume (exit 0), as `slipstrip run --resume`.
    again = run_mpi(None, "--resume", str(resumed))
    assert "nothing to resume" in again.stderr


def run_serial_config(out, *args, config=TINY, check=True):
    """`slipstrip run` of `config`; out None: `args` name the run (--resume RUN.h5)."""
    command = [SERIAL, "run", *([] if out is None else [str(config), "--out", str(out)]), "--quiet", *args]
    return subprocess.run(command, env=mpi_env(), capture_output=True, text=True, check=check, timeout=300)


def assert_resumed_equals(reference, resumed, stop_rows, written_by, created_by):
    """A run resumed on another process count against the uninterrupted run
    on that count (`reference`): every dataset and attribute bit for bit but
    the wall-clock dates, `processes` (kept from the run that created the
    file: `created_by`, None for `slipstrip run`), and the two means' first
    `stop_rows` rows, which are those of `written_by`, the uninterrupted run
    on the process count that wrote the restart point (bit for bit)."""
    with h5py.File(reference, "r") as a, h5py.File(resumed, "r") as b, h5py.File(written_by, "r") as w:
        if created_by is None:
            assert "processes" not in b.attrs
        else:
            assert b.attrs["processes"] == created_by
        names, other = [], []
        a.visit(names.append)
        b.visit(other.append)
        assert names == other
        for name in [""] + names:
            x, y = (a[name], b[name]) if name else (a, b)
            skip = WALL_CLOCK | {"processes"} if not name else set()
            assert set(x.attrs) - skip == set(y.attrs) - skip, name
            for key in set(x.attrs) - skip:
                assert np.asarray(x.attrs[key]).tobytes() == np.asarray(y.attrs[key]).tobytes(), (name, key)
            if not isinstance(x, h5py.Dataset):
                continue
            assert x.dtype == y.dtype and x.shape == y.shape, name
            if name in MEANS:
                assert y[:stop_rows].tobytes() == w[name][:stop_rows].tobytes(), name
                assert y[stop_rows:].tobytes() == x[stop_rows:].tobytes(), name
            else:
                assert x[()].tobytes() == y[()].tobytes(), name


# Identical strips (modal operators) and dissimilar bodies (the pair
# operators: face and antiplane operators, the normal stress): their runs on
# one and two processes are bit for bit (but the means), so a resume on the
# other count must be too.  Every operator kind's regrouping, half-spaces and
# block strips included, is checked without MPI by
# tests/cpp/test_kernels_interface_2d_mode_records.cpp.
ANOTHER_COUNT_CASES = ["modal strips", "dissimilar bodies"]


@pytest.mark.parametrize("case", ANOTHER_COUNT_CASES)
def test_restart_points_resume_on_another_process_count(tmp_path, case):
    config, extra = RESTART_CASES[case]
    args = ["--set", "output.front_slip_rate=2.01e-3", "--set", "output.snapshot_interval=1e-4", *extra]
    stop = ["--stop-after-steps", "133"]
    for d in ("one", "two", "a", "b", "c", "d"):
        (tmp_path / d).mkdir()
    # The uninterrupted runs on one process (slipstrip-mpi: `slipstrip run`'s
    # file bit for bit, but `processes`) and on two.
    one, two = tmp_path / "one" / "run.h5", tmp_path / "two" / "run.h5"
    run_mpi(one, *args, config=config, processes=1)
    run_mpi(two, *args, config=config)
    # Two processes -> one (slipstrip-mpi), and -> `slipstrip run --resume`
    # (a copy of the same stopped run).
    a, b = tmp_path / "a" / "run.h5", tmp_path / "b" / "run.h5"
    assert run_mpi(a, *args, *stop, config=config, check=False).returncode == 143
    with h5py.File(str(a) + ".restart", "r") as f:
        assert f["history"].attrs["kind"] == "interface 2d"
    for suffix in ("", ".restart"):
        shutil.copy(str(a) + suffix, str(b) + suffix)
    for path, resume in ((a, lambda p: run_mpi(None, "--resume", str(p), processes=1)),
                         (b, lambda p: run_serial_config(None, "--resume", str(p)))):
        done = resume(path)
        assert "resumed from step 133" in done.stderr and "completed after" in done.stderr, done.stderr
        assert not Path(str(path) + ".restart").exists()
        assert_resumed_equals(one, path, 134, two, created_by=2)
    # One process (slipstrip-mpi) -> two, and `slipstrip run`'s restart point -> two.
    c, d = tmp_path / "c" / "run.h5", tmp_path / "d" / "run.h5"
    assert run_mpi(c, *args, *stop, config=config, processes=1, check=False).returncode == 143
    assert run_serial_config(d, *args, *stop, config=config, check=False).returncode == 143
    for path, created_by in ((c, 1), (d, None)):
        done = run_mpi(None, "--resume", str(path))
        assert "resumed from step 133" in done.stderr and "completed after" in done.stderr, done.stderr
        assert_resumed_equals(two, path, 134, one, created_by=created_by)


def test_restart_points_refused_when_damaged_or_of_another_run(tmp_path):
    for d in ("one", "two", "other"):
        (tmp_path / d).mkdir()
    single, split, other = (tmp_path / d / "run.h5" for d in ("one", "two", "other"))
    args = ["--set", "time.duration_transits=1"]
    assert run_mpi(split, *args, "--stop-after-steps", "50", check=False).returncode == 143
    assert run_serial(single, *args, "--stop-after-steps", "50", check=False).returncode == 143
    # The interrupted files: as the completed ones.
    assert_runs_equal(single, split, 32 * 32)
    # Another run's restart point (another mesh: 32 x 15 nodes) next to this
    # run file: refused by one process and by `slipstrip run` (the config it
    # holds).
    assert run_mpi(other, *args, "--set", "geometry.nodes_z=15", "--set", "geometry.width=0.1171875",
                   "--stop-after-steps", "50", check=False).returncode == 143
    shutil.copy(str(split) + ".restart", tmp_path / "restart.keep")
    shutil.copy(str(other) + ".restart", str(split) + ".restart")
    refused = run_mpi(None, "--resume", str(split), processes=1, check=False)
    assert refused.returncode == 2, refused.stderr
    line = refusal_line(refused)
    assert line.startswith("rank 0: ") and "was written for another config than the run file" in line, line
    refused = run_serial(None, "--resume", str(split), check=False)
    assert refused.returncode == 2 and "was written for another config" in refusal_line(refused)
    shutil.copy(tmp_path / "restart.keep", str(split) + ".restart")
    # A damaged restart point: the message of `slipstrip run --resume`, on
    # another process count too.
    with h5py.File(str(split) + ".restart", "r+") as f:
        slip = f["simulation/slip"]
        slip[3] = slip[3] + 1e-9
    refused = run_mpi(None, "--resume", str(split), processes=3, check=False)
    assert refused.returncode == 2, refused.stderr
    assert "is damaged" in refusal_line(refused) and "rank 0: " in refusal_line(refused)
    refused = run_serial(None, "--resume", str(split), check=False)
    assert refused.returncode == 2 and "is damaged" in refusal_line(refused)
    with h5py.File(split, "r") as f:
        assert f.attrs["status"] == "interrupted"  # untouched


@pytest.mark.parametrize("args, names", [
    (["--set", "geometry.nodes_z=1", "--set", "geometry.width=0.25"], "geometry.nodes_z = 1"),
])
def test_refused_in_one_line_by_rank_0(tmp_path, args, names):
    out = tmp_path / "run.h5"
    refused = run_mpi(out, *args, check=False)
    assert refused.returncode == 2, refused.stderr
    lines = [line for line in refused.stderr.splitlines() if line.startswith("rank ")]
    assert len(lines) == 1 and lines[0].startswith("rank 0: ") and names in lines[0], refused.stderr
    assert not out.exists()


def test_resource_limits_as_slipstrip_run(tmp_path):
    """The run header and the limits of `slipstrip run` before any set-up: the
    output limit refuses in one line by rank 0 naming the option, as the
    serial run does; the memory limit is per process (the whole operator
    against P times it)."""
    out = tmp_path / "run.h5"
    refused = run_mpi(out, "--max-output-gib", "1e-9", check=False)
    assert refused.returncode == 2, refused.stderr
    line = refusal_line(refused)
    assert line.startswith("rank 0: ") and "output file would hold" in line and "--max-output-gib" in line, refused.stderr
    assert "output up to ~" in refused.stderr  # the header came first
    assert not out.exists()
    serial = run_serial(out, "--max-output-gib", "1e-9", check=False)
    assert serial.returncode == 2 and "output file would hold" in refusal_line(serial)
    refused = run_mpi(out, "--max-steps", "1", check=False)
    assert refused.returncode == 2 and "--max-steps" in refusal_line(refused), refused.stderr
    # The operator's memory: a limit of 0.75 of the whole operator's estimate
    # (read from the serial refusal) refuses one process and passes two.
    header = run_serial(out, "--max-memory-gib", "1e-12", check=False)
    line = refusal_line(header)
    assert header.returncode == 2 and "history operator needs ~" in line
    whole = float(line.split("history operator needs ~")[1].split(" GiB")[0])
    limit = str(0.75 * whole)
    alone = run_mpi(out, "--max-memory-gib", limit, processes=1, check=False)
    assert alone.returncode == 2 and "--max-memory-gib" in refusal_line(alone), alone.stderr
    assert not out.exists()
    run_mpi(out, "--max-memory-gib", limit, processes=2)
    with h5py.File(out, "r") as f:
        assert f.attrs["status"] == "completed"


def test_output_checks_on_rank_0(tmp_path):
    out = tmp_path / "run.h5"
    out.write_bytes(b"not a run file")
    refused = run_mpi(out, check=False)
    assert refused.returncode == 2
    lines = [line for line in refused.stderr.splitlines() if line.startswith("rank ")]
    assert len(lines) == 1 and lines[0].startswith("rank 0: ") and "exists" in lines[0], refused.stderr
    assert out.read_bytes() == b"not a run file"
    # The run's lock, held by another process: refused before any set-up.
    lock = Path(str(out) + ".lock")
    holder = subprocess.Popen(["flock", str(lock), "sleep", "60"])
    try:
        for _ in range(100):
            if lock.exists():
                break
            subprocess.run(["sleep", "0.05"])
        refused = run_mpi(out, "--overwrite", check=False)
    finally:
        holder.kill()
        holder.wait()
    assert refused.returncode == 2
    assert "rank 0: " in refused.stderr and "in use" in refused.stderr, refused.stderr
    assert out.read_bytes() == b"not a run file"


def test_the_config_is_never_the_output(tmp_path):
    # As `slipstrip run`: the config is an input, so --out naming it is
    # refused even with --overwrite, and the config is left as it was.
    config = tmp_path / "tiny.toml"
    config.write_text(TINY.read_text())
    before = config.read_bytes()
    refused = run_mpi(config, "--overwrite", check=False, config=config)
    assert refused.returncode == 2, refused.stderr
    line = refusal_line(refused)
    assert line.startswith("rank 0: ") and "--out" in line and "input" in line, refused.stderr
    assert config.read_bytes() == before
    assert not Path(str(config) + ".restart").exists()


def test_a_config_that_one_process_cannot_read_is_refused_by_all(tmp_path):
    # Every process reads the config.  Here rank 1 starts in another working
    # directory, where the relative config path names nothing (as a node that
    # does not see the file would): the processes agree on the failure, so
    # the job ends in one line with exit 2 instead of rank 0 waiting forever
    # in a collective that rank 1 has left.
    work, elsewhere = tmp_path / "work", tmp_path / "elsewhere"
    work.mkdir()
    elsewhere.mkdir()
    (work / "tiny.toml").write_text(TINY.read_text())
    script = ('if [ "$OMPI_COMM_WORLD_RANK" = 1 ]; then cd "$1"; fi; shift; exec "$@"')
    command = [MPIEXEC, "-np", "2", "--oversubscribe", "sh", "-c", script, "sh", str(elsewhere),
               str(MPI), "run", "tiny.toml", "--out", str(work / "run.h5"), "--quiet"]
    refused = subprocess.run(command, cwd=work, env=mpi_env(), capture_output=True, text=True, timeout=120)
    assert refused.returncode == 2, refused.stderr
    line = refusal_line(refused)
    assert line.startswith("rank 1: ") and "tiny.toml" in line, refused.stderr
    assert not (work / "run.h5").exists()


def signal_both_ranks(out, args, sig, ready):
    """Starts `mpirun -np 2 slipstrip-mpi run` of `out`, waits until ready()
    (or the job ended), sends `sig` to both processes; returns the job's exit
    code and stderr."""
    command = [MPIEXEC, "-np", "2", "--oversubscribe", MPI, "run", str(TINY), "--out", str(out), "--quiet", *args]
    job = subprocess.Popen(command, env=mpi_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        for _ in range(1200):
            if ready() or job.poll() is not None:
                break
            subprocess.run(["sleep", "0.05"])
        ranks = subprocess.run(["pgrep", "-P", str(job.pid)], capture_output=True, text=True).stdout.split()
        assert len(ranks) == 2
        for pid in ranks:
            os.kill(int(pid), sig)
        _, stderr = job.communicate(timeout=120)
    finally:
        if job.poll() is None:
            job.kill()
            job.wait()
    return job.returncode, stderr


def test_sigterm_or_sigkill_to_the_processes_then_resume_equals_uninterrupted(tmp_path):
    # As a batch system stops a job (Slurm's scancel signals every process):
    # rank 0's stop request ends the time loop on every process in the same
    # step with a restart point; status "interrupted", exit 143.  (OpenMPI's
    # mpirun itself ends the job at once on SIGTERM, without this.)  SIGKILL
    # leaves the last restart point of rank 0's wall-clock timer
    # (output.checkpoint_interval, read every 16 steps).  Either run, resumed
    # up to 300 steps past its restart point (wherever the signal landed, which
    # depends on the machine's speed), writes the file of a run stopped at the
    # same step from t = 0.
    args = ["--set", "time.duration_transits=100000", "--set", "output.checkpoint_interval=0.25"]
    for sig in (signal.SIGTERM, signal.SIGKILL):
        out = tmp_path / f"{sig.name}.h5"
        restart = Path(str(out) + ".restart")
        returncode, stderr = signal_both_ranks(out, args, sig, out.exists if sig == signal.SIGTERM else restart.exists)
        assert restart.exists(), stderr
        if sig == signal.SIGTERM:
            assert returncode == 143, stderr
            assert "interrupted after" in stderr and "--resume" in stderr
            with h5py.File(out, "r") as f:
                assert f.attrs["status"] == "interrupted"
        with h5py.File(restart, "r") as c:
            step = int(c["simulation"].attrs["step_index"])
        assert step > 0
        stop = str(step + 300)
        reference = tmp_path / f"reference_{sig.name}.h5"
        assert run_mpi(reference, *args, "--stop-after-steps", stop, check=False).returncode == 143
        resumed = run_mpi(None, "--resume", str(out), "--stop-after-steps", stop, check=False)
        assert resumed.returncode == 143, resumed.stderr
        assert f"resumed from step {step}" in resumed.stderr, resumed.stderr
        assert_files_identical(reference, out)
