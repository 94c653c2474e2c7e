"""Code actions: quick fixes keyed on diagnostic codes, refactorings at the cursor, and source actions.

Quick fixes read what the diagnostic's ``data`` carries (suggestions, the
replacement name, the missing parts, a compatibility fix), so they need no
second analysis. Source actions run the server's commands (generate, preview,
export JSON). The fixes of ROS habits are in ``ros_habits``, the package
metadata fix in ``package_metadata``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from lsprotocol import types as lsp

from .. import convert
from ..versions import DocumentView
from . import package_metadata, ros_habits

if TYPE_CHECKING:
    from ...model import nodes as m
    from ..server import IfaceServer

QUICKFIX = lsp.CodeActionKind.QuickFix.value
REWRITE = lsp.CodeActionKind.RefactorRewrite.value
SOURCE_GENERATE = "source.iface.generate"
SOURCE_PREVIEW = "source.iface.preview"
SOURCE_EXPORT = "source.iface.exportJson"
#: The target that writes a runnable component package (the node and its user module) beside the interface package.
COMPONENT_TARGET = "rclpy"
KINDS = [QUICKFIX, REWRITE, lsp.CodeActionKind.Source.value, SOURCE_GENERATE, SOURCE_PREVIEW, SOURCE_EXPORT]

ZERO = {"bool": "false", "string": '""', "wstring": '""', "binary": '""', "float32": "0.0", "float64": "0.0"}


class Fixes:
    """Code actions for one request, built over one view."""

    def __init__(self, view: DocumentView, params: lsp.CodeActionParams) -> None:
        self.view = view
        self.params = params
        self.out: list[lsp.CodeAction] = []

    # ---- edits -------------------------------------------------------------------
    def edit(self, start: int, end: int, new_text: str) -> lsp.WorkspaceEdit | None:
        """One edit of the compiled version text, placed in the current text."""
        placed = self.view.place(start, end)
        if placed is None:
            return None
        return convert.workspace_edit({self.view.uri: [convert.text_edit(self.view.index, *placed, new_text)]})

    def add(self, title: str, kind: str, edit: lsp.WorkspaceEdit | None, diag: lsp.Diagnostic | None = None,
            preferred: bool = False) -> None:
        """Offer an action that applies ``edit`` (nothing when the edit cannot be placed)."""
        if edit is not None:
            self.out.append(convert.code_action(title, kind, edit, None, [diag] if diag else None, preferred))

    # ---- diagnostics ------------------------------------------------------------------
    def for_diagnostic(self, diag: lsp.Diagnostic) -> None:
        """Quick fixes for one diagnostic the client sent back."""
        code = str(diag.code or "")
        data: dict[str, Any] = diag.data if isinstance(diag.data, dict) else {}
        view = self.view
        start = view.offset(diag.range.start.line, diag.range.start.character)
        end = view.offset(diag.range.end.line, diag.range.end.character)
        if start is None or end is None:
            return
        if code == "unknown-type":
            for s in data.get("suggestions", []):
                self.add(f"Change to '{s}'", QUICKFIX, self.edit(start, end, s), diag, preferred=True)
            name = data.get("name")
            if isinstance(name, str) and "." not in name:
                for kind in ("message", "struct"):
                    self.add(f"Create {kind} '{name}'", QUICKFIX, self._create(start, kind, name), diag)
        elif code == "ros-naming" and isinstance(data.get("replacement"), str):
            self._rename_to(diag, start, data["replacement"])
        elif code == "message-no-direction" and isinstance(data.get("name"), str):
            self._wire(diag, data["name"])
        elif code in ("flat-service", "flat-action"):
            self._explicit(diag, start)
        elif code == "service-part-missing" and isinstance(data.get("missing"), list):
            self._missing_parts(diag, start, [str(p) for p in data["missing"]])
        elif code == "missing-default":
            self._default(diag, start)
        elif code == "px4-timestamp-added":
            self._timestamp(start, diag)
        elif code == "ros2-package-metadata-missing" and isinstance(data.get("missing"), list):
            package_metadata.add_metadata(self, diag, [str(x) for x in data["missing"]])
        elif code == "ros-constant-as-field" and isinstance(data.get("replacement"), str):
            ros_habits.constant(self, diag, data)
        elif code == "syntax-error" and isinstance(data.get("package"), str) and isinstance(
                data.get("replacement"), str):
            ros_habits.ros_type(self, diag, start, end, data["package"], data["replacement"])
        elif code.startswith("compat-") and isinstance(data.get("fix"), dict):
            self._compat_fix(diag, data["fix"])

    def _definition_at(self, offset: int) -> m.Definition | None:
        from ...model import nodes as m
        from ...semantics.query import item_at

        iface = self.view.iface
        item = item_at(iface, offset) if iface is not None else None
        return item if isinstance(item, (m.Struct, m.Service, m.Action, m.Enum, m.Senum, m.Typedef, m.Const)) \
            else None

    def _create(self, offset: int, kind: str, name: str) -> lsp.WorkspaceEdit | None:
        from ...semantics.query import item_at

        iface = self.view.iface
        item = item_at(iface, offset) if iface is not None else None
        at = item.span.end if item is not None else len(self.view.ver.text)
        stub = f"\n\n{kind} {name} {{\n}}"
        if item is None or at >= len(self.view.ver.text.rstrip()):
            stub = stub + "\n" if not self.view.ver.text.endswith("\n") else stub.lstrip("\n") + "\n"
            at = len(self.view.ver.text)
        return self.edit(at, at, stub)

    def _rename_to(self, diag: lsp.Diagnostic, offset: int, new: str) -> None:
        from ...semantics.query import locate, references

        iface = self.view.iface
        if iface is None:
            return
        hit = locate(iface, offset)
        if hit is None:
            return
        title = f"Rename to '{new}' (the target's naming rule)"
        if hit.kind == "definition":
            changes: dict[str, list[lsp.TextEdit]] = {}
            from .navigation import workspace_interfaces
            for r in references(hit.target, iface, workspace_interfaces(self.view)):
                loc = self.view.location(r.interface.source, r.span)
                if loc is not None:
                    changes.setdefault(loc.uri, []).append(lsp.TextEdit(range=loc.range, new_text=new))
            self.add(title, QUICKFIX, convert.workspace_edit(changes) if changes else None, diag, preferred=True)
        else:
            self.add(title, QUICKFIX, self.edit(hit.span.start, hit.span.end, new), diag, preferred=True)

    def _wire(self, diag: lsp.Diagnostic, name: str) -> None:
        from ...model.naming import ros_field_name

        iface = self.view.iface
        if iface is None:
            return
        topic = "/" + (ros_field_name(name) or name.lower())
        text = self.view.ver.text
        if iface.wirings:
            at = iface.wirings[-1].span.end
            prefix, suffix = "\n", ""
        else:
            at = len(text)
            prefix, suffix = ("" if text.endswith("\n") else "\n") + "\n", "\n"
        for direction in ("publishes", "subscribes"):
            self.add(f"Add `{direction} {name} on \"{topic}\"`", QUICKFIX,
                     self.edit(at, at, f'{prefix}{direction} {name} on "{topic}"{suffix}'), diag)

    def _body(self, d: m.Definition) -> tuple[int, int] | None:
        """Offsets of the braces of a definition's body."""
        text = self.view.ver.text
        open_ = text.find("{", d.name_span.end, d.span.end)
        close = text.rfind("}", d.name_span.end, d.span.end)
        return (open_, close) if 0 <= open_ < close else None

    def _explicit(self, diag: lsp.Diagnostic, offset: int) -> None:
        from ...model import nodes as m
        from ...model.normalize import explicit_text

        d = self._definition_at(offset)
        if not isinstance(d, (m.Service, m.Action)) or d.form != "flat":
            return
        body = self._body(d)
        if body is None:
            return
        explicit = explicit_text(d, self.view.ver.text)
        self.add(f"Write {d.kind} '{d.name}' with explicit parts", QUICKFIX,
                 self.edit(body[0], body[1] + 1, "{\n" + explicit + "\n}"), diag, preferred=True)

    def _missing_parts(self, diag: lsp.Diagnostic, offset: int, missing: list[str]) -> None:
        d = self._definition_at(offset)
        body = self._body(d) if d is not None else None
        if d is None or body is None:
            return
        text = self.view.ver.text
        close = body[1]
        line_start = text.rfind("\n", 0, close) + 1
        before = text[line_start:close]
        lead = "" if before.strip() == "" else "\n"
        parts = "".join(f"    {p} {{}}\n" for p in missing)
        at = line_start if before.strip() == "" else close
        self.add(f"Add {' and '.join(missing)} to '{d.name}'", QUICKFIX, self.edit(at, at, lead + parts), diag,
                 preferred=True)

    def _default(self, diag: lsp.Diagnostic, offset: int) -> None:
        from ...model import nodes as m
        from ...semantics.query import locate

        iface = self.view.iface
        hit = locate(iface, offset) if iface is not None else None
        f = hit.target if hit is not None else None
        if not isinstance(f, m.Field) or f.default is not None:
            return
        value = _zero(f)
        if value is not None:
            at = f.name_span.end
            self.add(f"Add the default `{value}` to '{f.name}'", QUICKFIX, self.edit(at, at, f" = {value}"), diag,
                     preferred=True)

    def _timestamp(self, offset: int, diag: lsp.Diagnostic | None) -> None:
        from ...model import nodes as m

        d = self._definition_at(offset)
        if not isinstance(d, m.Struct) or any(f.name == "timestamp" for f in d.fields):
            return
        body = self._body(d)
        if body is None:
            return
        text = self.view.ver.text
        at = text.find("\n", body[0]) + 1 if "\n" in text[body[0]:body[1]] else body[0] + 1
        insert = "    uint64 timestamp  # time since system start (microseconds)\n" if at > body[0] + 1 \
            else " uint64 timestamp "
        self.add(f"Add `uint64 timestamp` to '{d.name}' (PX4)", QUICKFIX if diag else REWRITE,
                 self.edit(at, at, insert), diag)

    def multi(self, title: str, changes: list[tuple[int, int, str]], diag: lsp.Diagnostic,
              preferred: bool = False) -> None:
        """An action of several edits of this document (nothing when one cannot be placed)."""
        edits: list[lsp.TextEdit] = []
        for start, end, text in changes:
            placed = self.view.place(start, end)
            if placed is None:
                return
            edits.append(convert.text_edit(self.view.index, *placed, text))
        self.add(title, QUICKFIX, convert.workspace_edit({self.view.uri: edits}), diag, preferred)

    def _compat_fix(self, diag: lsp.Diagnostic, fix: dict[str, Any]) -> None:
        edits = fix.get("edits")
        if not isinstance(edits, list):
            return
        out: list[lsp.TextEdit] = []
        for e in edits:
            if not isinstance(e, dict):
                return
            placed = self.view.place(int(e.get("start", 0)), int(e.get("end", 0)))
            if placed is None:
                return
            out.append(convert.text_edit(self.view.index, *placed, str(e.get("text", ""))))
        title = {"add-default": "Add a default value (compatibility)", "make-optional": "Make the field optional",
                 "restore": "Restore what the baseline had"}.get(str(fix.get("kind")), "Apply the compatibility fix")
        self.add(title, QUICKFIX, convert.workspace_edit({self.view.uri: out}) if out else None, diag, preferred=True)

    # ---- at the cursor -------------------------------------------------------------------
    def at_cursor(self) -> None:
        """Refactorings offered where the cursor is, without a diagnostic (PX4's timestamp)."""
        from ...model import nodes as m

        view = self.view
        iface = view.iface
        start = view.offset(self.params.range.start.line, self.params.range.start.character)
        if iface is None or start is None:
            return
        d = self._definition_at(start)
        if isinstance(d, m.Struct) and iface.namespace("px4") and d.kind in ("message", "struct"):
            self._timestamp(start, None)

    def source_actions(self, targets: list[str], defaults: tuple[str, ...]) -> None:
        """Generate for each target, preview, export JSON."""
        uri = self.view.uri
        iface = self.view.iface
        if COMPONENT_TARGET in targets and iface is not None and iface.component is not None:
            self.out.append(convert.code_action(
                "Generate component package…", SOURCE_GENERATE,
                cmd=convert.command("Generate component package", "iface.generate", [uri, COMPONENT_TARGET])))
        ordered = [t for t in defaults if t in targets] + [t for t in targets if t not in defaults]
        for t in ordered:
            self.out.append(convert.code_action(f"Generate for {t}", SOURCE_GENERATE,
                                                cmd=convert.command(f"Generate for {t}", "iface.generate", [uri, t])))
        for t in ordered[:3] if not defaults else [t for t in ordered if t in defaults]:
            self.out.append(convert.code_action(f"Preview generated files ({t})", SOURCE_PREVIEW,
                                                cmd=convert.command("Preview generated files", "iface.preview", [uri, t])))
        self.out.append(convert.code_action("Export JSON", SOURCE_EXPORT,
                                            cmd=convert.command("Export JSON", "iface.exportJson", [uri])))


def _zero(f: m.Field) -> str | None:
    """A default that fits the field's type (and its range's lower end)."""
    from ...model import nodes as m
    from ...model.walk import resolve_typedefs

    t = resolve_typedefs(f.type)
    rng = f.range
    if isinstance(t, m.BaseType):
        if t.name in m.INT_RANGES:
            lo = rng[0] if rng and rng[0] is not None else 0
            return str(int(lo))
        if t.name in ZERO:
            if t.name in m.FLOAT_TYPES and rng and rng[0] is not None:
                return str(float(rng[0]))
            return ZERO[t.name]
        return None
    if isinstance(t, m.NamedType) and isinstance(t.target, m.Enum) and t.target.values:
        return t.target.values[0].name
    if isinstance(t, m.ArrayType):
        return "[]"
    return None


def _kind(kind: object) -> str:
    """A code action kind as its plain string."""
    return str(getattr(kind, "value", kind))


def _wants(only: list[str] | None, kind: str) -> bool:
    return not only or any(kind == k or kind.startswith(k + ".") for k in only)


def register(server: IfaceServer) -> None:
    """Register the code action handler."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_CODE_ACTION, lsp.CodeActionOptions(code_action_kinds=KINDS))
    async def code_actions(ls: IfaceServer, params: lsp.CodeActionParams) -> list[lsp.CodeAction] | None:
        only = [_kind(k) for k in params.context.only] if params.context.only else None
        targets: list[str] = []
        sources = not only or any(k == "source" or k.startswith("source.") for k in only)
        if sources:
            from .commands import available_targets
            targets = available_targets()

        def answer(view: DocumentView) -> list[lsp.CodeAction] | None:
            fixes = Fixes(view, params)
            if _wants(only, QUICKFIX):
                for diag in params.context.diagnostics:
                    fixes.for_diagnostic(diag)
            if _wants(only, REWRITE):
                fixes.at_cursor()
            if sources:
                fixes.source_actions(targets, project.settings.targets)
            return [a for a in fixes.out if _wants(only, _kind(a.kind))] or None

        return await project.view(params.text_document.uri, answer, fresh=True)
