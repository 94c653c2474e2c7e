"""Loading files for the compatibility commands: a file with errors cannot be compared."""

from __future__ import annotations

import sys
from collections.abc import Sequence

from ..semantics.compile import Compilation
from .common import (
    UsageError,
    check_suffix,
    compile_files,
    gather,
    has_errors,
    print_diagnostics,
)


def load_checked(paths: Sequence[str], include_paths: Sequence[str] = (), command: str = "compat") -> list[Compilation]:
    """Compile ``paths``; on unreadable files or files with errors print why and raise UsageError."""
    for p in paths:
        check_suffix(p)
    comps = compile_files(list(paths), include_paths)
    diags = [d for d in gather(comps) if d.severity.label == "error"]
    if has_errors(diags):
        print_diagnostics(diags, "text", sys.stderr)
        raise UsageError(f"{len(diags)} error{'s' if len(diags) != 1 else ''} in the input: fix "
                         f"{'it' if len(diags) == 1 else 'them'} before running {command}")
    return comps
