"""Output paths and error messages of every command, by the rules of the C++
CLI (the same functions, through the bindings; docs/reliability.md "Output
paths"):

* ``check_outputs``: an output never names an input (even with overwrite),
  never an existing file unless overwrite is given, never the same file as
  another output, and its directory must accept it -- checked before anything
  is computed.  Raises ``OutputPathError`` (a ``ValueError``) with one line.
* ``one_line``: any text as one printable line of bounded length (control
  characters escaped; head and tail of a long text kept), for every message
  that reaches a user.

    from slipstrip.paths import check_outputs
    check_outputs({"--csv": args.csv, "--plot": args.plot}, inputs=[args.run], overwrite=args.overwrite)
"""
from __future__ import annotations

import os
from typing import Iterable, Mapping, Union

from . import _slipstrip
from ._slipstrip import LockHeldError, OutputPathError  # noqa: F401  (re-exported)

__all__ = ["OutputPathError", "LockHeldError", "check_outputs", "run_outputs", "lock_run", "one_line",
           "MAX_MESSAGE_CHARS"]

PathLike = Union[str, "os.PathLike[str]"]

# The default bound of one_line (io::kMaxMessageChars).
MAX_MESSAGE_CHARS: int = _slipstrip.max_message_chars


def check_outputs(files: Mapping[str, PathLike | None] | None = None, *,
                  directories: Mapping[str, PathLike | None] | None = None,
                  inputs: Iterable[PathLike] = (), overwrite: bool = False,
                  overwrite_flag: str = "--overwrite") -> None:
    """Check every output of a command before it runs (io/output_paths.hpp).

    files / directories: {option name as the user wrote it: path}; None values
    (options not given) are skipped.  A directory output may exist as a
    directory; the files written into it are checked as files.
    overwrite_flag: how the message tells the user to allow replacing
    ("--overwrite" for a command line, "overwrite=True" for a function)."""
    outputs = [(str(o), os.fspath(p), False) for o, p in (files or {}).items() if p is not None]
    outputs += [(str(o), os.fspath(p), True) for o, p in (directories or {}).items() if p is not None]
    _slipstrip.check_output_paths(outputs, [os.fspath(p) for p in inputs], bool(overwrite), overwrite_flag)


def run_outputs(run_path: PathLike, option: str = "--out") -> dict[str, str]:
    """The files a new run writes, for check_outputs: the run file and its
    restart point RUN.h5.restart (solver/checkpoint.hpp)."""
    path = os.fspath(run_path)
    return {option: path, f"the restart point of {option}": _slipstrip.checkpoint_path(path)}


def lock_run(run_path: PathLike, what: str | None = None):
    """The lock of "one process per run" (RUN.h5.lock, io/file_lock.hpp), as
    the solver takes it: hold it while writing into a run file.  Raises
    LockHeldError (a ValueError) if another process holds it.  Use as
    ``with lock_run(path): ...``."""
    path = os.fspath(run_path)
    return _HeldLock(_slipstrip.run_lock_path(path), what or f"run file '{path}'")


class _HeldLock:
    def __init__(self, lock_path: str, what: str):
        self._lock = _slipstrip._FileLock(lock_path, what)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.release()
        return False

    def release(self) -> None:
        """Removes the lock file and releases the lock (also at garbage collection or process end)."""
        self._lock = None


def one_line(text: object, max_chars: int = MAX_MESSAGE_CHARS) -> str:
    """str(text) (or bytes) as one printable line of at most max_chars bytes
    (io/messages.hpp).  Bytes that are not UTF-8 (a surrogate-escaped file
    name, binary input) are shown as \\xNN."""
    raw = text if isinstance(text, bytes) else str(text).encode("utf-8", errors="surrogateescape")
    return _slipstrip.one_line(raw, int(max_chars))
