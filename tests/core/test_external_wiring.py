"""Wirings of external types marked (action) and (diagnostics) land in A and Δ (as import --from node writes them)."""

from __future__ import annotations

from pathlib import Path

from iface.semantics.compile import Workspace

TEXT = """component x

external foo_msgs

provides foo_msgs.Fib on "/fib" (action)
calls foo_msgs.Fib on "/other/fib" (action)
provides foo_msgs.Health on "~/diagnostics" (diagnostics)
provides foo_msgs.Add on "/add"
calls foo_msgs.Health on "/other/diagnostics" (diagnostics)
"""


def test_marked_external_wirings_are_read_into_a_and_delta(tmp_path: Path) -> None:
    path = tmp_path / "x.iface"
    path.write_text(TEXT, encoding="utf-8")
    comp = Workspace().compile_path(str(path))
    assert [d.format() for d in comp.diagnostics] == []
    iface = comp.interface
    assert [(e.role, e.name) for e in iface.actions] == [("provides", "/fib"), ("calls", "/other/fib")]
    assert [(e.role, e.name) for e in iface.services] == [("provides", "/add"), ("calls", "/other/diagnostics")]
    assert [(e.role, e.name, e.definition) for e in iface.diagnostics_endpoints] == [
        ("provides", "~/diagnostics", None)]
    assert iface.diagnostics == []  # no definition to hold: the type is external
