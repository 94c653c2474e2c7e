"""The CLI's side of the terminal: output that survives a closed pipe and escapes control characters; signals.

``guarded_output`` wraps stdout and stderr for the length of a command:

- a reader that goes away (``iface-lsp check bad.iface | head -c0``) does not
  change the command's exit status, and nothing is said about it: the rest
  of the output goes to ``/dev/null``;
- control characters (C0 but tab and line feed, DEL, C1, the Unicode line
  separators and bidirectional overrides) are written as ``\\uXXXX``, so a
  name or string from an input file cannot move the cursor, clear the
  screen or reorder a line. In JSON output the escape is the JSON escape of
  the same character, so JSON stays valid and means the same;
- text that cannot be encoded is written with backslash escapes, never an
  exception.

``write_verbatim`` writes file content (``fmt -``, ``fmt --diff``) without the
escaping. ``interruptible`` turns SIGTERM into ``Terminated``, an exception
that unwinds like Ctrl-C's KeyboardInterrupt, so temporary files are removed
on the way out.
"""

from __future__ import annotations

import os
import re
import signal
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, TextIO

_CONTROL = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u2028\u2029\u202a-\u202e\u2066-\u2069]")


class Terminated(BaseException):
    """SIGTERM arrived: unwind (cleaning up on the way) and exit with 143."""


def escape_controls(text: str) -> str:
    """``text`` with control characters written as ``\\uXXXX``."""
    if not _CONTROL.search(text):
        return text
    return _CONTROL.sub(lambda m: f"\\u{ord(m.group()):04x}", text)


def one_line(text: str) -> str:
    """``text`` as one line: line breaks become spaces, control characters are escaped."""
    return escape_controls(" ".join(text.split("\n")))


class _Guarded:
    """A text stream proxy: escapes control characters, swallows a broken pipe."""

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream
        self.broken = False

    def write(self, text: str) -> int:
        return self._write(escape_controls(text), len(text))

    def write_verbatim(self, text: str) -> int:
        return self._write(text, len(text))

    def _write(self, text: str, size: int) -> int:
        if not self.broken:
            try:
                self._stream.write(text)
            except BrokenPipeError:
                self._reader_gone()
        return size

    def flush(self) -> None:
        if not self.broken:
            try:
                self._stream.flush()
            except BrokenPipeError:
                self._reader_gone()

    def _reader_gone(self) -> None:
        """Send what is left (and the interpreter's last flush) to /dev/null."""
        self.broken = True
        try:
            fd = self._stream.fileno()
            devnull = os.open(os.devnull, os.O_WRONLY)
            try:
                os.dup2(devnull, fd)
            finally:
                os.close(devnull)
        except (OSError, ValueError, AttributeError):
            pass

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


@contextmanager
def guarded_output() -> Iterator[None]:
    """Guard stdout and stderr (see the module docstring) while the block runs."""
    saved = sys.stdout, sys.stderr
    for stream in saved:
        reconfigure = getattr(stream, "reconfigure", None)
        if reconfigure is not None:
            try:
                reconfigure(errors="backslashreplace")
            except (ValueError, OSError):
                pass
    out, err = _Guarded(saved[0]), _Guarded(saved[1])
    sys.stdout, sys.stderr = out, err
    try:
        yield
    finally:
        out.flush()
        err.flush()
        sys.stdout, sys.stderr = saved


def write_verbatim(text: str) -> None:
    """Write file content to stdout as it is (no escaping), still surviving a closed pipe."""
    stream = sys.stdout
    if isinstance(stream, _Guarded):
        stream.write_verbatim(text)
    else:
        stream.write(text)


def _terminate(signum: int, frame: object) -> None:
    raise Terminated()


@contextmanager
def interruptible() -> Iterator[None]:
    """While the block runs, SIGTERM raises ``Terminated`` (in the main thread; elsewhere nothing changes)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)
