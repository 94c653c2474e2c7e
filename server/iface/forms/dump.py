"""The model as plain data: every node with its kind, fields and source range (for goldens)."""

from __future__ import annotations

import dataclasses
import functools
import os
from typing import Any

from ..model import nodes as m
from ..model.source import Source, Span

_SKIP = {"target", "name_span", "id_span", "path_span", "topic_span"}


def dump_interface(iface: m.Interface) -> dict[str, Any]:
    """A deterministic, JSON-ready picture of an interface and its seven sets."""
    src = iface.source
    return {
        "name": iface.name,
        "version": iface.version,
        "items": [_node(i, src) for i in iface.items],
        "sets": {
            "subscribed": [_endpoint(e) for e in iface.subscribed],
            "published": [_endpoint(e) for e in iface.published],
            "services": [_endpoint(e) for e in iface.services],
            "actions": [_endpoint(e) for e in iface.actions],
            "parameters": [f.name for f in iface.parameters],
            "state": [f.name for f in iface.state],
            "diagnostics": [_endpoint(e) for e in iface.diagnostics_endpoints],
        },
        "contract": {
            "assumptions": [_label(x) for x in iface.assumptions],
            "guarantees": [_label(x) for x in iface.guarantees],
        },
    }


def _label(x: object) -> str:
    if isinstance(x, m.Endpoint):
        return f"{x.role} {x.definition.name if x.definition else '?'} {x.name}"
    return f"{type(x).__name__.lower()} {getattr(x, 'name', '?')}"


def _endpoint(e: m.Endpoint) -> dict[str, Any]:
    return {"role": e.role, "name": e.name, "type": e.definition.name if e.definition else None}


def _range(span: Span, src: Source) -> str:
    l1, c1 = src.position(span.start)
    l2, c2 = src.position(span.end)
    return f"{l1 + 1}:{c1 + 1}-{l2 + 1}:{c2 + 1}"


@functools.cache
def _written(cls: type) -> tuple[str, ...]:
    """The fields of a node class the dump writes: not skipped, not derived (computed from the rest)."""
    return tuple(f.name for f in dataclasses.fields(cls) if f.name not in _SKIP and not f.metadata.get("derived"))


def _node(node: Any, src: Source) -> Any:
    if isinstance(node, Span):
        return _range(node, src)
    if isinstance(node, list):
        return [_node(x, src) for x in node]
    if isinstance(node, tuple):
        return [_node(x, src) for x in node]
    if not dataclasses.is_dataclass(node):
        return node
    cls: type = type(node)
    out: dict[str, Any] = {"node": cls.__name__}
    for name in _written(cls):
        value = getattr(node, name)
        if isinstance(node, m.Include) and name == "resolved" and value:
            value = os.path.relpath(value, os.path.dirname(src.path))  # stable wherever the tree lives
        if value is None or value == [] or value == () or value is False or (name == "implicit" and not value):
            continue
        out[name] = _node(value, src)
    kind = getattr(type(node), "kind", None)
    if isinstance(kind, str):  # a kind every node of the class has is kept on the class, not on each node
        out["kind"] = kind
    if isinstance(node, m.NamedType):
        if node.target is not None:
            out["resolves_to"] = f"{node.target.kind} {node.target.name}"
        elif node.external:
            out["resolves_to"] = f"external {node.external}"
    return out
