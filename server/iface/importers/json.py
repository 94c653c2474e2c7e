"""Import the JSON form the ``json`` target writes (see ``iface.jsonform``) back into ``.iface`` files.

Each JSON file becomes the ``.iface`` file it was made from (its ``file`` key),
written so that compiling it gives a model equal to the one exported.
"""

from __future__ import annotations

import json
import re
from pathlib import Path, PurePosixPath
from typing import Any

from ..emit.base import GeneratedFile
from ..forms.jsonform import FormError, from_json
from ..text.printer import PrintError
from . import Importer, ImportResult, InputError, Origin, Problem

_STEM = re.compile(r"^[A-Za-z0-9_][A-Za-z0-9_.\-]*$")


def _line_of(text: str, error: json.JSONDecodeError) -> int:
    return error.lineno if error.doc == text else 0


def import_file(path: Path, result: ImportResult) -> None:
    """One JSON form → one ``.iface`` file."""
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(f"{path}: cannot read the file ({e})") from None
    result.sources.append(str(path))
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        result.problems.append(Problem(str(path), _line_of(text, e), f"not JSON: {e.msg}"))
        return
    except (ValueError, RecursionError) as e:  # a number of 5,000 digits; arrays nested 100,000 deep
        reason = "nested too deeply" if isinstance(e, RecursionError) else str(e).split(";")[0]
        result.problems.append(Problem(str(path), 0, f"not the iface JSON form: {reason}"))
        return
    name = _file_name(doc, path)
    try:
        files = [(name, from_json(doc))] + _included_files(doc, PurePosixPath(name).parent, "")
    except (FormError, PrintError) as e:
        result.problems.append(Problem(str(path), 0, f"not the iface JSON form: {e}"))
        return
    for out, text in files:
        result.files.append(GeneratedFile(out, text))
    result.origins.append(Origin(str(path), name, str(doc.get("name", "")), "json"))


def _included_files(doc: Any, folder: PurePosixPath, where: str) -> list[tuple[str, str]]:
    """The files embedded under ``included``, each where its include statement finds it (beside its includer)."""
    out: list[tuple[str, str]] = []
    embedded = doc.get("included") if isinstance(doc, dict) else None
    if embedded is None:
        return out
    if not isinstance(embedded, list):
        raise FormError(f"{where}/included", "expected an array")
    for i, entry in enumerate(embedded):
        at = f"{where}/included/{i}"
        if not isinstance(entry, dict) or not isinstance(entry.get("path"), str):
            raise FormError(f"{at}/path", "expected a string")
        written = PurePosixPath(entry["path"])
        if written.is_absolute() or ".." in written.parts or not entry["path"].endswith((".iface", ".thrift")):
            raise FormError(f"{at}/path", f"the included file '{entry['path']}' cannot be written beside the "
                                          "file that includes it; import it on its own")
        target = folder / written
        form = entry.get("form")
        out.append((str(target), from_json(form)))
        out.extend(_included_files(form, target.parent, f"{at}/form"))
    return out


def _file_name(doc: dict[str, Any], path: Path) -> str:
    given = doc.get("file")
    if isinstance(given, str) and _STEM.match(given) and given.endswith((".iface", ".thrift")):
        return given
    return f"{path.stem}.iface"


def run(inputs: list[str], options: dict[str, Any]) -> ImportResult:
    """Import every JSON file given; two forms of one file name are refused."""
    result = ImportResult()
    for raw in inputs:
        path = Path(raw)
        if not path.is_file():
            raise InputError(f"{raw}: no such file")
        import_file(path, result)
    unique: dict[str, GeneratedFile] = {}
    for f in result.files:
        seen = unique.get(f.path)
        if seen is not None and seen.text != f.text:
            raise InputError(f"two JSON files would both be written to {f.path}, with different content")
        unique.setdefault(f.path, f)
    result.files = list(unique.values())
    return result


IMPORTER = Importer(name="json", description="the JSON form written by the json target → .iface", run=run)
