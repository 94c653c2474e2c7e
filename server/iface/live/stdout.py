"""Native libraries' console output kept out of iface's own output.

Fast DDS writes its log (Jazzy's 2.14: errors too, such as a shared-memory port it cannot lock) to the
process's standard output, file descriptor 1: into a command's JSON (``handover``, ``system``, ``verify``)
or the language server's messages. While a command talks ROS, descriptor 1 is stderr's and Python's
``sys.stdout`` writes to the real standard output.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import BinaryIO


def _on_descriptor_1() -> bool:
    try:
        return sys.stdout.fileno() == 1
    except (AttributeError, OSError, ValueError):  # a StringIO, a closed or detached stream
        return False


@contextmanager
def native_output_to_stderr() -> Iterator[None]:
    """Inside, what native code writes to descriptor 1 goes to stderr, and ``sys.stdout`` to the real standard
    output. Nothing changes where ``sys.stdout`` is not descriptor 1 (a redirection in this process)."""
    if not _on_descriptor_1():
        yield
        return
    sys.stdout.flush()
    before = sys.stdout
    real = os.dup(1)
    os.dup2(2, 1)
    ours = open(real, "w", encoding=before.encoding, errors=before.errors,  # noqa: SIM115 - closed below
                newline=None, closefd=False, buffering=1 if before.line_buffering else -1)
    sys.stdout = ours
    try:
        yield
    finally:
        sys.stdout = before
        ours.close()  # flushed; the descriptor stays open (closefd=False)
        os.dup2(real, 1)
        os.close(real)


def real_stdout_for_good() -> BinaryIO | None:
    """For a process that talks on its standard output for good (the language server): descriptor 1 becomes
    stderr's from now on, ``sys.stdout`` is ``sys.stderr``, and the real standard output is returned (None, and
    nothing changed, where descriptor 1 or 2 is not open)."""
    try:
        real = os.dup(1)
    except OSError:
        return None
    try:
        os.dup2(2, 1)
    except OSError:
        os.close(real)
        return None
    if sys.stdout is not None:
        sys.stdout.flush()
    sys.stdout = sys.stderr
    return os.fdopen(real, "wb", buffering=0)
