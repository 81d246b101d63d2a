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

__all__ = ["OutputPathError", "LockHeldError", "check_outputs", "one_line", "MAX_MESSAGE_CHARS"]

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


def one_line(text: object, max_chars: int = MAX_MESSAGE_CHARS) -> str:
    """str(text) (or bytes) as one printable line of at most max_chars bytes
    (io/messages.hpp).  Bytes that are not UTF-8 (a surrogate-escaped file
    name, binary input) are shown as \\xNN."""
    raw = text if isinstance(text, bytes) else str(text).encode("utf-8", errors="surrogateescape")
    return _slipstrip.one_line(raw, int(max_chars))
