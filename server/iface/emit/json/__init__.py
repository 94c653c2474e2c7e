"""The ``json`` target: the JSON form of the whole interface (see ``iface.forms.jsonform``).

JSON needs no templates: the form is a dict built in a fixed order and written
with ``json.dumps(indent=2, ensure_ascii=False)``, so the same input gives the
same bytes. ``iface-lsp schema`` prints the JSON Schema every output validates
against; ``iface-lsp import --from json`` reads an output back into ``.iface``.

May import: what ``emit`` may (``model``, ``syntax``, ``semantics``, ``text``, ``forms``) and the shared
modules of ``emit``.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ...forms.jsonform import to_json
from ...semantics.compile import Compilation
from ..base import GENERATED_MARK, GeneratedFile, Result, Target

#: The key that carries the "generated — do not edit" header (JSON has no comments).
HEADER_KEY = "generated"


def render(comp: Compilation) -> str:
    """The JSON text of one compiled file, with the generated header as its first key."""
    name = Path(comp.path).name
    doc = {HEADER_KEY: f"{GENERATED_MARK} from {name} — do not edit", **to_json(comp.interface)}
    return json.dumps(doc, sort_keys=False, indent=2, ensure_ascii=False) + "\n"


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """One file, ``<stem>.json``."""
    return Result([GeneratedFile(f"{Path(comp.path).stem}.json", render(comp))], [])


TARGET = Target(
    name="json",
    description="the JSON form of the whole interface: the seven sets, types, fields, defaults, docs",
    generate=generate,
)
