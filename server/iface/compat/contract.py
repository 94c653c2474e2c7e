"""The paper's contract C = (A, G): what a component assumes of its environment and what it guarantees."""

from __future__ import annotations

import json
from typing import Any

from ..model import nodes as m
from ..model.walk import type_text
from ..semantics.compile import Compilation
from .side import Side
from .values import value_text
from .parts import endpoint_qos, endpoint_type


def _endpoint(side: Side, kind: str, ep: m.Endpoint) -> dict[str, Any]:
    out: dict[str, Any] = {"kind": kind, "role": ep.role, "name": ep.name, "type": endpoint_type(side, ep)}
    qos = endpoint_qos(ep)
    if qos:
        out["qos"] = qos
    return out


def _setting(f: m.Field, what: str) -> dict[str, Any]:
    out: dict[str, Any] = {"kind": what, "name": f.name, "type": type_text(f.type)}
    if f.default is not None:
        out["default"] = value_text(f.default)
    if f.unit:
        out["unit"] = f.unit
    r = f.range
    if r is not None:
        out["range"] = [r[0], r[1]]
    return out


def contract(comp: Compilation) -> dict[str, Any]:
    """Assumptions (M, called S and A, P, Σ) and guarantees (N, provided S and A, Δ, Σ) as JSON data.

    State belongs to both sides: the component assumes its state is handed over
    and guarantees to keep it.
    """
    side = Side(comp)
    iface = side.iface
    assumptions: list[dict[str, Any]] = [_endpoint(side, "topic", e) for e in iface.subscribed]
    assumptions += [_endpoint(side, "service", e) for e in iface.services if e.role == "calls"]
    assumptions += [_endpoint(side, "action", e) for e in iface.actions if e.role == "calls"]
    assumptions += [_setting(f, "parameter") for f in iface.parameters]
    assumptions += [_setting(f, "state") for f in iface.state]
    guarantees: list[dict[str, Any]] = [_endpoint(side, "topic", e) for e in iface.published]
    guarantees += [_endpoint(side, "service", e) for e in iface.services if e.role == "provides"]
    guarantees += [_endpoint(side, "action", e) for e in iface.actions if e.role == "provides"]
    guarantees += [{"kind": "diagnostics", "name": ep.name, "type": endpoint_type(side, ep)}
                   for ep in iface.diagnostics_endpoints]
    guarantees += [_setting(f, "state") for f in iface.state]
    return {"component": iface.name, "version": iface.version, "assumptions": assumptions,
            "guarantees": guarantees}


def _line(item: dict[str, Any]) -> str:
    kind = item["kind"]
    if kind in ("topic", "service", "action"):
        qos = item.get("qos")
        extra = " (" + ", ".join(f"{k}={v}" for k, v in qos.items()) + ")" if qos else ""
        return f"  {item['role']} {item['type']} on \"{item['name']}\"{extra}"
    if kind == "diagnostics":
        return f"  diagnostics {item['type']} on \"{item['name']}\""
    parts = [f"  {kind} {item['name']}: {item['type']}"]
    if "default" in item:
        parts.append(f"= {item['default']}")
    if "unit" in item:
        parts.append(f"[{item['unit']}]")
    if "range" in item:
        lo, hi = item["range"]
        parts.append(f"in {'' if lo is None else f'{lo:g}'}..{'' if hi is None else f'{hi:g}'}")
    return " ".join(parts)


def render_contract(data: dict[str, Any], fmt: str) -> str:
    """The contract as text or JSON."""
    if fmt == "json":
        return json.dumps(data, indent=2, ensure_ascii=False) + "\n"
    version = f" {data['version']}" if data["version"] else ""
    lines = [f"contract of {data['component']}{version}: C = (A, G)", "A (assumptions):"]
    lines += [_line(i) for i in data["assumptions"]] or ["  (none)"]
    lines.append("G (guarantees):")
    lines += [_line(i) for i in data["guarantees"]] or ["  (none)"]
    return "\n".join(lines) + "\n"
