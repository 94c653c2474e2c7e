"""``iface-lsp roundtrip --from ros2|px4|json INPUT... [-v]``: import, regenerate, compare, count.

Imports into a temporary folder, compiles, regenerates with the matching
target, and compares every original file with its regenerated one through the
platform's own parser (see ``iface.importers.oracle``). Prints one line per
file that differs (or could not be imported) and ``N of M identical``; exits 1
on any difference, 2 on usage or I/O errors.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ..emit import generate
from ..importers import ImportResult, InputError, Origin, get_importer
from ..importers.oracle import (
    FileView,
    OracleMissing,
    OracleRefused,
    differences,
    idl_views,
    px4_view,
    renamed,
    rihs01,
    ros_view,
    structural,
)
from ..importers.output import write_imported
from ..semantics.compile import Compilation, Workspace

FORMATS = ("ros2", "px4", "json")


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="ROS 2 package folders (ros2), a uORB .msg folder (px4), or JSON files (json)")
    p.add_argument("--from", dest="source", required=True, choices=FORMATS, help="what to round-trip")
    p.add_argument("--keep", metavar="DIR", help="write the imported and regenerated files to DIR and keep them")
    p.add_argument("-v", "--verbose", action="store_true", help="also print the identical files")


class Run:
    """One round trip: the imported files, their compilations, and the findings."""

    def __init__(self, folder: Path, verbose: bool) -> None:
        self.folder = folder
        self.verbose = verbose
        self.ws = Workspace()
        self.compiled: dict[str, Compilation] = {}
        self.generated: dict[tuple[str, str], dict[str, str]] = {}
        self.identical = 0
        self.total = 0

    def compile(self, name: str) -> Compilation:
        if name not in self.compiled:
            self.compiled[name] = self.ws.compile_path(str(self.folder / "iface" / name))
        return self.compiled[name]

    def regenerate(self, name: str, target: str) -> dict[str, str]:
        """Generated files of one imported file (path → text); errors become one report."""
        key = (name, target)
        if key not in self.generated:
            comp = self.compile(name)
            errors = [d for d in comp.all_diagnostics() if d.severity == 1]
            if errors:
                raise RegenerationFailed(f"{name} does not compile: {errors[0].format(Path(errors[0].path).name)}")
            result = generate(comp, target)
            if result.has_errors:
                first = next(d for d in result.diagnostics if d.severity == 1)
                raise RegenerationFailed(f"the {target} target refuses {name}: "
                                         f"{first.format(Path(first.path).name)}")
            self.generated[key] = {f.path: f.text for f in result.files}
            out = self.folder / target / Path(name).stem
            for path, text in self.generated[key].items():
                (out / path).parent.mkdir(parents=True, exist_ok=True)
                (out / path).write_text(text, encoding="utf-8")
        return self.generated[key]

    def report(self, source: str, problems: list[str]) -> None:
        self.total += 1
        if not problems:
            self.identical += 1
            if self.verbose:
                print(f"{source}: identical")
            return
        for p in problems:
            print(f"{source}: {p}")


class RegenerationFailed(Exception):
    """The imported file does not compile, or the target refuses it."""


# ---------------------------------------------------------------------------
# ROS 2 and PX4


def _ros2(run: Run, result: ImportResult) -> None:
    by_source: dict[str, list[Origin]] = {}
    for o in result.origins:
        by_source.setdefault(o.source, []).append(o)
    judged: dict[str, list[tuple[FileView, FileView]]] = {}
    failures: dict[str, str] = {}
    names: dict[str, str] = {}  # an .idl struct's name → the name of its regenerated part
    for source in result.sources:
        origins = by_source.get(source, [])
        try:
            if Path(source).suffix == ".idl":
                judged[source] = _ros2_idl(run, source, origins, names)
            else:
                judged[source] = [_ros2_file(run, source, origins)]
        except _Skip as e:
            failures[source] = str(e)
    originals: dict[str, Any] = {}
    regenerated: dict[str, Any] = {}
    for source, pairs in judged.items():
        if Path(source).suffix == ".idl":
            judged[source] = pairs = [(renamed(a, names), b) for a, b in pairs]
        for a, b in pairs:
            originals.update((part.name, part.descs) for part in a.parts)
            regenerated.update((part.name, part.descs) for part in b.parts)
    for source in result.sources:
        if source in failures:
            run.report(source, [failures[source]])
            continue
        problems: list[str] = []
        for a, b in judged[source]:
            problems.extend(differences(a, b))
            for pa, pb in zip(a.parts, b.parts):
                ha, hb = rihs01(pa.name, originals), rihs01(pb.name, regenerated)
                if ha != hb:
                    problems.append(f"{pa.name.rpartition('/')[2]}: RIHS01 {ha} became {hb}")
        run.report(source, problems)


class _Skip(Exception):
    """A file that cannot be compared: the message says why (it counts as a difference)."""


def _regenerated(run: Run, origin: Origin) -> tuple[str, str, str]:
    """(package, path, text) of the file the ros2 target wrote for ``origin``: .msg/.srv/.action, else .idl."""
    package = _package_of(origin, run)
    if package is None:
        raise _Skip("not imported (see the problems above)")
    try:
        files = run.regenerate(origin.iface, "ros2")
    except RegenerationFailed as e:
        raise _Skip(str(e)) from None
    for ext in (origin.kind, "idl"):
        rel = f"{package}/{origin.kind}/{origin.definition}.{ext}"
        if rel in files:
            return package, rel, files[rel]
    raise _Skip(f"the ros2 target wrote no {package}/{origin.kind}/{origin.definition}.{origin.kind}")


def _view_of(kind: str, package: str, rel: str, text: str, *, structural_only: bool) -> FileView:
    """The regenerated file as the platform's parser reads it."""
    name = Path(rel).stem
    try:
        if rel.endswith(".idl"):
            view = idl_views(text).get(name)
            if view is None:
                raise _Skip(f"the regenerated {rel} defines no {name}")
            return view
        view = ros_view(kind, package, name, text)
    except OracleRefused as e:
        raise _Skip(f"the regenerated {rel}: {e}") from None
    return structural(view) if structural_only else view


def _ros2_file(run: Run, source: str, origins: list[Origin]) -> tuple[FileView, FileView]:
    """A .msg/.srv/.action file and its regenerated file, as rosidl (or rosbags, for .idl) reads them."""
    if not origins:
        raise _Skip("not imported (see the problems above)")
    origin = origins[0]
    path = Path(source)
    package, rel, text = _regenerated(run, origin)
    try:
        a = ros_view(origin.kind, package, path.stem, path.read_text(encoding="utf-8"))
    except OracleRefused as e:
        raise _Skip(f"the original: {e}") from None
    b = _view_of(origin.kind, package, rel, text, structural_only=False)
    # a .msg regenerated as .idl (a wchar) is compared as .idl states it: types, without defaults
    return (structural(a), b) if rel.endswith(".idl") else (a, b)


def _ros2_idl(run: Run, source: str, origins: list[Origin], names: dict[str, str]) -> list[tuple[FileView, FileView]]:
    """Every interface of an .idl file and its regenerated file, as rosbags' IDL parser reads them."""
    try:
        views = idl_views(Path(source).read_text(encoding="utf-8"))
    except OracleRefused as e:
        raise _Skip(f"not imported: {e}") from None
    by_name = {o.definition: o for o in origins}
    missing = [n for n in views if n not in by_name]
    if missing or not views:
        raise _Skip(f"not imported: {', '.join(missing) or 'no struct'} (see the problems above)")
    pairs = []
    for name, a in views.items():
        origin = by_name[name]
        package, rel, text = _regenerated(run, origin)
        b = _view_of(origin.kind, package, rel, text, structural_only=True)
        names.update((pa.name, pb.name) for pa, pb in zip(a.parts, b.parts))
        pairs.append((a, b))
    return pairs


def _package_of(origin: Origin, run: Run) -> str | None:
    return run.compile(origin.iface).interface.namespace("ros2")


def _px4(run: Run, result: ImportResult) -> None:
    origins = {o.source: o for o in result.origins}
    for source in result.sources:
        path = Path(source)
        origin = origins.get(source)
        if origin is None:
            run.report(source, ["not imported (see the problems above)"])
            continue
        try:
            files = run.regenerate(origin.iface, "px4")
        except RegenerationFailed as e:
            run.report(source, [str(e)])
            continue
        rel = next((p for p in files if p.startswith("msg/") and _same_name(Path(p).stem, origin.definition)), None)
        if rel is None:
            run.report(source, [f"the px4 target wrote no msg/{origin.definition}.msg"])
            continue
        try:
            a = px4_view(path.stem, path.read_text(encoding="utf-8"))
            b = px4_view(path.stem, files[rel])
        except OracleRefused as e:
            run.report(source, [str(e)])
            continue
        run.report(source, differences(a, b))


def _same_name(a: str, b: str) -> bool:
    return a.replace("_", "").lower() == b.replace("_", "").lower()


# ---------------------------------------------------------------------------
# JSON


def _json(run: Run, result: ImportResult) -> None:
    from ..emit.json import HEADER_KEY
    from ..forms.jsonform import canonical

    origins = {o.source: o for o in result.origins}
    for source in result.sources:
        origin = origins.get(source)
        if origin is None:
            run.report(source, ["not imported (see the problems above)"])
            continue
        original = json.loads(Path(source).read_text(encoding="utf-8"))
        original.pop(HEADER_KEY, None)
        original.pop("file", None)
        again = canonical(run.compile(origin.iface).interface)
        run.report(source, [] if again == original else [_json_difference(original, again)])


def _json_difference(a: Any, b: Any, where: str = "") -> str:
    if isinstance(a, dict) and isinstance(b, dict):
        for key in list(a) + [k for k in b if k not in a]:
            if a.get(key) != b.get(key):
                return _json_difference(a.get(key), b.get(key), f"{where}/{key}")
    if isinstance(a, list) and isinstance(b, list):
        for i, (x, y) in enumerate(zip(a, b)):
            if x != y:
                return _json_difference(x, y, f"{where}/{i}")
        if len(a) != len(b):
            return f"{where or '/'}: {len(a)} elements became {len(b)}"
    return f"{where or '/'}: expected {json.dumps(a, ensure_ascii=False)[:80]}, got {json.dumps(b, ensure_ascii=False)[:80]}"


COMPARE: dict[str, Callable[[Run, ImportResult], None]] = {"ros2": _ros2, "px4": _px4, "json": _json}


def run(args: argparse.Namespace) -> int:
    """Exit 0 when every file comes back identical, 1 otherwise, 2 on usage or I/O errors."""
    importer = get_importer(args.source)
    if importer is None:
        print(f"iface-lsp roundtrip: the {args.source} importer is not installed", file=sys.stderr)
        return 2
    try:
        result = importer.run(list(args.inputs), {})
    except InputError as e:
        print(f"iface-lsp roundtrip: {e}", file=sys.stderr)
        return 2
    for p in result.problems:
        if p.severity == "error":
            print(p.format(p.path), file=sys.stderr)
    with tempfile.TemporaryDirectory(prefix="iface-roundtrip-") as tmp:
        folder = Path(args.keep) if args.keep else Path(tmp)
        report = write_imported(result.files, folder / "iface", force=True)
        if report.errors:
            for line in report.errors:
                print(f"iface-lsp roundtrip: {line}", file=sys.stderr)
            return 2
        rt = Run(folder, args.verbose)
        try:
            COMPARE[args.source](rt, result)
        except OracleMissing as e:
            print(f"iface-lsp roundtrip: {e}", file=sys.stderr)
            return 2
    if args.keep:
        print(f"kept the imported and regenerated files in {args.keep}", file=sys.stderr)
    print(f"{rt.identical} of {rt.total} identical")
    return 0 if rt.identical == rt.total else 1
