"""The paper's Listing 1 checks with exit 0, and its seven sets are read as documented."""

from __future__ import annotations

from tests.conftest import run_main

from .helpers import DATA, compile_file

LISTING1 = DATA / "valid" / "listing1.iface"


def test_listing1_checks_with_exit_zero() -> None:
    r = run_main("check", str(LISTING1))
    assert r.returncode == 0, r.stdout + r.stderr
    assert "error" not in r.stdout
    assert "warning[flat-service]" in r.stdout and "warning[flat-action]" in r.stdout


def test_listing1_seven_sets() -> None:
    iface = compile_file(LISTING1).interface
    assert iface.name == "listing1"
    assert iface.subscribed == [] and iface.published == []
    assert [(e.role, e.name) for e in iface.services] == [("provides", "service1"), ("provides", "service2")]
    assert [e.name for e in iface.actions] == ["action1", "action2"]
    assert [f.name for f in iface.parameters] == ["param1", "param2", "param3", "param4"]
    assert [f.name for f in iface.state] == ["position", "velocity", "acceleration", "mode"]
    assert [s.name for s in iface.diagnostics] == ["diagnostics"]


def test_flat_bodies_are_read_by_position() -> None:
    iface = compile_file(LISTING1).interface
    s1 = iface.symbols["service1"]
    assert [f.name for f in s1.request.fields] == ["str", "i"]
    assert [f.name for f in s1.response.fields] == ["result"]
    a2 = iface.symbols["action2"]
    assert [f.name for f in a2.goal.fields] == ["par1", "par2"]
    assert [f.name for f in a2.feedback.fields] == ["f"]
    assert [f.name for f in a2.result.fields] == ["result"]
    a1 = iface.symbols["action1"]
    assert ([f.name for f in a1.goal.fields], [f.name for f in a1.feedback.fields],
            [f.name for f in a1.result.fields]) == (["par1"], ["s"], ["r"])


def test_contract_view() -> None:
    iface = compile_file(DATA / "valid" / "mini_robot.iface").interface
    assumptions = [getattr(x, "name", None) for x in iface.assumptions]
    guarantees = [getattr(x, "name", None) for x in iface.guarantees]
    assert assumptions == ["/cmd_vel", "max_speed", "rate_hz"]
    assert guarantees == ["/odom", "/stop", "diagnostics"]
    assert iface.name == "drive" and iface.version == "2.0.0"
