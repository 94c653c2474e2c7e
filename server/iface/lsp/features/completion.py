"""Completion from the text around the cursor and the names of the last compile.

Runs on the event loop without waiting for a compile: the context comes from
``context.context_at`` and the names from the latest compiled version (immutable).
"""

from __future__ import annotations

from functools import cache
from typing import TYPE_CHECKING

from lsprotocol import types as lsp

from .. import convert
from ..context import Context, context_at

if TYPE_CHECKING:
    from ..server import IfaceServer
    from ..versions import Name, CompiledVersion

MAX_ITEMS = 100

KEYWORDS = ("include", "namespace", "component", "external", "const", "typedef", "enum", "struct", "union",
            "exception", "message", "configuration", "state", "service", "action", "publishes", "subscribes",
            "provides", "calls", "system", "instance")

#: Block snippets: label → (snippet body, plain text for clients without snippets, description)
SNIPPETS: dict[str, tuple[str, str, str]] = {
    "message": ("message ${1:Name} {\n    ${2:float64} ${3:value}$0\n}", "message ", "a message (wire it with publishes/subscribes)"),
    "struct": ("struct ${1:Name} {\n    $0\n}", "struct ", "a struct"),
    "enum": ("enum ${1:Name} {\n    ${2:FIRST} = 0,\n    $0\n}", "enum ", "an enum"),
    "service": ("service ${1:Name} {\n    request {\n        $2\n    }\n    response {\n        $0\n    }\n}",
                "service ", "a service with request and response"),
    "action": ("action ${1:Name} {\n    goal {\n        $2\n    }\n    result {\n        $3\n    }\n"
               "    feedback {\n        $0\n    }\n}", "action ", "an action with goal, result and feedback"),
    "configuration": ("configuration ${1:Params} {\n    ${2:float64} ${3:max_speed} = ${4:1.0} (unit = \"${5:m/s}\")$0\n}",
                      "configuration ", "the component's parameters (P)"),
    "state": ("state ${1:State} {\n    $0\n}", "state ", "the component's state (Σ)"),
    "component": ("component ${1:name} version \"${2:0.1.0}\"", "component ", "the component's name and version"),
    "publishes": ("publishes ${1:Type} on \"${2:/topic}\"", "publishes ", "publish a message on a topic (N)"),
    "subscribes": ("subscribes ${1:Type} on \"${2:/topic}\"", "subscribes ", "subscribe to a topic (M)"),
    "provides": ("provides ${1:Service} on \"${2:/name}\"", "provides ", "provide a service or action"),
    "calls": ("calls ${1:Service} on \"${2:/name}\"", "calls ", "call a service or action"),
    "include": ("include \"${1:file}.iface\"", "include ", "include another interface file"),
    "namespace": ("namespace ${1:ros2} ${2:package}", "namespace ", "the package name for a target"),
    "typedef": ("typedef ${1:float64} ${2:Name}", "typedef ", "a type alias"),
    "const": ("const ${1:i32} ${2:NAME} = ${3:0}", "const ", "a constant"),
    "system": ("system ${1:name} version \"${2:0.1.0}\"", "system ", "a system of component instances"),
    "instance": ("instance ${1:name} : ${2:component}", "instance ", "an instance of an included component"),
}

#: Container types offered beside the base types.
CONTAINERS = ("list", "set", "map")
TYPE_KINDS = frozenset({"struct", "message", "union", "exception", "enum", "senum", "typedef", "configuration",
                        "state"})
SECTIONS = {"service": ("request", "response"), "action": ("goal", "result", "feedback")}
NAMESPACE_SCOPES = ("ros2", "px4", "cpp", "py", "java", "*")
QOS_KEYS = ("qos.depth", "qos.reliability", "qos.durability", "qos.history", "qos.deadline", "qos.lifespan",
            "qos.liveliness", "rate")
FIELD_KEYS = ("unit", "range", "min", "max", "deprecated")
DEFINITION_KEYS = ("diagnostics", "role", "deprecated")


@cache
def base_types() -> tuple[str, ...]:
    """Every spelling of a base type the language knows (``BASE_ALIASES``), then the containers."""
    from ...model.nodes import BASE_ALIASES

    return (*BASE_ALIASES, *CONTAINERS)


def register(server: IfaceServer) -> None:
    """Register the completion handler."""
    project = server.project

    @server.feature(lsp.TEXT_DOCUMENT_COMPLETION,
                    lsp.CompletionOptions(trigger_characters=[".", '"', "("]))
    def completion(ls: IfaceServer, params: lsp.CompletionParams) -> lsp.CompletionList | None:
        doc = project.docs.get(params.text_document.uri)
        if doc is None:
            return None
        state = doc.state
        offset = state.index.offset(params.position.line, params.position.character)
        ctx = context_at(state.text, offset)
        ver = project.compiled.get(doc.uri)
        names = ver.names if ver is not None else ()
        topics = _topics(project, ver) if ctx.where == "topic" else []  # every wiring: only where wanted
        caps = ls.client_capabilities.text_document
        item_caps = caps.completion.completion_item if caps and caps.completion else None
        snippets = bool(item_caps and item_caps.snippet_support)
        markdown = bool(item_caps and item_caps.documentation_format
                        and lsp.MarkupKind.Markdown in item_caps.documentation_format)
        items = Items(ctx, state.index, offset, snippets, markdown)
        if ctx.where.startswith("instance-"):
            offer_system(ctx, ver.system_names if ver is not None else (), items)
        else:
            offer(ctx, names, topics, items, sorted_types(ver) if ver is not None else None)
        built, incomplete = items.build(MAX_ITEMS)
        return convert.completion_list(built, incomplete=incomplete)


def _topics(project: object, ver: object) -> list[tuple[str, str, str]]:
    found: dict[tuple[str, str, str], None] = {}
    index = getattr(project, "workspace_index", None)
    if index is not None:
        for t in index.topics():
            found.setdefault(t)
    for topic, type_name in getattr(ver, "topics", ()):
        found.setdefault((topic, type_name, ""))
    return list(found)


class Items:
    """Completion candidates being collected, filtered by the typed prefix; LSP items only for the best."""

    def __init__(self, ctx: Context, index: convert.LineIndex, offset: int, snippets: bool, markdown: bool) -> None:
        self.ctx = ctx
        self.index = index
        self.offset = offset
        self.snippets = snippets
        self.markdown = markdown
        # (sort key, label, kind, detail, doc, insert text, snippet, replace from)
        self.candidates: list[tuple[str, str, str, str, str, str | None, bool, int | None]] = []
        self.seen: set[str] = set()
        self.prefix = ctx.prefix.lower()

    def fits(self, label: str) -> bool:
        """True when ``label`` fits the typed prefix."""
        return not self.prefix or self.prefix in label.lower()

    def add(self, label: str, kind: str, detail: str = "", doc: str = "", insert: str | None = None,
            snippet: bool = False, sort: str = "5", replace_from: int | None = None) -> None:
        """One candidate, if its label fits the prefix and it is new."""
        if label in self.seen:
            return
        if self.prefix and self.prefix not in label.lower():
            return
        self.seen.add(label)
        self.candidates.append((f"{sort}{label}", label, kind, detail, doc if self.markdown else "",
                                insert, snippet and self.snippets, replace_from))

    def build(self, limit: int) -> tuple[list[lsp.CompletionItem], bool]:
        """LSP items for the ``limit`` best candidates, and whether some were left out."""
        best = sorted(self.candidates)[:limit]
        items = []
        for sort, label, kind, detail, doc, insert, snippet, replace_from in best:
            edit = (self.index, replace_from, self.offset) if replace_from is not None else None
            items.append(convert.completion_item(label, kind, detail, doc, insert, snippet, sort, edit))
        return items, len(self.candidates) > limit


def sorted_types(ver: CompiledVersion) -> tuple[tuple[Name, ...], tuple[Name, ...]]:
    """The type names of a compiled version sorted by name: local ones, then included ones (built once per compiled version)."""
    if ver.sorted_types is None:
        types = sorted((n for n in ver.names if n.kind in TYPE_KINDS), key=lambda n: n.name)
        ver.sorted_types = (tuple(n for n in types if "." not in n.name), tuple(n for n in types if "." in n.name))
    return ver.sorted_types


def offer(ctx: Context, names: tuple[Name, ...], topics: list[tuple[str, str, str]], items: Items,
          types: tuple[tuple[Name, ...], tuple[Name, ...]] | None = None) -> None:
    """Fill ``items`` with what fits ``ctx``; ``types`` are the type names sorted (see ``sorted_types``)."""
    where = ctx.where
    if where == "top":
        for kw in KEYWORDS:
            if kw in SNIPPETS and items.snippets:
                body, _, desc = SNIPPETS[kw]
                items.add(kw, "snippet", desc, insert=body, snippet=True, sort="1")
            else:
                items.add(kw, "keyword", SNIPPETS.get(kw, ("", "", ""))[2], insert=kw + " ", sort="1")
    elif where in ("type", "member"):
        if where == "member":
            if ctx.body in SECTIONS:
                for sec in SECTIONS[ctx.body]:
                    insert = f"{sec} {{\n    $0\n}}" if items.snippets else sec
                    items.add(sec, "section", f"the {sec} of the {ctx.body}", insert=insert,
                              snippet=items.snippets, sort="1")
            for kw in ("const", "required", "optional"):
                items.add(kw, "keyword", insert=kw + " ", sort="2")
        _types(names, items, types)
    elif where == "wiring-type":
        wanted = {"publishes": ("message", "struct"), "subscribes": ("message", "struct"),
                  "provides": ("service", "action"), "calls": ("service", "action"), "extends": ("service",)}
        kinds = wanted.get(ctx.direction or "", ())
        for n in names:
            if n.kind in kinds:
                items.add(n.name, n.kind, n.kind, n.doc, sort="1")
    elif where == "wiring-on":
        items.add("on", "keyword", insert="on ", sort="1")
    elif where == "topic":
        _topic_items(ctx, topics, items)
    elif where == "annotation-key":
        keys = QOS_KEYS if ctx.direction else FIELD_KEYS + DEFINITION_KEYS
        from ..describe import ANNOTATIONS
        for key in keys:
            items.add(key, "annotation", doc=ANNOTATIONS.get(key, ""), insert=f"{key} = ", sort="1")
    elif where == "annotation-value" and ctx.wired_type:
        fields = next((n.members for n in names if n.name == ctx.wired_type), ())
        for f in fields:
            items.add(f'"{f}"', "field", f"field of {ctx.wired_type}", sort="1")
    elif where == "value":
        _values(ctx, names, items)
    elif where == "dotted":
        _dotted(ctx, names, items)
    elif where == "namespace-scope":
        for scope in NAMESPACE_SCOPES:
            items.add(scope, "keyword", "namespace scope", insert=scope + " ", sort="1")


def offer_system(ctx: Context, names: tuple[Name, ...], items: Items) -> None:
    """In a system file: the components an instance can be, its annotations, and their values."""
    from ...semantics.systems import ANNOTATIONS, BOOLEANS, RESTART, RUNTIMES

    if ctx.where == "instance-component":
        for n in names:
            if n.kind == "component":
                items.add(n.name, "component", "component", n.doc, sort="1")
    elif ctx.where == "instance-annotation-key":
        for key, meaning in ANNOTATIONS.items():
            items.add(key, "annotation", doc=meaning, insert=f"{key} = ", sort="1")
    elif ctx.where == "instance-annotation-value":
        inside = ctx.string_start is not None
        values: list[tuple[str, str]] = []
        if ctx.key == "restart":
            values = [(r, "restart policy") for r in RESTART]
        elif ctx.key == "after":
            values = [(n.name, f"instance of {n.members[0]}") for n in names if n.kind == "instance"]
        elif ctx.key == "snapshot":
            values = [("1s", "period"), ("500ms", "period")]
        elif ctx.key == "runtime":
            values = [(r, "runtime") for r in RUNTIMES]
        elif ctx.key == "intra_process":
            values = [(b, "intra-process communication") for b in BOOLEANS]
        elif ctx.key == "standby":
            values = [(b, "a spare process for a fast restart") for b in BOOLEANS]
        elif ctx.key == "container":
            values = [(n.name, f"container of {', '.join(n.members)}") for n in names if n.kind == "container"]
        items.prefix = ""  # the quote is part of the label; the client filters
        for value, detail in values:
            items.add(f'"{value}"', "value", detail, sort="1", replace_from=ctx.string_start if inside else None)


def _types(names: tuple[Name, ...], items: Items, types: tuple[tuple[Name, ...], tuple[Name, ...]] | None) -> None:
    for b in base_types():
        items.add(b, "base-type", "builtin type", sort="3")
    if types is None:
        local = tuple(n for n in names if n.kind in TYPE_KINDS and "." not in n.name)
        types = (local, tuple(n for n in names if n.kind in TYPE_KINDS and "." in n.name))
    # in name order, a group past its first MAX_ITEMS + 1 fitting names cannot reach the MAX_ITEMS best:
    # the cost of a completion does not grow with the file
    for group, sort in zip(types, ("2", "4")):
        added = 0
        for n in group:
            if n.name not in items.seen and items.fits(n.name):
                items.add(n.name, n.kind, n.kind, n.doc, sort=sort)
                added += 1
                if added > MAX_ITEMS:
                    break


def _topic_items(ctx: Context, topics: list[tuple[str, str, str]], items: Items) -> None:
    inside = ctx.string_start is not None
    start = ctx.string_start if inside else None
    for topic, type_name, direction in sorted(topics):
        fits = not ctx.wired_type or type_name == ctx.wired_type or type_name.rpartition(".")[2] == \
            ctx.wired_type.rpartition(".")[2]
        detail = f"{direction} {type_name}".strip()
        items.prefix = ""  # the quote and slashes are part of the label; the client filters
        items.add(f'"{topic}"', "topic", detail, sort="1" if fits else "3", replace_from=start)


def _values(ctx: Context, names: tuple[Name, ...], items: Items) -> None:
    vt = ctx.value_type
    target = next((n for n in names if vt and n.name == vt), None)
    if target is not None and target.kind == "enum":
        for v in target.members:
            items.add(v, "enum-value", f"{target.name} value", sort="1")
    if vt == "bool" or vt is None:
        for b in ("true", "false"):
            items.add(b, "keyword", sort="2")
    for n in names:
        if n.kind == "const":
            items.add(n.name, "const", "constant", n.doc, sort="3")


def _dotted(ctx: Context, names: tuple[Name, ...], items: Items) -> None:
    head = ctx.prefix.rpartition(".")[0]
    for n in names:
        if n.name == head:
            kind = "enum-value" if n.kind == "enum" else "field"
            for member in n.members:
                items.add(f"{head}.{member}", kind, f"member of {head}", sort="1",
                          replace_from=ctx.prefix_start)
        elif n.name.startswith(head + ".") and n.kind in TYPE_KINDS | {"service", "action", "const"}:
            items.add(n.name, n.kind, n.kind, n.doc, sort="2", replace_from=ctx.prefix_start)
