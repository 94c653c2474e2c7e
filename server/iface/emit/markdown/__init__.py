"""The markdown target: the interface as a document.

Interfaces double as documentation: a title, the description, the seven sets
as tables, the contract (assumptions and guarantees) and a table per type.
Every piece of text from the interface is escaped, so a doc comment cannot
start a heading, close a table cell or inject HTML.

May import: what ``emit`` may (``model``, ``syntax``, ``semantics``, ``text``, ``forms``) and the shared
modules of ``emit``.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from ...model import nodes as m
from ...semantics.compile import Compilation
from ..base import GeneratedFile, Result, Target, TemplateSet
from ..support import component_span
from ..text import header_name
from .build import call_rows, contract_item, endpoint_rows, fields_table, type_sections
from .escape import code, md, paragraphs

TEMPLATES = Path(__file__).parent / "templates"
FILTERS: dict[str, Callable[..., Any]] = {"md": md, "code": code, "paragraphs": paragraphs}


def generate(comp: Compilation, options: dict[str, Any]) -> Result:
    """One Markdown file, ``<component>.md``; the document renders any interface, so it reports nothing."""
    iface = comp.interface
    ts = TemplateSet(TEMPLATES, "markdown", filters=FILTERS, override=options.get("templates"))
    view = {
        "iface": iface,
        "doc": iface.component.doc if iface.component else None,
        "subscribed": endpoint_rows(iface.subscribed),
        "published": endpoint_rows(iface.published),
        "services": call_rows(iface.services, ("request", "response")),
        "actions": call_rows(iface.actions, ("goal", "result", "feedback")),
        "parameters": fields_table("", iface.parameters),
        "state": fields_table("", iface.state),
        "diagnostics": [row[:2] + row[3:] for row in call_rows(iface.diagnostics_endpoints, ("request", "response"))],
        "assumptions": [contract_item(x) for x in iface.assumptions],
        "guarantees": [contract_item(x) for x in iface.guarantees],
        "state_names": [f.name for f in iface.state],
        "sections": type_sections(iface),
    }
    text = ts.render("interface.md.j2", source_name=header_name(comp.path),
                     open="<!--", close=" -->", **view)
    file_name = _file_name(iface)
    return Result(files=[GeneratedFile(file_name, text, (iface.source, component_span(iface)))])


def _file_name(iface: m.Interface) -> str:
    stem = "".join(c if c.isalnum() or c in "_-" else "_" for c in iface.name).strip("._") or "interface"
    return f"{stem}.md"


TARGET = Target("markdown", "Markdown: the interface as a document (seven sets, contract, a table per type)",
                generate, str(TEMPLATES))

__all__ = ["TARGET", "generate"]
