"""Stopping a scan cleanly: its own SIGINT/SIGTERM handling, and one lock per run file.

A scan may be started with SIGINT ignored (a script's background job: the
shell sets SIGINT to SIG_IGN, and Python then installs no KeyboardInterrupt
handler), and SIGTERM ends a Python process at once by default, leaving its
solvers running as orphans.  So while a scan runs, `StopSignals` installs its
own handlers for both, whatever was inherited: the first signal is recorded,
no further run starts, every running task forwards it to its solver
(task.py, `_run_solver`), the solver writes its restart point and exits
128 + signal, and the row says "interrupted".  The scan then exits with the
same 128 + signal (130 for SIGINT, 143 for SIGTERM).

`RunLock` makes sure one run file never has two writers: a task takes an
exclusive flock on `locks/run_<i>.lock` before touching `run_<i>.h5`, and its
solver inherits the locked descriptor, so the lock lasts as long as the
solver does, even when the scan itself was killed (SIGKILL) and the solver
runs on as an orphan.  A relaunched scan that finds the lock taken leaves
that run alone and says which process holds it.
"""
from __future__ import annotations

import fcntl
import os
import signal
import threading
from pathlib import Path
from typing import TextIO

HANDLED_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def signal_name(signum: int) -> str:
    return signal.Signals(signum).name


class StopSignals:
    """While active (a `with` block in the main thread), SIGINT and SIGTERM are
    recorded instead of ending the process; calling the object gives the
    first signal received, 0 if none.  Outside the main thread (where Python
    cannot install handlers) it records nothing and the inherited handling
    stays.  The previous handlers are restored on exit."""

    def __init__(self, stream: TextIO | None = None):
        self.stream = stream
        self.signal = 0
        self.received = threading.Event()  # for threads that wait on a stop (the Dask client)
        self._previous: dict[int, object] = {}

    def __call__(self) -> int:
        return self.signal

    def _handle(self, signum, frame) -> None:
        first = not self.signal
        if first:
            self.signal = signum
            self.received.set()
        if self.stream is not None:
            what = ("stopping: no new run starts; the running solvers get the signal, write their "
                    "restart points and are listed as interrupted" if first else
                    "already stopping: waiting for the running solvers to write their restart points")
            print(f"[scan] {signal_name(signum)}: {what}", file=self.stream, flush=True)

    def __enter__(self) -> "StopSignals":
        if threading.current_thread() is threading.main_thread():
            for s in HANDLED_SIGNALS:
                self._previous[s] = signal.signal(s, self._handle)
        return self

    def __exit__(self, *exc) -> None:
        for s, handler in self._previous.items():
            signal.signal(s, handler)
        self._previous.clear()


def never_stop() -> int:
    """The stop request of a task nobody can stop (no signal handling around it)."""
    return 0


def exit_code(signum: int) -> int:
    """The shell's exit status of a process ended by `signum`: 128 + signum (SIGINT 130, SIGTERM 143)."""
    return 128 + signum


class ScanInterrupted(Exception):
    """run_scan was stopped by a signal; the summary of what ran is written.
    `signal` is the signal number, `rows` the rows written to the summary."""

    def __init__(self, signum: int, rows: list[dict], not_started: int):
        self.signal, self.rows, self.not_started = signum, rows, not_started
        n_interrupted = sum(r.get("status") == "interrupted" for r in rows)
        super().__init__(f"stopped by {signal_name(signum)}: {n_interrupted} run(s) interrupted "
                         f"(restart points kept), {not_started} not started; the summary lists the runs "
                         "finished or interrupted so far; relaunch the same command to continue "
                         "(interrupted runs resume from their restart points)")


def lock_path(run_file: Path) -> Path:
    """The lock file of a run file: locks/run_<i>.lock in the run's directory.
    Lock files are never deleted: deleting one while another process opens
    it would let two processes lock two different files of the same name."""
    return run_file.parent / "locks" / run_file.with_suffix(".lock").name


class RunBusy(Exception):
    """Another process holds the run's lock (a solver of an earlier scan, or another scan)."""


class RunLock:
    """Exclusive flock on locks/run_<i>.lock for as long as this object and every
    process that inherited `fd` keep it open (RAII: released on exit).  The
    file holds the pid of the last holder (`note_holder`), for the message
    a relaunch prints.  Raises RunBusy on entry if another process holds it."""

    def __init__(self, run_file: Path):
        self.path = lock_path(run_file)
        self.fd = -1

    def __enter__(self) -> "RunLock":
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(fd, 64, 0).decode(errors="replace").strip() or "unknown"
            os.close(fd)
            raise RunBusy(f"{self.path.name} is held by process {holder}") from None
        except BaseException:
            os.close(fd)
            raise
        self.fd = fd
        self.note_holder(os.getpid())
        return self

    def note_holder(self, pid: int) -> None:
        os.ftruncate(self.fd, 0)
        os.pwrite(self.fd, f"{pid}\n".encode(), 0)

    def __exit__(self, *exc) -> None:
        if self.fd >= 0:
            os.close(self.fd)  # the lock goes with the last descriptor (a solver may still hold one)
            self.fd = -1
