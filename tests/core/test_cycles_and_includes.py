"""Typedef and extends cycles are errors naming the cycle; include chains of any length compile without a
false error, past MAX_INCLUDE_DEPTH the message names the chain; shared includes are compiled once."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from iface.semantics import compile as compile_module
from iface.semantics.compile import MAX_INCLUDE_DEPTH, Workspace
from tests.conftest import ROOT, run_main


def _errors(text: str, name: str) -> list[tuple[int, str, str]]:
    comp = Workspace().compile_text(f"/virtual/{name}", text)
    return [(d.location()[0], d.code, d.message) for d in comp.diagnostics if d.severity == 1]


def test_a_typedef_cycle_names_the_cycle_at_each_typedef() -> None:
    errors = _errors("typedef B A\ntypedef C B\ntypedef A C\nstruct S { 1: A a }\n", "t.thrift")
    assert [(line, code) for line, code, _ in errors] == [(1, "typedef-cycle"), (2, "typedef-cycle"),
                                                          (3, "typedef-cycle")]
    assert "A → B → C → A" in errors[0][2] and "B → C → A → B" in errors[1][2]


def test_a_typedef_through_a_container_of_itself_is_a_cycle() -> None:
    errors = _errors("typedef map<i32, list<A>> A\n", "t.thrift")
    assert [(line, code) for line, code, _ in errors] == [(1, "typedef-cycle")] and "A → A" in errors[0][2]
    assert _errors("struct Node { 1: list<Node> children }\ntypedef list<Node> Forest\n", "t.thrift") == []


def test_an_extends_cycle_names_the_cycle() -> None:
    errors = _errors("service A extends B {}\nservice B extends C {}\nservice C extends A {}\nservice D extends D {}\n",
                     "s.thrift")
    assert [(line, code) for line, code, _ in errors] == [(1, "extends-cycle"), (2, "extends-cycle"),
                                                          (3, "extends-cycle"), (4, "extends-cycle")]
    assert "A → B → C → A" in errors[0][2] and "D → D" in errors[3][2]


def test_a_recursive_typedef_in_a_robot_file_does_not_hang(tmp_path: Path) -> None:
    src = tmp_path / "cyc.iface"
    src.write_text('typedef list<A> A\nmessage S { A a }\npublishes S on "/s"\n')
    code = f"from iface.semantics.compile import Workspace; Workspace().compile_path({str(src)!r})"
    try:
        subprocess.run([sys.executable, "-c", code], check=True, timeout=120, cwd=ROOT)
    except subprocess.TimeoutExpired:
        pytest.fail("checking a file with 'typedef list<A> A' does not end")
    r = run_main("check", str(src))
    assert r.returncode == 1 and "error[typedef-cycle]" in r.stdout


def _chain(folder: Path, n: int, leaf_type: str = "i32") -> Path:
    """f0.iface includes f1.iface … includes f{n-1}.iface, each using the next one's type."""
    folder.mkdir()
    for i in range(n):
        last = i + 1 == n
        head = "" if last else f'include "f{i + 1}.iface"\n'
        field = leaf_type if last else f"f{i + 1}.T{i + 1}"
        (folder / f"f{i}.iface").write_text(f"{head}struct T{i} {{\n    1: {field} x\n}}\n")
    return folder / "f0.iface"


def test_a_chain_of_hundreds_of_includes_has_no_false_error(tmp_path: Path) -> None:
    top = _chain(tmp_path / "chain", 600)
    comp = Workspace().compile_path(str(top))  # inside pytest: a deep stack already
    assert [d.format() for d in comp.all_diagnostics() if d.severity == 1] == []
    assert len(comp.closure()) == 600
    r = run_main("check", "-q", str(top))
    assert r.returncode == 0 and r.stdout == "", r.stdout[:500]


def test_an_error_at_the_bottom_of_a_long_chain_reaches_the_top(tmp_path: Path) -> None:
    top = _chain(tmp_path / "chain", 300, leaf_type="Missing")
    comp = Workspace().compile_path(str(top))
    assert [d.code for d in comp.diagnostics] == ["include-error"]
    assert "unknown type 'Missing'" in comp.diagnostics[0].message


def test_past_the_depth_limit_the_message_names_the_chain(tmp_path: Path) -> None:
    top = _chain(tmp_path / "chain", MAX_INCLUDE_DEPTH + 5)
    comp = Workspace().compile_path(str(top))
    deep = [d for d in comp.all_diagnostics() if d.code == "include-too-deep"]
    assert len(deep) == 1
    d = deep[0]
    assert Path(d.path).name == f"f{MAX_INCLUDE_DEPTH - 1}.iface"
    assert f"more than {MAX_INCLUDE_DEPTH} files deep" in d.message
    assert d.message.count("→") == 6 and "f0.iface → f1.iface → f2.iface → …" in d.message
    assert f"f{MAX_INCLUDE_DEPTH}.iface" in d.message
    assert d.data["chain"][0] == str(top) and len(d.data["chain"]) == MAX_INCLUDE_DEPTH + 1
    assert not any(d.code == "nesting-too-deep" for d in comp.all_diagnostics())


def test_shared_includes_are_compiled_and_checked_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A lattice: every file of a level includes both files of the next (2**levels paths, 2*levels files)."""
    levels = 24
    for k in range(levels):
        for side in "ab":
            head = "" if k + 1 == levels else f'include "l{k + 1}a.iface"\ninclude "l{k + 1}b.iface"\n'
            (tmp_path / f"l{k}{side}.iface").write_text(f"{head}struct S{k}{side} {{ 1: i32 x }}\n")
    stamps = {"n": 0}
    real = Workspace._stamp

    def counting(self: Workspace, key: str) -> object:
        stamps["n"] += 1
        return real(self, key)

    monkeypatch.setattr(compile_module.Workspace, "_stamp", counting)
    ws = Workspace()
    comp = ws.compile_path(str(tmp_path / "l0a.iface"))
    assert len(comp.closure()) == 2 * levels - 1
    assert stamps["n"] < 20 * levels, stamps  # linear in the files, not in the 2**24 paths
    stamps["n"] = 0
    assert ws.compile_path(str(tmp_path / "l0a.iface")) is comp  # unchanged: the cached compilation
    assert stamps["n"] < 20 * levels, stamps


def test_the_references_that_close_a_cycle_are_left_unresolved() -> None:
    """So that no walk of the model (emitters, hover, compat) follows the cycle round."""
    comp = Workspace().compile_text("/virtual/c.thrift", "typedef list<A> A\ntypedef C B\ntypedef B C\n"
                                    "service S extends S {}\ntypedef i32 Fine\ntypedef Fine AlsoFine\n")
    a, b, c, s, fine, also = comp.interface.definitions
    assert a.type.element.target is None and b.type.target is None and c.type.target is None
    assert s.extends.target is None
    assert also.type.target is fine


def test_an_unchanged_buffer_and_its_includes_are_not_compiled_again(tmp_path: Path) -> None:
    (tmp_path / "inc.iface").write_text("struct Shared { 1: i32 x }\n")
    ws = Workspace()
    path = str(tmp_path / "main.iface")
    text = 'include "inc.iface"\nstruct Uses { 1: inc.Shared s }\n'
    first = ws.compile_text(path, text)
    assert ws.compile_text(path, text) is first
    assert ws.compile_text(path, text + "\n") is not first
