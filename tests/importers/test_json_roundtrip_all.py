"""JSON round trip on everything: ``json`` → ``import --from json`` → ``check`` / ``generate`` gives the same files.

Issue 16: the JSON form carries the files its includes give (embedded under ``included``), every
named type says what it refers to, and generating from the imported file gives byte-identical
files, for every example, every test fixture without errors and (when present) the corpus.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from iface.emit.json import render
from iface.emit.registry import targets
from iface.importers.json import run as import_json
from iface.model.diagnostics import Severity
from iface.semantics.compile import Compilation, Workspace

from ..conftest import ROOT, run_main
from .test_import_quality import _corpus

EXAMPLES = ROOT / "examples"
TARGETS = sorted(targets().items())


def _inputs(tmp: Path) -> list[Path]:
    found = sorted(EXAMPLES.glob("*.iface")) + sorted(
        p for p in (ROOT / "tests").rglob("*") if p.suffix in (".iface", ".thrift") and p.is_file())
    corpus = _corpus()
    if corpus is not None:
        found += sorted((corpus / "thrift").rglob("*.thrift"))
        # the ROS 2 packages, as import --from ros2 writes them
        packages = [p for p in sorted((corpus / "ros2").glob("*/")) + sorted((corpus / "ros2").glob("*/*/"))
                    if any((p / kind).is_dir() for kind in ("msg", "srv", "action"))]
        run_main("import", "-q", "--from", "ros2", *(str(p) for p in packages), "--out", str(tmp))
        found += sorted(tmp.glob("*.iface"))
    return found


def _clean(path: Path) -> Compilation | None:
    comp = Workspace().compile_path(str(path))
    return None if any(d.severity == Severity.ERROR for d in comp.all_diagnostics()) else comp


def _unresolved(form: Any, where: str = "") -> list[str]:
    """JSON pointers of named types that say neither what they refer to nor their package."""
    out: list[str] = []
    if isinstance(form, dict):
        if form.get("kind") == "named" and "refers_to" not in form and "external" not in form:
            out.append(where)
        for k, v in form.items():
            out += _unresolved(v, f"{where}/{k}")
    elif isinstance(form, list):
        for i, v in enumerate(form):
            out += _unresolved(v, f"{where}/{i}")
    return out


def _round_trip(comp: Compilation, tmp: Path) -> Compilation:
    tmp.mkdir(parents=True, exist_ok=True)
    form = tmp / f"{Path(comp.path).stem}.json"
    form.write_text(render(comp), encoding="utf-8")
    result = import_json([str(form)], {})
    assert not result.problems, [p.message for p in result.problems]
    out = tmp / "imported"
    for f in result.files:
        (out / f.path).parent.mkdir(parents=True, exist_ok=True)
        (out / f.path).write_text(f.text, encoding="utf-8")
    return Workspace().compile_path(str(out / result.files[0].path))


def _files(comp: Compilation) -> dict[str, dict[str, str]]:
    """Every target's files (targets that refuse the input are left out), each written beside its source: a
    system's launch file names its system file and parameter files relative to where it is written."""
    out = {}
    for name, target in TARGETS:
        result = target.generate(comp, {"out": str(Path(comp.path).parent)})
        if not result.has_errors:
            out[name] = {f.path: f.text for f in result.files}
    return out


def test_every_example_fixture_and_corpus_file_round_trips_to_identical_files(tmp_path: Path) -> None:
    checked = 0
    differing: list[str] = []
    for i, path in enumerate(_inputs(tmp_path / "corpus_ros2")):
        comp = _clean(path)
        if comp is None:
            continue
        assert not _unresolved(json.loads(render(comp))), path
        back = _round_trip(comp, tmp_path / str(i))
        errors = [d.format() for d in back.all_diagnostics() if d.severity == Severity.ERROR]
        assert not errors, (path, errors)
        assert [(d.code, d.message) for d in back.diagnostics] == [(d.code, d.message) for d in comp.diagnostics], path
        if _files(back) != _files(comp):
            differing.append(str(path))
        checked += 1
    assert not differing
    assert checked >= 250  # examples and fixtures: a guard against the list quietly emptying


def test_the_robot_arm_round_trips_through_the_cli(tmp_path: Path) -> None:
    arm = EXAMPLES / "robot_arm.iface"
    assert run_main("generate", str(arm), "-t", "json", "-o", str(tmp_path / "json"), "-q").returncode == 0
    form = json.loads((tmp_path / "json" / "robot_arm.json").read_text())
    assert [x["path"] for x in form["included"]] == ["arm_common.iface"]
    assert form["included"][0]["form"]["file"] == "arm_common.iface"
    done = run_main("import", "--from", "json", str(tmp_path / "json" / "robot_arm.json"), "--out", str(tmp_path / "imp"))
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in (tmp_path / "imp").iterdir()) == ["arm_common.iface", "robot_arm.iface"]
    check = run_main("check", str(tmp_path / "imp" / "robot_arm.iface"))
    assert check.returncode == 0 and check.stdout.startswith("ok: 2 files"), check.stdout
    for out, source in (("a", arm), ("b", tmp_path / "imp" / "robot_arm.iface")):
        assert run_main("generate", str(source), "-t", "ros2", "-o", str(tmp_path / out), "-q").returncode == 0
    a = {p.relative_to(tmp_path / "a"): p.read_bytes() for p in (tmp_path / "a").rglob("*") if p.is_file()}
    b = {p.relative_to(tmp_path / "b"): p.read_bytes() for p in (tmp_path / "b").rglob("*") if p.is_file()}
    assert a == b and len(a) > 10


def test_an_embedded_include_that_would_leave_the_output_folder_is_refused(tmp_path: Path) -> None:
    form = json.loads(render(Workspace().compile_path(str(EXAMPLES / "robot_arm.iface"))))
    form["included"][0]["path"] = "../arm_common.iface"
    (tmp_path / "x.json").write_text(json.dumps(form))
    done = run_main("import", "--from", "json", str(tmp_path / "x.json"), "--out", str(tmp_path / "out"))
    assert done.returncode == 1
    assert "/included/0/path" in done.stderr and "import it on its own" in done.stderr


@pytest.mark.parametrize("position", [None, 2])
def test_constants_keep_their_place_among_the_fields(tmp_path: Path, position: int | None) -> None:
    body = "const u8 MAX = 3, u8 a, u8 b" if position is None else "u8 a, u8 b, const u8 MAX = 3"
    src = tmp_path / "c.iface"
    src.write_text(f"message M {{ {body} }}\npublishes M on \"/m\"\n")
    comp = Workspace().compile_path(str(src))
    (const,) = json.loads(render(comp))["items"][0]["consts"]
    assert const.get("position") == position
    back = _round_trip(comp, tmp_path / "rt")
    struct = back.interface.definitions[0]
    order = sorted([*struct.fields, *struct.consts], key=lambda x: x.span.start)
    assert [x.name for x in order] == (["MAX", "a", "b"] if position is None else ["a", "b", "MAX"])
