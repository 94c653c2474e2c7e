"""Generated code a person reads: no generated line over 200 characters, the user's stubs at most 100 a line.

Over every generated file of every example and test component, for both node targets; the interface's
JSON file the component package installs is left out: it is the ``json`` target's file byte for byte,
where a doc comment is one JSON string however long. ``iface.nodes.layout`` lays out what grows with the
interface (a member's QoS, a parameter's description, a handler's types, a doc comment).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from iface.emit import generate
from iface.nodes.layout import USER_WIDTH, WIDTH, comment, fit, wrap
from iface.semantics.compile import Workspace

from ..ros_harness.ros import DATA, ROOT

INTERFACES = sorted([*ROOT.glob("examples/*.iface"), *DATA.glob("*.iface"), *DATA.glob("live/*.iface")])


def _long_lines(target: str, iface: Path) -> list[str]:
    result = generate(Workspace().compile_path(str(iface)), target)
    if result.has_errors:
        return []  # a file the target refuses (a system, an interface package of nothing) writes no node
    stem = iface.stem
    out = []
    for f in result.files:
        if f.path.endswith(f"/{stem}.json"):
            continue
        limit = USER_WIDTH if f.once else WIDTH
        out += [f"{f.path}:{n}: {len(line)} > {limit}" for n, line in enumerate(f.text.splitlines(), 1)
                if len(line) > limit]
    return out


@pytest.mark.parametrize("target", ["rclpy", "rclcpp"])
@pytest.mark.parametrize("iface", INTERFACES, ids=[p.stem for p in INTERFACES])
def test_no_generated_line_is_too_long(target: str, iface: Path) -> None:
    assert _long_lines(target, iface) == []


def test_the_interfaces_are_the_ones_that_grow_lines() -> None:
    names = {p.stem for p in INTERFACES}
    assert {"robot_arm", "every_member", "qos_probe", "thermostat", "counter_v2", "listing1", "live_probe"} <= names


# ---- the layout itself ---------------------------------------------------------------------------------


def test_a_line_that_fits_is_left_as_it_is() -> None:
    line = "self._publisher(Sample, '/x', {'depth': 7})"
    assert fit(line, 8) == line


def test_a_long_call_is_laid_out_bracket_by_bracket_and_means_the_same() -> None:
    qos = {f"key_{i}": f"value number {i}" for i in range(12)}
    line = f"result = dict(first=1, qos={qos!r}, last=[1, 2, 3])"
    laid = fit(line, 4, width=60)
    assert 4 + len(laid.splitlines()[0]) <= 60
    assert all(len(x) <= 60 for x in laid.splitlines()[1:]), laid
    scope: dict[str, object] = {}
    exec(compile(ast.parse(laid), "<fit>", "exec"), scope)  # noqa: S102 - the laid-out code must run the same
    assert scope["result"] == {"first": 1, "qos": qos, "last": [1, 2, 3]}


def test_a_string_too_long_for_any_line_is_cut_into_adjacent_literals() -> None:
    text = "word " * 80
    laid = fit(f"dict(name='p', description={text!r})", 8, width=100)
    assert all(len(x) <= 100 for x in laid.splitlines()[1:]) and 8 + len(laid.splitlines()[0]) <= 100
    assert eval(laid) == {"name": "p", "description": text}
    cpp = fit('p.description = "' + "a long description " * 20 + '";', 4, width=80)
    assert cpp.count('"') > 2 and all(len(x) <= 80 for x in cpp.splitlines()[1:]) and cpp.endswith('";')


def test_prose_is_wrapped_and_left_as_it_is_when_it_fits() -> None:
    assert wrap("short text", 2, "//! ") == ["//! short text"]
    lines = comment("word " * 60, 2, "//! ", width=60).split("\n")
    assert len(lines) > 1 and all(x.lstrip().startswith("//! ") for x in lines)
    assert all(len(x) <= 60 for x in lines[1:]) and 2 + len(lines[0]) <= 60
