"""The system graph in DOT, Mermaid and JSON, with its checks; and impact."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest
from compat_support import DATA, HASH_SEEDS, cached, run_cli

from iface.compat.graph import build, graph_json, render_dot, render_mermaid
from iface.compat.impact import impact, impact_json

SYSTEM = [DATA / "system" / n for n in ("camera.iface", "detector.iface", "logger.iface")]
ARM = [DATA / "verdicts" / n for n in ("arm_v1.iface", "planner.iface", "monitor.iface")]


def _graph(paths):  # type: ignore[no-untyped-def]
    return build([cached(p) for p in paths])


def test_links_run_from_sender_to_receiver() -> None:
    data = graph_json(_graph(ARM), str)
    links = {(lk["kind"], lk["name"], lk["from"], lk["to"]) for lk in data["links"]}
    assert links == {("topic", "/arm/pose", "arm", "planner"), ("topic", "/arm/pose", "arm", "monitor"),
                     ("topic", "/arm/status", "arm", "monitor"), ("topic", "/arm/cmd", "planner", "arm"),
                     ("service", "/arm/plan", "planner", "arm")}
    assert data["checks"] == []


def test_checks() -> None:
    g = _graph(SYSTEM)
    codes = sorted({(d.code, d.severity.label) for d in g.checks})
    assert codes == [("graph-qos-mismatch", "error"), ("graph-topic-type-conflict", "error"),
                     ("graph-unprovided-service", "warning"), ("graph-unpublished-topic", "warning")]
    qos = next(d for d in g.checks if d.code == "graph-qos-mismatch")
    assert "durability: offered volatile, requested transient_local" in qos.message
    assert "reliability: offered best_effort, requested reliable" in qos.message
    assert qos.path.endswith("detector.iface")
    assert g.has_errors


def test_dot_is_valid() -> None:
    text = render_dot(_graph(SYSTEM))
    assert text.startswith("digraph system {") and text.endswith("}\n")
    assert '"camera" -> "detector"' in text and "color=red" in text
    if shutil.which("dot") is None:
        pytest.skip("graphviz dot is not installed")
    done = subprocess.run(["dot", "-Tsvg"], input=text, capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 0, done.stderr


def test_mermaid() -> None:
    text = render_mermaid(_graph(ARM))
    assert text.splitlines()[0] == "flowchart LR"
    assert '  arm -->|"/arm/pose: arm_msgs/Pose"| planner' in text
    assert '  planner -.->|"/arm/plan: arm_msgs/Plan (service)"| arm' in text


@pytest.mark.parametrize("fmt", ["dot", "mermaid", "json"])
def test_cli_formats_are_deterministic(fmt: str) -> None:
    args = ["graph", *[str(p) for p in SYSTEM], "--format", fmt]
    one, two = (run_cli(*args, hash_seed=seed) for seed in HASH_SEEDS)
    assert one.returncode == 1  # the checks find errors
    assert one.stdout == two.stdout and one.stderr == two.stderr
    if fmt == "json":
        assert json.loads(one.stdout)["schema"] == "iface-graph/1"
    else:
        assert "error[graph-qos-mismatch]" in one.stderr


def test_impact() -> None:
    old, new = cached(DATA / "verdicts" / "arm_v1.iface"), cached(DATA / "verdicts" / "arm_v3.iface")
    system = [cached(p) for p in ARM[1:]]
    result = impact_json(impact(system, old, new), str)
    assert {"component": "monitor", "status": "broken"} in result["affected"]
    broken = [lk for lk in result["links"] if lk["status"] == "broken"]
    assert broken == [{"status": "broken", "kind": "topic", "name": "/arm/status", "role": "publishes",
                       "peer": "monitor", "rules": ["definition-removed", "published-removed"]}]
    assert result["verdict"] == "incompatible"


def test_impact_cli() -> None:
    done = run_cli("impact", "--system", "verdicts/planner.iface", "verdicts/monitor.iface",
                   "--replace", "verdicts/arm_v1.iface", "verdicts/arm_v2.iface")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "  added     topic /arm/battery" not in done.stdout  # nobody subscribes the new topic
    assert "unchanged topic /arm/status  arm -> monitor" in done.stdout
    assert "removed   topic /arm/cmd  planner -> arm" in done.stdout
    broken = run_cli("impact", "--system", "verdicts/planner.iface", "verdicts/monitor.iface",
                     "--replace", "verdicts/arm_v1.iface", "verdicts/arm_v3.iface")
    assert broken.returncode == 1 and "affected components: monitor (broken)" in broken.stdout


def test_same_name_in_another_package_or_with_other_fields_is_a_conflict(tmp_path: Path) -> None:
    from iface.semantics.compile import Workspace

    pub = tmp_path / "nav.iface"
    pub.write_text('namespace ros2 nav_pkg\nmessage Status { float64 battery, u8 mode }\n'
                   'publishes Status on "/nav/status"\n')
    other_pkg = tmp_path / "mon.iface"
    other_pkg.write_text('namespace ros2 monitor_pkg\nmessage Status { float64 battery, u8 mode }\n'
                         'subscribes Status on "/nav/status"\n')
    other_fields = tmp_path / "mon2.iface"
    other_fields.write_text('namespace ros2 nav_pkg\nmessage Status { i32 level }\n'
                            'subscribes Status on "/nav/status"\n')
    same = tmp_path / "mon3.iface"
    same.write_text('namespace ros2 nav_pkg\nmessage Status { float64 battery, u8 mode }\n'
                    'subscribes Status on "/nav/status"\n')
    ws = Workspace()

    def conflicts(*paths: Path) -> list[str]:
        g = build([ws.compile_path(str(p)) for p in paths])
        return [d.message for d in g.checks if d.code == "graph-topic-type-conflict"]

    assert conflicts(pub, same) == []
    assert any("monitor_pkg/Status" in msg and "nav_pkg/Status" in msg for msg in conflicts(pub, other_pkg))
    assert any("other fields" in msg for msg in conflicts(pub, other_fields))
