"""Writing imported ``.iface`` files through the shared writer, without a "generated" stamp.

Imported files are the user's to edit, so they carry no stamp; an existing file
with other content is therefore refused unless ``force``.
"""

from __future__ import annotations

from pathlib import Path

from ..emit.base import GeneratedFile
from ..emit.write import WriteReport, write_files


def write_imported(files: list[GeneratedFile], out_dir: str | Path, *, force: bool = False) -> WriteReport:
    """Write ``files`` under ``out_dir``; every path is checked before anything is written."""
    return write_files(files, out_dir, force=force, stamped=False)
