"""The output-path rule of slipstrip.run() and `export --seas`, the rule of
`slipstrip run --out` (docs/reliability.md, "What survives what"), for any
Python command to call before it writes:

* an output never names an input (the same file by device and inode, so
  ``./a.h5``, ``a.h5`` and a symbolic link to it are one file), even with
  overwrite;
* two outputs never name the same file;
* an output that exists is refused unless overwrite is given (the message
  names how: ``--overwrite`` for a command line, ``overwrite=True`` for a
  function); a directory in the place of a file output is refused;
* a file output's directory must exist and accept it: the file is opened for
  writing as the command will (without truncating; a new file is created and
  removed again), so a missing or read-only directory is found before
  anything is computed;
* a directory output (the command writes files into it) may exist, but only
  as a directory; the files written there are file outputs of their own.

Raises ``OutputPathError`` (a ``ValueError``) with one line naming the
option, the path and the reason.

    from slipstrip.paths import check_outputs
    check_outputs({"--csv": args.csv, "--plot": args.plot}, inputs=[args.run], overwrite=args.overwrite)
"""
from __future__ import annotations

import os
from typing import Iterable, Mapping, Union

__all__ = ["OutputPathError", "check_outputs"]

PathLike = Union[str, "os.PathLike[str]"]


class OutputPathError(ValueError):
    """A refused output path (a bad command line: exit code 2)."""


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except (OSError, ValueError):  # one of them does not exist (or is not a valid path)
        return False


def _check_file(option: str, path: str, overwrite: bool, overwrite_flag: str) -> None:
    if os.path.isdir(path):
        raise OutputPathError(f"{option} '{path}' is a directory: expected a file name")
    if os.path.islink(path) and not os.path.exists(path):
        raise OutputPathError(f"{option} '{path}' is a symbolic link to nothing: refusing to write through it")
    exists = os.path.exists(path)
    if exists and not overwrite:
        raise OutputPathError(f"{option} '{path}' already exists: refusing to overwrite it "
                              f"(give {overwrite_flag} to replace it, or choose another path)")
    directory = os.path.dirname(path) or "."
    if not os.path.isdir(directory):
        reason = "is not a directory" if os.path.lexists(directory) else "does not exist"
        raise OutputPathError(f"{option} '{path}': output directory '{directory}' {reason}")
    # The real test of writability (permissions, read-only file system): open
    # the file as the command will, without truncating anything.
    try:
        fd = os.open(path, os.O_WRONLY) if exists else os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
    except OSError as e:
        raise OutputPathError(f"{option} '{path}' cannot be written: {e.strerror}") from None
    os.close(fd)
    if not exists:
        os.unlink(path)


def check_outputs(files: Mapping[str, PathLike | None] | None = None, *,
                  directories: Mapping[str, PathLike | None] | None = None,
                  inputs: Iterable[PathLike] = (), overwrite: bool = False,
                  overwrite_flag: str = "--overwrite") -> None:
    """Check every output of a command before it runs.

    files / directories: {option name as the user wrote it: path}; None or
    empty values (options not given) are skipped.  inputs: the files the
    command reads.  Raises OutputPathError for the first refused output."""
    outputs = [(str(o), os.fspath(p), False) for o, p in (files or {}).items() if p is not None and os.fspath(p)]
    outputs += [(str(o), os.fspath(p), True) for o, p in (directories or {}).items()
                if p is not None and os.fspath(p)]
    inputs = [os.fspath(p) for p in inputs]
    seen: list[tuple[str, str]] = []
    for option, path, is_directory in outputs:
        for source in inputs:
            if _same_file(path, source) or os.path.abspath(path) == os.path.abspath(source):
                raise OutputPathError(f"{option} '{path}' is the input '{source}': refusing to write over an "
                                      f"input (even with {overwrite_flag})")
        for other_option, other in seen:
            if os.path.abspath(path) == os.path.abspath(other) or _same_file(path, other):
                raise OutputPathError(f"{option} '{path}' and {other_option} '{other}' are the same file: "
                                      "give each output its own path")
        seen.append((option, path))
        if is_directory:
            if os.path.lexists(path) and not os.path.isdir(path):
                raise OutputPathError(f"{option} '{path}' exists and is not a directory: expected a directory "
                                      "for the files it writes")
        else:
            _check_file(option, path, overwrite, overwrite_flag)
