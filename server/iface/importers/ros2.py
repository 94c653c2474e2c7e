"""Import ROS 2 packages: ``msg/``, ``srv/``, ``action/`` (and ``.idl``) → one ``.iface`` per package.

Each package becomes ``<package>.iface`` with ``namespace ros2 <package>``; a
type of another imported package is reached through ``include
"<other>.iface"``, a type of a package that was not given through ``external
<other>`` (and a note says so). ROS 2 lets a message and a service (or an
action) share a name, which one ``.iface`` file cannot: the later kind then
goes to a companion file ``<package>_srv.iface`` (or ``_action``) in the same
``ros2`` namespace, which includes the package file.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..emit.base import GeneratedFile
from ..model import nodes as m
from ..model.normalize import normalize_action, normalize_service
from ..model.source import Span
from ..text.printer import PrintError, print_items
from . import Importer, ImportResult, InputError, Origin, Problem, Severity
from .rosidl import (
    Kind,
    RosFile,
    RosSyntaxError,
    RosType,
    clean_comments,
    is_package_name,
    parse_file,
)
from .rosmodel import (
    BINARY_FILE,
    PRIMITIVES,
    Spans,
    members,
    not_imported,
    not_imported_type,
    nul_line,
    uses,
)

KINDS: tuple[Kind, ...] = ("msg", "srv", "action")
IDL_FOLDERS = ("msg", "srv", "action", "idl")


@dataclass(slots=True)
class Package:
    """One ROS 2 package given on the command line."""

    name: str
    folder: Path
    files: list[tuple[Kind, Path]] = field(default_factory=list)
    idl: list[Path] = field(default_factory=list)
    parsed: list[tuple[Path, RosFile]] = field(default_factory=list)


def package_name(folder: Path) -> str:
    """The name in ``package.xml``, else the folder name."""
    xml = folder / "package.xml"
    if xml.is_file():
        try:
            node = ET.parse(xml).getroot().find("name")
        except (ET.ParseError, OSError):
            node = None
        if node is not None and node.text and node.text.strip():
            return node.text.strip()
    return folder.resolve().name


def package_metadata(folder: Path) -> dict[str, str]:
    """version, description, license, maintainer and maintainer_email from ``package.xml``."""
    xml = folder / "package.xml"
    try:
        root = ET.parse(xml).getroot() if xml.is_file() else None
    except (ET.ParseError, OSError):
        root = None
    if root is None:
        return {}
    out: dict[str, str] = {}
    for key in ("version", "description", "license"):
        node = root.find(key)
        if node is not None and node.text and " ".join(node.text.split()):
            out[key] = " ".join(node.text.split())
    maintainer = root.find("maintainer")
    if maintainer is not None:
        if maintainer.text and maintainer.text.strip():
            out["maintainer"] = " ".join(maintainer.text.split())
        if maintainer.get("email"):
            out["maintainer_email"] = maintainer.get("email", "").strip()
    return out


def find_packages(inputs: list[str], problems: list[Problem]) -> list[Package]:
    """The packages named on the command line, each once; folders without interfaces get a warning.

    An input may be one ``.msg``/``.srv``/``.action``/``.idl`` file: its package is the folder above
    its ``msg/``, ``srv/``, ``action/`` or ``idl/`` folder (else its own folder), named by its
    ``package.xml`` or that folder's name; only the files given are imported.
    """
    out: dict[Path, Package] = {}
    whole: set[Path] = set()
    for raw in inputs:
        path = Path(raw)
        if path.is_file() and path.suffix[1:] in IDL_FOLDERS:
            folder = path.parent.parent if path.parent.name in IDL_FOLDERS else path.parent
            key = folder.resolve()
            pkg = out.setdefault(key, Package(package_name(folder), folder))
            if key in whole:
                continue
            kind = path.suffix[1:]
            if kind == "idl":
                if path not in pkg.idl:
                    pkg.idl.append(path)
            elif (kind, path) not in pkg.files:
                pkg.files.append((kind, path))  # type: ignore[arg-type]
            continue
        if not path.is_dir():
            raise InputError(f"{raw}: not a folder or a .msg, .srv, .action or .idl file (give ROS 2 package "
                             "folders or interface files)")
        key = path.resolve()
        if key in whole:
            continue
        whole.add(key)
        pkg = Package(package_name(path), path)
        for kind in KINDS:
            sub = path / kind
            if sub.is_dir():
                pkg.files.extend((kind, p) for p in sorted(sub.glob(f"*.{kind}")) if p.is_file())
        for idl_dir in IDL_FOLDERS:
            if (path / idl_dir).is_dir():
                pkg.idl.extend(p for p in sorted((path / idl_dir).glob("*.idl")) if p.is_file())
        if not pkg.files and not pkg.idl:
            problems.append(Problem(str(path), 0, "no msg/, srv/ or action/ interface files: not imported",
                                    "warning"))
            out.pop(key, None)
            continue
        out[key] = pkg
    names: dict[str, Package] = {}
    for pkg in out.values():
        if pkg.name in names:
            raise InputError(f"{pkg.folder}: the package '{pkg.name}' is also given as {names[pkg.name].folder}")
        names[pkg.name] = pkg
    return list(out.values())


def _read(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError as e:
        raise InputError(f"{path}: byte {e.start} is not UTF-8") from None
    except OSError as e:
        raise InputError(f"{path}: {e.strerror}") from None


class _PackageImport:
    """Builds the ``.iface`` file(s) of one package."""

    def __init__(self, pkg: Package, known: dict[str, dict[str, Kind]], result: ImportResult,
                 edges: dict[str, set[str]], externals_seen: set[str], broken: dict[tuple[str, str], Path]) -> None:
        self.pkg = pkg
        self.known = known
        #: the messages of the imported packages that are not imported, by (package, name): their files
        self.broken = broken
        self.result = result
        self.edges = edges
        self.externals_seen = externals_seen
        self.spans = Spans()

    def problem(self, path: Path, line: int, message: str, severity: Severity = "error") -> None:
        self.result.problems.append(Problem(str(path), line, message, severity))

    def reachable(self, start: str, goal: str) -> bool:
        stack, seen = [start], set()
        while stack:
            x = stack.pop()
            if x == goal:
                return True
            if x not in seen:
                seen.add(x)
                stack.extend(self.edges.get(x, ()))
        return False

    def name_of(self, t: RosType, path: Path, line: int, local_prefix: str, uses: dict[str, str]) -> str:
        """The .iface name of a message type, recording the include or external it needs."""
        pkg = self.pkg.name
        other = t.package or pkg
        if other == pkg:
            if self.known[pkg].get(t.name) != "msg":
                raise RosSyntaxError(self.unknown(pkg, t.name))
            return f"{local_prefix}{t.name}" if local_prefix else t.name
        if other in self.known:
            if self.known[other].get(t.name) != "msg":
                raise RosSyntaxError(self.unknown(other, t.name))
            if uses.get(other) == "include" or (other not in uses and not self.reachable(other, pkg)):
                uses[other] = "include"
                self.edges.setdefault(pkg, set()).add(other)
                return f"{other}.{t.name}"
            if other not in uses:
                self.problem(path, line, f"'{other}' uses '{pkg}' too: its types are kept as `external {other}` "
                             "so that the files do not include each other", "note")
        uses[other] = "external"
        if other not in self.externals_seen and other not in self.known:
            self.externals_seen.add(other)
            self.problem(path, line, f"'{other}/{t.name}' is from the package '{other}', which was not imported: "
                         f"kept as an external reference (`external {other}`); to import it too, give its "
                         "folder as well or `--deps DIR` with a folder that holds it", "note")
        return f"{other}.{t.name}"

    def unknown(self, pkg: str, name: str) -> str:
        """Why the message ``name`` of the imported package ``pkg`` cannot be used."""
        shown = name if pkg == self.pkg.name else f"{pkg}/{name}"
        path = self.broken.get((pkg, name))
        if path is not None:
            return not_imported_type(shown, path)
        return f"unknown type '{shown}': the package '{pkg}' has no msg/{name}.msg"

    def definition(self, path: Path, rf: RosFile, local_prefix: str, uses: dict[str, str]) -> m.Definition | None:
        """The model definition of one parsed file, or None when a line of it is wrong."""
        problems: list[tuple[int, str]] = []
        parts = []
        for i, part in enumerate(rf.parts):
            def name_of(t: RosType, _part: Any = part) -> str:
                line = next((e.line for e in _part.elements if e.type is t), 0)
                return self.name_of(t, path, line, local_prefix, uses)
            fields, consts = members(part, name_of, self.spans, problems=problems)
            parts.append((fields, consts))
        for line, message in problems:
            self.problem(path, line, message)
        if problems:
            return None
        doc = clean_comments(rf.parts[0].comments)
        span = self.spans()
        if rf.kind == "msg":
            fields, consts = parts[0]
            return m.Struct("message", rf.name, span, span, fields, consts, [], doc)
        names = ("request", "response") if rf.kind == "srv" else ("goal", "result", "feedback")
        sections = [m.Section(n, self.spans(), Span(0, 0), f, c, False,
                              clean_comments(part.comments) if i > 0 else None)
                    for i, (n, (f, c), part) in enumerate(zip(names, parts, rf.parts))]
        if rf.kind == "srv":
            svc = m.Service(rf.name, span, span, sections=sections, doc=doc)
            normalize_service(svc)
            return svc
        act = m.Action(rf.name, span, span, sections=sections, doc=doc)
        normalize_action(act)
        return act

    def run(self) -> None:
        pkg = self.pkg
        files: dict[str, list[tuple[Path, m.Definition]]] = {"": []}
        uses: dict[str, dict[str, str]] = {"": {}}
        placed: dict[str, str] = {}
        for path, rf in pkg.parsed:
            first = placed.setdefault(rf.name, rf.kind)
            suffix = "" if first == rf.kind else f"_{rf.kind}"
            files.setdefault(suffix, [])
            uses.setdefault(suffix, {})
            prefix = f"{pkg.name}." if suffix else ""
            d = self.definition(path, rf, prefix, uses[suffix])
            if d is not None:
                files[suffix].append((path, d))
        for suffix, defs in files.items():
            if not defs and suffix:
                continue
            self.write(suffix, defs, uses[suffix])

    def write(self, suffix: str, defs: list[tuple[Path, m.Definition]], uses: dict[str, str]) -> None:
        pkg = self.pkg.name
        out = f"{pkg}{suffix}.iface"
        items: list[m.Item] = []
        meta = package_metadata(self.pkg.folder)
        # a declared component that wires nothing: an interface package, whose messages, services and
        # actions are types (it provides nothing); with package.xml's metadata, which the ros2 target
        # writes back (the companion file repeats it, so both generate the same package.xml)
        annotations = [m.Annotation(k, m.Value("string", meta[k], self.spans(), ""), self.spans())
                       for k in ("description", "maintainer", "maintainer_email", "license") if k in meta]
        items.append(m.ComponentDecl(pkg, self.spans(), Span(0, 0), meta.get("version"), annotations))
        items.append(m.Namespace("ros2", pkg, self.spans()))
        if suffix:
            items.append(m.Include(f"{pkg}.iface", self.spans(), Span(0, 0)))
        for other in sorted(uses):
            if uses[other] == "include":
                items.append(m.Include(f"{other}.iface", self.spans(), Span(0, 0)))
        items.extend(m.External(o, self.spans()) for o in sorted(uses) if uses[o] == "external")
        order = {k: i for i, k in enumerate(KINDS)}
        defs = sorted(defs, key=lambda x: (order[_kind(x[1])], x[1].name))
        items.extend(d for _, d in defs)
        header = f"ROS 2 package {pkg}, imported by iface-lsp import --from ros2."
        try:
            text = print_items(items, header)
        except PrintError as e:
            self.problem(self.pkg.folder, 0, str(e))
            return
        self.result.files.append(GeneratedFile(out, text))
        for path, d in defs:
            self.result.origins.append(Origin(str(path), out, d.name, _kind(d)))


def _kind(d: m.Definition) -> Kind:
    return "srv" if isinstance(d, m.Service) else "action" if isinstance(d, m.Action) else "msg"


def _idl_files(pkg: Package, result: ImportResult) -> None:
    """Read .idl files through rosbags' IDL parser (fields and constants) and their ``@default`` values (comments
    are not read).

    Each .idl file is a source of the import, so that a round trip counts it whether it imports or not.
    """
    result.sources.extend(str(p) for p in pkg.idl)
    try:
        import rosbags.typesys  # noqa: F401
    except ImportError:
        for p in pkg.idl:
            result.problems.append(Problem(str(p), 0, "reading .idl files needs the rosbags package "
                                           "(pip install rosbags): not imported", "warning"))
        return
    from .idl import line_of, read_idl, ros_files_from_idl

    for p in pkg.idl:
        text = _read(p)
        nul = nul_line(text)
        if nul is not None:
            result.problems.append(Problem(str(p), nul, BINARY_FILE))
            continue
        try:
            types = read_idl(text)
        except InputError:
            raise
        except Exception as e:  # rosbags raises its own error types for bad IDL
            result.problems.append(Problem(str(p), 0, f"cannot read the IDL file: {e}"))
            continue
        files, problems = ros_files_from_idl(types, pkg.name, text)
        result.problems.extend(Problem(str(p), line_of(text, msg), msg) for msg in problems)
        pkg.parsed.extend((p, rf) for rf in files)


def run(inputs: list[str], options: dict[str, Any]) -> ImportResult:
    """Import every package given; problems are reported per line, the other files still import.

    ``options["deps"]``: a folder searched (recursively) for the packages the inputs use; each one
    found is imported too, into its own ``.iface`` that the users include, and so on for its own
    dependencies.
    """
    deps = options.get("deps")
    if not deps:
        return _run_once(inputs)
    found = dependency_folders(Path(deps))
    given = list(inputs)
    while True:
        result = _run_once(given)
        extra = [str(found[name]) for name in result.missing if name in found and str(found[name]) not in given]
        if not extra:
            return result
        given += extra


def dependency_folders(root: Path) -> dict[str, Path]:
    """ROS 2 package folders under ``root`` by package name (the first found by sorted path wins)."""
    if not root.is_dir():
        raise InputError(f"{root}: --deps needs a folder of ROS 2 packages")
    out: dict[str, Path] = {}
    for xml in sorted(root.rglob("package.xml")):
        out.setdefault(package_name(xml.parent), xml.parent)
    return out


def _known(packages: list[Package], broken: dict[tuple[str, str], Path]) -> dict[str, dict[str, Kind]]:
    """The kind of each name the packages define, but the ``broken`` messages (a service or action of the
    same name stays)."""
    known: dict[str, dict[str, Kind]] = {}
    for pkg in packages:
        names = known.setdefault(pkg.name, {})
        for _, rf in pkg.parsed:
            if rf.kind != "msg":
                names.setdefault(rf.name, rf.kind)
            elif (pkg.name, rf.name) not in broken:
                names[rf.name] = "msg"  # a type reference always means the message
    return known


def _broken(packages: list[Package], known: dict[str, dict[str, Kind]],
            unread: dict[tuple[str, str], Path]) -> dict[tuple[str, str], Path]:
    """Every message that is not imported, by (package, name): its file. One is not when its file has an error
    (``unread``), a value of it is one its type cannot hold, or it uses a message of an imported package that
    is not imported (``not_imported``)."""
    files = dict(unread)
    broken = list(unread)
    users: dict[tuple[str, str], list[tuple[str, str]]] = {}
    for pkg in packages:
        for path, rf in pkg.parsed:
            if rf.kind != "msg":
                continue
            key = (pkg.name, rf.name)
            files[key] = path
            used, wrong = uses(rf.parts)
            for t in used:
                ref = (t.package or pkg.name, t.name)
                if ref[0] not in known:
                    continue  # an external package
                wrong = wrong or known[ref[0]].get(ref[1]) != "msg"
                users.setdefault(ref, []).append(key)
            if wrong:
                broken.append(key)
    return {key: files[key] for key in sorted(not_imported(broken, users))}


def _run_once(inputs: list[str]) -> ImportResult:
    result = ImportResult()
    packages = []
    unread: dict[tuple[str, str], Path] = {}
    for pkg in find_packages(inputs, result.problems):
        if not is_package_name(pkg.name):
            result.problems.append(Problem(str(pkg.folder), 0, f"'{pkg.name}' is not a valid ROS 2 package name"))
            continue
        packages.append(pkg)
        for kind, path in pkg.files:
            result.sources.append(str(path))
            text = _read(path)
            nul = nul_line(text)
            rf = parse_file(kind, pkg.name, path.stem, text) if nul is None else \
                RosFile(kind, pkg.name, path.stem, problems=[(nul, BINARY_FILE)])
            for line, message in rf.problems:
                result.problems.append(Problem(str(path), line, message))
            if not rf.problems:
                pkg.parsed.append((path, rf))
            elif kind == "msg":
                unread[pkg.name, path.stem] = path
        _idl_files(pkg, result)
    broken = _broken(packages, _known(packages, {}), unread)
    known = _known(packages, broken)
    edges: dict[str, set[str]] = {}
    externals: set[str] = set()
    for pkg in sorted(packages, key=lambda p: p.name):
        if pkg.parsed:
            _PackageImport(pkg, known, result, edges, externals, broken).run()
    result.files.sort(key=lambda f: f.path)
    result.problems.sort(key=lambda p: (p.path, p.line))
    result.missing = sorted(externals)
    return result


IMPORTER = Importer(
    name="ros2",
    description="ROS 2 packages (msg/, srv/, action/, .idl) → one .iface per package",
    run=run,
)

__all__ = ["IMPORTER", "PRIMITIVES", "run"]
