"""Lowering, part 3: which ROS 2 interface files a definition becomes (messages, services, actions)."""

from __future__ import annotations

from ...model import nodes as m
from ...model.naming import ros_type_name
from ..text import doc_lines
from .fields import FieldLowering
from .package import RosInterface


class DefinitionLowering(FieldLowering):
    """Messages, services (flat, sectioned or Thrift functions) and actions."""

    def interfaces_of(self, d: m.Definition, owner: m.Interface) -> list[RosInterface]:
        """The ROS interfaces a definition becomes (none for enums, typedefs and constants)."""
        src = owner.source
        doc = doc_lines(getattr(d, "doc", None))
        if isinstance(d, m.Struct):
            if d.kind in ("message", "struct", "exception"):
                name = self.type_name(d)
                sec = self.section("message", d.fields, d.consts, owner)
                return [] if name is None else [RosInterface("msg", name, [sec], doc, src, d.name_span)]
            if d.kind == "union":
                self.error("ros2-unsupported", f"union '{d.name}' has no ROS 2 equivalent (a message holds all "
                           "its fields): use a message with a kind field", src, d.name_span)
            return []
        if isinstance(d, m.Senum):
            self.error("ros2-unsupported", f"senum '{d.name}' has no ROS 2 equivalent: use an enum or string "
                       "constants", src, d.name_span)
            return []
        if isinstance(d, m.Service):
            return self.service(d, owner, doc)
        if isinstance(d, m.Action):
            name = self.type_name(d)
            extra = list(d.consts)
            secs = []
            for part, part_sec in (("goal", d.goal), ("result", d.result), ("feedback", d.feedback)):
                fields = part_sec.fields if part_sec else []
                consts = (part_sec.consts if part_sec else []) + (extra if part == "goal" else [])
                secs.append(self.section(part, fields, consts, owner, part_sec.doc if part_sec else None))
            return [] if name is None else [RosInterface("action", name, secs, doc, src, d.name_span)]
        return []

    def service(self, d: m.Service, owner: m.Interface, doc: list[str]) -> list[RosInterface]:
        src = owner.source
        if d.form != "functions":
            name = self.type_name(d)
            req = self.section("request", d.request.fields if d.request else [],
                               (d.request.consts if d.request else []) + list(d.consts), owner,
                               d.request.doc if d.request else None)
            res = self.section("response", d.response.fields if d.response else [],
                               d.response.consts if d.response else [], owner,
                               d.response.doc if d.response else None)
            return [] if name is None else [RosInterface("srv", name, [req, res], doc, src, d.name_span)]
        out = []
        base = self.type_name(d)
        for fn in d.functions:
            fname = ros_type_name(fn.name)
            if fname is None:
                self.error("ros-name-invalid", f"function name '{fn.name}' cannot be part of a ROS 2 type name",
                           src, fn.name_span)
                continue
            if fn.throws:
                self.error("ros2-unsupported", f"'{d.name}.{fn.name}' throws exceptions, which ROS 2 services "
                           "cannot: return an error field in the response instead", src, fn.throws[0].span)
            req = self.section("request", fn.params, [], owner)
            result: list[m.Field] = []
            if fn.returns is not None:
                result = [m.Field("result", fn.returns, fn.returns.span, fn.returns.span)]
            res = self.section("response", result, [], owner)
            if base is not None:
                comments = doc_lines(fn.doc) or doc
                out.append(RosInterface("srv", base + fname, [req, res], comments, src, fn.name_span))
        if d.consts and out:
            out[0].sections[0].consts.extend(c for c in (self.const(c, owner) for c in d.consts) if c)
        return out
