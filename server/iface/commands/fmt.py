"""``iface-lsp fmt FILE... [--check] [--diff] [-q]``: format files in place, or check that they are.

Each file rewritten is named on stderr (``formatted PATH``); ``-q`` silences that.

Exit codes: 0 done (or, with ``--check``, nothing to change); 1 with ``--check``
when a file would change; 2 on usage or I/O errors (nothing is written for
a file that cannot be read). ``-`` formats stdin to stdout.
"""

from __future__ import annotations

import argparse
import difflib
import os
import sys
import tempfile
from dataclasses import dataclass

from ..model.source import Source
from ..semantics.compile import MAX_FILE_BYTES, SUFFIXES
from ..text.formatter import Formatted, format_document
from .common import UsageError, check_suffix, display_path
from .terminal import write_verbatim

STDIN = "-"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("files", nargs="+", metavar="FILE",
                   help=f"{' or '.join(SUFFIXES)} files to format; '-' formats stdin to stdout")
    p.add_argument("--check", action="store_true",
                   help="write nothing; print 'PATH: would reformat' and exit 1 if any file would change")
    p.add_argument("--diff", action="store_true",
                   help="write nothing; print a unified diff of the changes")
    p.add_argument("--indent", type=int, default=4, metavar="N",
                   help="spaces per indentation level (default 4)")
    p.add_argument("-q", "--quiet", action="store_true", help="do not name the files rewritten")


@dataclass(slots=True)
class _Input:
    path: str
    text: str


def run(args: argparse.Namespace) -> int:
    """Format or check every file; see the module docstring for the exit codes."""
    try:
        _check_arguments(args)
    except UsageError as e:
        print(f"iface-lsp fmt: {e}", file=sys.stderr)
        return 2
    status = 0
    for path in args.files:
        try:
            src = _read(path)
            result = format_document(src.text, args.indent)
            _report(src, result)
            changed = result.text != src.text
            if args.diff and changed:
                _print_diff(src, result.text)
            if args.check:
                if changed:
                    print(f"{_shown(path)}: would reformat")
                    status = max(status, 1)
            elif path == STDIN:
                if not args.diff:
                    write_verbatim(result.text)
            elif changed and not args.diff:
                _write_atomically(path, result.text)
                if not args.quiet:
                    print(f"formatted {_shown(path)}", file=sys.stderr)
        except UsageError as e:
            print(f"iface-lsp fmt: {e}", file=sys.stderr)
            status = 2
    return status


def _check_arguments(args: argparse.Namespace) -> None:
    if not 1 <= args.indent <= 16:
        raise UsageError(f"--indent must be between 1 and 16, not {args.indent}")
    if args.files.count(STDIN) > 1:
        raise UsageError("'-' (stdin) can be given only once")
    for path in args.files:
        if path == STDIN:
            continue
        check_suffix(path)
        if not os.path.isfile(path):
            raise UsageError(f"{path}: no such file")


def _shown(path: str) -> str:
    return path if path == STDIN else display_path(path)


def _read(path: str) -> _Input:
    """The text of a file (or stdin), as UTF-8; anything else is a UsageError."""
    try:
        data = sys.stdin.buffer.read() if path == STDIN else _read_bytes(path)
    except OSError as e:
        raise UsageError(f"{path}: cannot read the file ({e.strerror or e})") from None
    if len(data) > MAX_FILE_BYTES:
        raise UsageError(f"{_shown(path)}: the file is larger than {MAX_FILE_BYTES // (1024 * 1024)} MB; "
                         "iface reads interface files up to that size")
    if b"\0" in data:
        raise UsageError(f"{_shown(path)}: the file holds NUL bytes: it is binary, not an interface file")
    try:
        return _Input(path, data.decode("utf-8"))
    except UnicodeDecodeError as e:
        text = data[:e.start].decode("utf-8")
        line, col = Source(path, text).position(len(text))
        raise UsageError(f"{_shown(path)}:{line + 1}:{col + 1}: byte 0x{data[e.start]:02x} is not valid UTF-8 "
                         "(iface files are UTF-8); the file was not changed") from None


def _read_bytes(path: str) -> bytes:
    with open(path, "rb") as f:
        return f.read()


def _report(src: _Input, result: Formatted) -> None:
    """Say on stderr which parts were left as written, and why."""
    source = Source(src.path, src.text)
    shown = _shown(src.path)
    for r in result.broken:
        line, col = source.position(r.content_start)
        print(f"{shown}:{line + 1}:{col + 1}: note[fmt-syntax-error]: this definition has syntax errors and "
              "was left as written (see 'iface-lsp check')", file=sys.stderr)
    for r in result.unsafe:
        line, col = source.position(r.content_start)
        print(f"{shown}:{line + 1}:{col + 1}: warning[fmt-self-check]: left as written because the formatter "
              f"could not vouch for its output ({r.unsafe}); please report this", file=sys.stderr)


def _print_diff(src: _Input, new: str) -> None:
    name = _shown(src.path)
    diff = difflib.unified_diff(src.text.splitlines(keepends=True), new.splitlines(keepends=True),
                                f"{name} (original)", f"{name} (formatted)")
    for line in diff:
        write_verbatim(line if line.endswith("\n") else line + "\n\\ No newline at end of file\n")


def _write_atomically(path: str, text: str) -> None:
    """Replace the file's content in one step: a temporary file beside it, then os.replace.

    A symbolic link is followed, so the link stays and its target is replaced.
    """
    from ..emit.write import signals_deferred  # only when writing: emit loads jinja2

    path = os.path.realpath(path)
    folder = os.path.dirname(path)
    with signals_deferred():  # Ctrl-C or SIGTERM lands after the file is replaced (or left as it was)
        try:
            mode = os.stat(path).st_mode & 0o7777
            fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{os.path.basename(path)}.", suffix=".tmp")
        except OSError as e:
            raise UsageError(f"{path}: cannot write beside the file ({e.strerror or e})") from None
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(text.encode("utf-8"))
                f.flush()
                os.fsync(f.fileno())
            os.chmod(tmp, mode)
            os.replace(tmp, path)
        except BaseException as e:  # no temporary file is left behind
            try:
                os.unlink(tmp)
            except OSError:
                pass
            if isinstance(e, OSError):
                raise UsageError(f"{path}: cannot write the file ({e.strerror or e})") from None
            raise
