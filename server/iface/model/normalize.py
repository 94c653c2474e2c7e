"""Read service and action bodies into their parts (request/response, goal/result/feedback).

Flat bodies (the paper's Listing 1) are read by position:
- a flat ``service`` body: every field but the last is the request, the last is the response;
- a flat diagnostics service (Δ) reads the other way, as the paper's Listing 1 writes it
  (``service diagnostics { string result, i32 r, string cmd }``): the last field is the
  request, the command the caller sends; the fields before it are the response it gets back;
- a flat ``action`` body: the last field is the result, the one before it the
  feedback, all earlier ones the goal (with two fields: goal and result).
The explicit forms ``request {…} response {…}`` and ``goal {…} result {…} feedback {…}``
say it directly, and are what tools write.
"""

from __future__ import annotations

from . import nodes as m
from .source import AnchoredSpan, Span

SERVICE_PARTS = ("request", "response")
ACTION_PARTS = ("goal", "result", "feedback")


def _implicit(name: str, fields: list[m.Field], at: Span) -> m.Section:
    """A section read from a flat body; its spans move with the chunk the body is in."""
    near = fields[0].span if fields else at
    if fields:
        start, end = fields[0].span.start, fields[-1].span.end
    else:
        start, end = at.start, at.end
    if isinstance(near, AnchoredSpan):
        return m.Section(name, AnchoredSpan(start, end, near.anchor), AnchoredSpan(start, start, near.anchor),
                         list(fields), [], True)
    return m.Section(name, Span(start, end), Span(start, start), list(fields), [], True)


def normalize_service(svc: m.Service) -> None:
    """Fill ``form``, ``request`` and ``response`` from what the body holds."""
    svc.request = svc.response = None
    if svc.functions:
        svc.form = "functions"
        return
    if svc.sections:
        svc.form = "explicit"
        for sec in svc.sections:
            if sec.name == "request" and svc.request is None:
                svc.request = sec
            elif sec.name == "response" and svc.response is None:
                svc.response = sec
        return
    fields = svc.flat_fields
    svc.form = "flat" if fields else "empty"
    if svc.is_diagnostics:
        svc.response = _implicit("response", fields[:-1], svc.name_span)
        svc.request = _implicit("request", fields[-1:], svc.name_span)
    else:
        svc.request = _implicit("request", fields[:-1], svc.name_span)
        svc.response = _implicit("response", fields[-1:], svc.name_span)


def flat_order(defn: m.Service | m.Action) -> tuple[str, ...]:
    """The parts of a flat body in the order their fields are written."""
    if isinstance(defn, m.Service):
        return ("response", "request") if defn.is_diagnostics else SERVICE_PARTS
    return ("goal", "feedback", "result")


def normalize_action(act: m.Action) -> None:
    """Fill ``form``, ``goal``, ``result`` and ``feedback`` from what the body holds."""
    act.goal = act.result = act.feedback = None
    if act.sections:
        act.form = "explicit"
        for sec in act.sections:
            if sec.name in ACTION_PARTS and getattr(act, sec.name) is None:
                setattr(act, sec.name, sec)
        return
    f = act.flat_fields
    act.form = "flat" if f else "empty"
    if len(f) >= 3:
        goal, feedback, result = f[:-2], f[-2:-1], f[-1:]
    elif len(f) == 2:
        goal, feedback, result = f[:1], [], f[1:]
    else:
        goal, feedback, result = f, [], []
    act.goal = _implicit("goal", goal, act.name_span)
    act.result = _implicit("result", result, act.name_span)
    act.feedback = _implicit("feedback", feedback, act.name_span)


def flat_reading(defn: m.Service | m.Action) -> str:
    """How a flat body is read, in words (used by diagnostics and hover)."""
    def names(sec: m.Section | None) -> str:
        return ", ".join(f.name for f in sec.fields) if sec and sec.fields else "nothing"

    if isinstance(defn, m.Service):
        if defn.is_diagnostics:
            return (f"a diagnostics service, last field first: request (what the caller sends): "
                    f"{names(defn.request)}; response (what it gets back): {names(defn.response)}")
        return f"request: {names(defn.request)}; response: {names(defn.response)}"
    return f"goal: {names(defn.goal)}; result: {names(defn.result)}; feedback: {names(defn.feedback)}"


def explicit_text(defn: m.Service | m.Action, text: str, indent: str = "    ") -> str:
    """The body of a flat service or action, from its source ``text``, in the explicit form."""
    source = defn.flat_fields
    parts = SERVICE_PARTS if isinstance(defn, m.Service) else ACTION_PARTS
    lines: list[str] = []
    for part in parts:
        sec: m.Section | None = getattr(defn, part)
        members = [f for f in (sec.fields if sec else []) if f in source]
        if not members:
            lines.append(f"{indent}{part} {{}}")
            continue
        lines.append(f"{indent}{part} {{")
        lines.extend(f"{indent}{indent}{text[f.span.start:f.span.end]}" for f in members)
        lines.append(f"{indent}}}")
    return "\n".join(lines)
