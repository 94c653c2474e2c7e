"""Thrift IDL: iface reads the Thrift features as Thrift does."""

from __future__ import annotations

from pathlib import Path

from iface.model import nodes as m
from iface.model.walk import typedef_chain
from iface.semantics.compile import Workspace

from .helpers import DATA, compile_file

FEATURES = DATA / "valid" / "thrift_features.thrift"


def test_features_check_without_errors() -> None:
    comp = compile_file(FEATURES)
    assert not [d for d in comp.all_diagnostics() if d.severity == 1], [d.format() for d in comp.diagnostics]


def test_model_of_thrift_features() -> None:
    iface = compile_file(FEATURES).interface
    kw = iface.symbols["Keywords"]
    assert [f.name for f in kw.fields][:4] == ["i8", "string", "uuid", "binary"]
    assert [f.id for f in kw.fields][-1] is None
    assert kw.fields[4].requiredness == "optional" and kw.fields[5].requiredness == "required"
    assert kw.fields[10].reference
    assert [a.key for a in kw.annotations] == ["cpp.type", "annotation.without.value"]
    shared = kw.fields[8].type
    assert isinstance(shared, m.NamedType) and shared.target is not None and shared.target.name == "Shared"
    assert [t.name for t in typedef_chain(kw.fields[9].type)] == ["SharedAlias"]
    mode = iface.symbols["Mode"]
    assert [(v.name, v.value) for v in mode.values] == [("SLOW", 1), ("FAST", 2), ("TURBO", 10)]
    store = iface.symbols["Store"]
    assert store.extends is not None and store.extends.target is iface.symbols["Base"]
    get, notify, names = store.functions
    assert get.doc == "Reads a record." and get.throws[0].name == "failure"
    assert notify.oneway and notify.returns is None
    assert names.annotations[0].key == "deprecated"
    assert [ns.scope for ns in iface.namespaces] == ["cpp", "py.twisted", "*"]
    assert iface.includes[1].cpp


def test_integer_too_big_for_i64_is_an_error_on_its_line(tmp_path: Path) -> None:
    p = tmp_path / "broken.thrift"
    p.write_text("const i64 ok = 68719476736\nconst i64 broken = 9876543210987654321 // > 2^63\n")
    comp = Workspace().compile_path(str(p))
    errors = [d for d in comp.diagnostics if d.severity == 1]
    assert [(d.code, d.location()[0]) for d in errors] == [("int-out-of-range", 2)]


def test_thrift_files_do_not_get_robot_rules(tmp_path: Path) -> None:
    p = tmp_path / "plain.thrift"
    p.write_text("struct lower_case { 1: i32 CamelField }\nstruct Tree { 1: list<Tree> kids }\n")
    comp = Workspace().compile_path(str(p))
    assert comp.diagnostics == []


def test_robot_rules_apply_to_thrift_with_a_ros2_namespace(tmp_path: Path) -> None:
    p = tmp_path / "ros.thrift"
    p.write_text("namespace ros2 pkg\nstruct lower_case { 1: i32 x }\n")
    comp = Workspace().compile_path(str(p))
    assert [d.code for d in comp.diagnostics] == ["ros-naming"]
