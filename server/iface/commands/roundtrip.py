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
    OracleMissing,
    OracleRefused,
    differences,
    px4_view,
    rihs01,
    ros_view,
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
    origins = {o.source: o for o in result.origins}
    originals: dict[str, Any] = {}
    regenerated: dict[str, Any] = {}
    pending: list[tuple[str, Any, Any]] = []
    failures: dict[str, str] = {}
    for source in result.sources:
        path = Path(source)
        kind = path.suffix[1:]
        origin = origins.get(source)
        if kind == "idl":  # never counted as identical unseen: imported or not, it is reported
            failures[source] = ("not compared: roundtrip cannot judge .idl files yet" if origin is not None
                                else "not imported (see the problems above)")
            continue
        package = _package_of(origin, run) if origin else None
        if origin is None or package is None:
            failures[source] = "not imported (see the problems above)"
            continue
        try:
            files = run.regenerate(origin.iface, "ros2")
        except RegenerationFailed as e:
            failures[source] = str(e)
            continue
        rel = f"{package}/{kind}/{origin.definition}.{kind}"
        if rel not in files:
            failures[source] = f"the ros2 target wrote no {rel}"
            continue
        try:
            a = ros_view(kind, package, path.stem, path.read_text(encoding="utf-8"))
        except OracleRefused as e:
            failures[source] = f"the original: {e}"
            continue
        try:
            b = ros_view(kind, package, origin.definition, files[rel])
        except OracleRefused as e:
            failures[source] = f"the regenerated {rel}: {e}"
            continue
        for part in a.parts:
            originals[part.name] = part.descs
        for part in b.parts:
            regenerated[part.name] = part.descs
        pending.append((source, a, b))
    for source in result.sources:
        if source in failures:
            run.report(source, [failures[source]])
            continue
        _, a, b = next(x for x in pending if x[0] == source)
        problems = differences(a, b)
        for pa, pb in zip(a.parts, b.parts):
            ha, hb = rihs01(pa.name, originals), rihs01(pb.name, regenerated)
            if ha != hb:
                problems.append(f"{pa.name.rpartition('/')[2]}: RIHS01 {ha} became {hb}")
        run.report(source, problems)


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
