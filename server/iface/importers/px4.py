"""Import PX4 uORB ``.msg`` files: one ``.iface`` file for a message folder.

The uORB format is ROS 1's ``.msg`` format as PX4 uses it (read by
``genmsg``): ``TYPE NAME`` fields without defaults, ``TYPE NAME = VALUE``
constants (``ORB_QUEUE_LENGTH`` and ``MESSAGE_VERSION`` among them), fixed
arrays, nested message types, ``#`` comments, and ``# TOPICS a b`` lines naming
the topics that carry the message (several lines add up). Each message becomes
a ``message`` whose topics are the annotation ``px4.topics``; comments become
docs as for ROS 2 (leading lines: the message, lines before and after a
member: that member).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from ..emit.base import GeneratedFile
from ..model import nodes as m
from ..text.printer import PrintError, print_items, quote
from . import Importer, ImportResult, InputError, Origin, Problem
from .rosidl import (
    Element,
    Part,
    RosSyntaxError,
    RosType,
    clean_comments,
    parse_primitive,
    parse_type,
)
from .rosmodel import BINARY_FILE, Spans, members, not_imported, not_imported_type, nul_line, uses

TOPICS = "# TOPICS "
UORB_TYPES = frozenset({"bool", "char", "byte", "int8", "uint8", "int16", "uint16", "int32", "uint32",
                        "int64", "uint64", "float32", "float64"})
PX4_PACKAGES = ("px4", "px4_msgs")
_IDENTIFIER = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def topics_of(text: str) -> list[str]:
    """The topics of a message file, as PX4's generator reads ``# TOPICS`` lines (none: the default topic)."""
    out: list[str] = []
    for line in text.split("\n"):
        if line.startswith(TOPICS):
            out.extend(t for t in line.strip().replace(TOPICS.strip(), "", 1).split(" ") if t)
    return out


def parse_message(name: str, text: str) -> tuple[Part, list[tuple[int, str]]]:
    """One uORB message: its members with their comments, and the malformed lines."""
    problems: list[tuple[int, str]] = []
    part = Part(name, 1)
    lines = text.replace("\t", " ").splitlines()
    head = 0
    while head < len(lines) and lines[head].startswith("#"):
        if not lines[head].startswith(TOPICS):
            part.comments.append(lines[head].lstrip("#"))
        head += 1
    pending: list[str] = []
    last: Element | None = None
    seen: dict[str, int] = {}
    for number, raw in enumerate(lines[head:], start=head + 1):
        if raw.startswith(TOPICS):
            continue
        code, hash_at, after = raw.partition("#")
        comment = after.lstrip("#") if hash_at else None
        if not code.strip():
            if comment is not None:
                if code and last is not None:
                    last.comments.append(comment)
                else:
                    pending.append(comment)
            continue
        if comment is not None:
            pending.append(comment)
        try:
            element = _element(code.strip(), number)
        except RosSyntaxError as e:
            problems.append((number, str(e)))
            pending = []
            continue
        if element.name in seen:
            problems.append((number, f"'{element.name}' is already declared on line {seen[element.name]}"))
            pending = []
            continue
        seen[element.name] = number
        element.comments, pending = pending, []
        part.elements.append(element)
        last = element
    return part, problems


def _element(code: str, number: int) -> Element:
    if "=" in code:
        left, _, value = code.partition("=")
        words = left.split()
        if len(words) != 2:
            raise RosSyntaxError(f"'{code}' is not a constant: write TYPE NAME = VALUE")
        t = _type(words[0])
        if t.array is not None or not t.primitive:
            raise RosSyntaxError(f"the constant '{words[1]}' must have a single numeric or bool type")
        value = value.strip()
        return Element("constant", t, words[1], number, parse_primitive(t, value), [value])
    words = code.split()
    if len(words) != 2:
        raise RosSyntaxError(f"'{code}' is not a field: write TYPE NAME (uORB fields have no defaults)")
    if not _IDENTIFIER.match(words[1]):
        raise RosSyntaxError(f"'{words[1]}' is not a valid field name")
    return Element("field", _type(words[0]), words[1], number)


def _type(text: str) -> RosType:
    t = parse_type(text)
    if t.primitive and t.name not in UORB_TYPES:
        raise RosSyntaxError(f"uORB has no {t.name} type: use a fixed char[N] array")
    if t.array in ("bounded", "unbounded"):
        raise RosSyntaxError(f"'{text}' has a variable length: uORB arrays have a fixed size (T[N])")
    return t


def output_name(folder: Path) -> str:
    """The .iface file stem: the folder's name when it names something, else ``px4_msgs``."""
    name = folder.resolve().name
    return name if _IDENTIFIER.match(name) and name not in ("msg", "msgs") else "px4_msgs"


def import_folder(folder: Path, result: ImportResult) -> None:
    """Every ``.msg`` file under ``folder`` into ``<name>.iface``."""
    paths = sorted(p for p in folder.rglob("*.msg") if p.is_file())
    if not paths:
        result.problems.append(Problem(str(folder), 0, "no .msg files: nothing imported", "warning"))
        return
    parsed: list[tuple[Path, Part, str]] = []
    unread: dict[str, Path] = {}
    for path in paths:
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as e:
            raise InputError(f"{path}: cannot read the file ({e})") from None
        result.sources.append(str(path))
        nul = nul_line(text)
        part, problems = parse_message(path.stem, text) if nul is None else (Part(path.stem, 0), [(nul, BINARY_FILE)])
        if not _IDENTIFIER.match(path.stem):
            problems.insert(0, (0, f"'{path.stem}' cannot name a message"))
        for line, message in problems:
            result.problems.append(Problem(str(path), line, message))
        if not problems:
            parsed.append((path, part, text))
        else:
            unread[path.stem] = path
    broken = _broken(parsed, unread)
    names = {part.name for _, part, _ in parsed} - set(broken)
    spans = Spans()
    externals: set[str] = set()
    defs: list[tuple[Path, m.Struct]] = []
    for path, part, text in parsed:
        member_problems: list[tuple[int, str]] = []

        def name_of(t: RosType, _path: Path = path) -> str:
            if t.package is None or t.package in PX4_PACKAGES:
                if t.name in names:
                    return t.name
                if t.name in broken:
                    raise RosSyntaxError(not_imported_type(t.name, broken[t.name]))
                if t.package is None:
                    raise RosSyntaxError(f"unknown type '{t.name}': there is no {t.name}.msg in {folder}")
            package = t.package or "px4_msgs"
            if package not in externals:
                externals.add(package)
                result.problems.append(Problem(str(_path), 0, f"'{t.text()}' is not in {folder}: kept as an "
                                               f"external reference (`external {package}`)", "note"))
            return f"{package}.{t.name}"

        fields, consts = members(part, name_of, spans, problems=member_problems)
        for line, message in member_problems:
            result.problems.append(Problem(str(path), line, message))
        if member_problems:
            continue
        topics = topics_of(text)
        annotations = [m.Annotation("px4.topics", m.Value("string", " ".join(topics), spans(),
                                                          quote(" ".join(topics))), spans())] if topics else []
        span = spans()
        defs.append((path, m.Struct("message", part.name, span, span, fields, consts, annotations,
                                    clean_comments(part.comments))))
    stem = output_name(folder)
    # a declared component that wires nothing: a package of message types, not a module
    span = spans()
    items: list[m.Item] = [m.ComponentDecl(stem, span, span)]
    items.extend(m.External(e, spans()) for e in sorted(externals))
    items.extend(d for _, d in sorted(defs, key=lambda x: x[1].name))
    try:
        text = print_items(items, "PX4 uORB messages, imported by iface-lsp import --from px4.")
    except PrintError as e:
        result.problems.append(Problem(str(folder), 0, str(e)))
        return
    out = f"{stem}.iface"
    result.files.append(GeneratedFile(out, text))
    result.origins.extend(Origin(str(path), out, d.name, "msg") for path, d in defs)


def _broken(parsed: list[tuple[Path, Part, str]], unread: dict[str, Path]) -> dict[str, Path]:
    """Every message of the folder that is not imported, by name: its file. One is not when its file has an
    error (``unread``), a value of it is one its type cannot hold, or it uses a message of the folder that is
    not imported (``not_imported``)."""
    files = dict(unread)
    broken = list(unread)
    names = {part.name for _, part, _ in parsed}
    users: dict[str, list[str]] = {}
    for path, part, _ in parsed:
        files[part.name] = path
        used, wrong = uses([part])
        for t in used:
            if t.package is None or (t.package in PX4_PACKAGES and t.name in names):
                wrong = wrong or t.name not in names
                users.setdefault(t.name, []).append(part.name)
        if wrong:
            broken.append(part.name)
    return {name: files[name] for name in sorted(not_imported(broken, users))}


def run(inputs: list[str], options: dict[str, Any]) -> ImportResult:
    """Import each message folder given."""
    result = ImportResult()
    for raw in inputs:
        folder = Path(raw)
        if not folder.is_dir():
            raise InputError(f"{raw}: not a folder (give the folder of the uORB .msg files)")
        import_folder(folder, result)
    stems = [f.path for f in result.files]
    if len(stems) != len(set(stems)):
        raise InputError("two message folders would be written to the same .iface file: import them one by one")
    result.problems.sort(key=lambda p: (p.path, p.line))
    return result


IMPORTER = Importer(name="px4", description="PX4 uORB .msg files → one .iface file", run=run)
