"""The ros2 target's parameter file: only what ROS 2 can load, every refusal located at the parameter."""

from __future__ import annotations

from pathlib import Path

import pytest

from iface.emit.ros2 import CODES

from .helpers import compile_text, run
from .oracles import load_yaml


def params_yaml(text: str) -> tuple[str, list]:
    comp = compile_text(text, "params.iface")
    assert not comp.has_errors, [d.format() for d in comp.diagnostics]
    result = run("ros2", comp)
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    (yaml_text,) = [f.text for f in result.files if f.path.endswith(".params.yaml")]
    # the snippets declare no license or maintainer: that warning is tested with the package metadata
    return yaml_text, [d for d in result.diagnostics if d.code != "ros2-package-metadata-missing"]


def located(comp_text: str, code: str) -> list[str]:
    """The source text at each diagnostic ``code`` of generating ``comp_text``."""
    comp = compile_text(comp_text, "params.iface")
    result = run("ros2", comp)
    return [comp.interface.source.text[d.span.start:d.span.end] for d in result.diagnostics if d.code == code]


def test_an_empty_list_default_is_written_as_no_default_with_a_warning() -> None:
    text, diags = params_yaml("component c\nconfiguration c { i32[] empty = [], i32[] some = [1, 2] }\n")
    assert [d.code for d in diags] == ["ros2-param-empty-list"]
    assert "empty: []" not in text
    assert "    # empty (int32[]): not set here: ROS 2 cannot load an empty list" in text
    assert load_yaml(text) == {"c": {"ros__parameters": {"some": [1, 2]}}}
    assert located("component c\nconfiguration c { i32[] empty = [] }\n", "ros2-param-empty-list") == ["[]"]


def test_an_integer_outside_int64_is_refused_at_the_default() -> None:
    comp = compile_text("component c\nconfiguration c { u64 huge = 18446744073709551615 }\n",
                        "params.iface")
    result = run("ros2", comp)
    assert result.has_errors and result.files == []
    (d,) = [d for d in result.diagnostics if d.code == "ros2-param-value"]
    assert comp.interface.source.text[d.span.start:d.span.end] == "18446744073709551615"
    assert "int64" in d.message


def test_a_u64_parameter_is_warned_about_int64() -> None:
    text, diags = params_yaml("component c\nconfiguration c { u64 small = 5, u64[] list = [1] }\n")
    assert sorted(d.code for d in diags) == ["ros2-param-uint64", "ros2-param-uint64"]
    assert load_yaml(text) == {"c": {"ros__parameters": {"small": 5, "list": [1]}}}
    assert located("component c\nconfiguration c { u64 small }\n", "ros2-param-uint64") == ["u64"]


def test_every_type_ros2_parameters_hold_is_written_loadably() -> None:
    text, diags = params_yaml(
        "component c\nenum Mode { A = 1, B = 2 }\nconfiguration c {\n"
        "  bool on = true, i8 a = -1, i64 b = -9223372036854775808, u32 c = 4294967295, double d = 1,\n"
        '  string s = "x", Mode mode = Mode.B, bool[] bs = [true], i16[] is = [1, 2], double[] ds = [1, 2.5],\n'
        '  string[] ss = ["a", "b"], binary blob\n}\n')
    assert diags == []
    assert load_yaml(text)["c"]["ros__parameters"] == {
        "on": True, "a": -1, "b": -9223372036854775808, "c": 4294967295, "d": 1.0, "s": "x", "mode": 2,
        "bs": [True], "is": [1, 2], "ds": [1.0, 2.5], "ss": ["a", "b"]}


@pytest.mark.parametrize(("field", "reason"), [
    ("map<string, i32> m", "no maps"),
    ("set<i32> s", "no sets"),
    ("i32[][] nested", "no arrays of arrays"),
    ("binary[] blobs", "no arrays of arrays"),
    ("uuid[] ids", "no arrays of arrays"),
    ("S sub", "no message types"),
    ("S[] subs", "no arrays of messages"),
    ("geometry_msgs.Pose pose", "no message types"),
])
def test_types_ros2_parameters_cannot_hold_are_errors_at_the_type(field: str, reason: str) -> None:
    src = f"component c\nexternal geometry_msgs\nstruct S {{ i32 a }}\nconfiguration c {{ {field} }}\n"
    comp = compile_text(src, "params.iface")
    assert not comp.has_errors, [d.format() for d in comp.diagnostics]
    result = run("ros2", comp)
    assert result.has_errors and result.files == []
    (d,) = [d for d in result.diagnostics if d.severity == 1]
    assert d.code == "ros2-param-type" and reason in d.message
    assert comp.interface.source.text[d.span.start:d.span.end] == field.rsplit(" ", 1)[0]


def test_the_new_codes_are_in_the_table() -> None:
    for code in ("ros2-param-value", "ros2-param-empty-list", "ros2-param-uint64", "ros2-param-type"):
        assert code in CODES
    assert CODES["ros2-param-value"][0] == 1 and CODES["ros2-param-empty-list"][0] == 2


def test_cli_empty_list_exit_0_with_warning_and_no_unloadable_value(tmp_path: Path) -> None:
    from tests.conftest import run_main

    src = tmp_path / "p.iface"
    src.write_text("component c\nconfiguration c { i32[] empty = [], u64 huge = 18446744073709551615 }\n")
    proc = run_main("generate", str(src), "-t", "ros2", "-o", str(tmp_path / "out"))
    assert proc.returncode == 1
    assert "warning[ros2-param-empty-list]" in proc.stdout and "error[ros2-param-value]" in proc.stdout
    assert not (tmp_path / "out").exists()
