"""Δ, the diagnostics and control services, is a set of its own: never counted in S.

Issue 16: a wired diagnostics service was in S and in Δ. It is in Δ only, in the model, the
dump, the JSON form, Markdown, the contract and compat findings (the graph: tests/compat);
an unwired ``service diagnostics`` is told what it is; a flat diagnostics body reads as what
the caller sends (the last field) and gets (the others).
"""

from __future__ import annotations

import json
from pathlib import Path

from iface.compat import compare
from iface.compat.contract import contract
from iface.emit.registry import generate
from iface.forms.dump import dump_interface
from iface.forms.jsonform import to_json
from iface.semantics.compile import Compilation, Workspace

from ..conftest import ROOT, run_main

ARM = ROOT / "examples" / "robot_arm.iface"
LISTING1 = ROOT / "tests" / "core" / "data" / "valid" / "listing1.iface"


def _comp(path: Path) -> Compilation:
    return Workspace().compile_path(str(path))


def test_a_wired_diagnostics_service_is_in_delta_only() -> None:
    iface = _comp(ARM).interface
    assert [e.definition.name for e in iface.services if e.definition] == ["MoveToPose", "JointLimitsService",
                                                                          "MoveToPose"]
    assert [d.name for d in iface.diagnostics] == ["ArmDiagnostics"]
    (ep,) = iface.diagnostics_endpoints
    assert (ep.role, ep.name, ep.definition.name) == ("provides", "/arm/diagnostics", "ArmDiagnostics")
    assert iface.guarantees.count(ep.definition) == 1  # once, as Δ


def test_dump_json_form_markdown_and_contract_keep_delta_apart() -> None:
    comp = _comp(ARM)
    sets = dump_interface(comp.interface)["sets"]
    assert "ArmDiagnostics" not in {e["type"] for e in sets["services"]}
    assert sets["diagnostics"] == [{"role": "provides", "name": "/arm/diagnostics", "type": "ArmDiagnostics"}]
    form = to_json(comp.interface)["sets"]
    assert "/arm/diagnostics" not in {e["name"] for e in form["services"]} and form["diagnostics"] == ["ArmDiagnostics"]
    (md,) = generate(comp, "markdown").files
    assert "| S | services | 3 |" in md.text and "| Δ | diagnostics | 1 |" in md.text
    assert "| `/arm/diagnostics` | `ArmDiagnostics` | level: u8 | summary: string&lt;=256, error\\_count: u32 |" in md.text
    data = contract(comp)
    kinds = [(g["kind"], g["name"]) for g in data["guarantees"] if "diagnostics" in g["name"]]
    assert kinds == [("diagnostics", "/arm/diagnostics")]


def test_removing_the_diagnostics_service_is_a_delta_finding_only(tmp_path: Path) -> None:
    text = ARM.read_text()
    start = text.index("/** Health report")
    end = text.index("} (diagnostics)") + len("} (diagnostics)")
    (tmp_path / "arm_common.iface").write_text((ROOT / "examples" / "arm_common.iface").read_text())
    (tmp_path / "new.iface").write_text(text[:start] + text[end:].replace(
        'provides ArmDiagnostics on "/arm/diagnostics"\n', ""))
    report = compare(_comp(ARM), _comp(tmp_path / "new.iface"))
    rules = sorted(f.rule for f in report.findings if f.severity.label == "error")
    assert rules == ["diagnostics-removed"], rules


def test_an_unwired_diagnostics_service_is_told_what_it_is() -> None:
    comp = _comp(LISTING1)
    (hint,) = [d for d in comp.diagnostics if d.code == "diagnostics-service"]
    assert hint.severity.label == "hint"
    assert "diagnostics and control service (the set Δ, kept apart from its services S)" in hint.message
    assert "served as 'diagnostics'" in hint.message and 'provides diagnostics on \\"/name\\"' not in hint.message
    assert [e.name for e in comp.interface.diagnostics_endpoints] == ["diagnostics"]
    assert all(e.definition.name != "diagnostics" for e in comp.interface.services if e.definition)


def test_a_flat_diagnostics_service_reads_as_what_the_caller_sends_and_gets() -> None:
    comp = _comp(LISTING1)
    svc = next(d for d in comp.interface.diagnostics)
    assert [f.name for f in svc.request.fields] == ["cmd"]
    assert [f.name for f in svc.response.fields] == ["result", "r"]
    (warning,) = [d for d in comp.diagnostics if d.code == "flat-service" and "'diagnostics'" in d.message]
    assert "request (what the caller sends): cmd; response (what it gets back): result, r" in warning.message
    from iface.model.normalize import explicit_text  # what the flat-service quick fix writes
    assert explicit_text(svc, comp.source.text) == ("    request {\n        string cmd\n    }\n"
                                                    "    response {\n        string result\n        i32 r\n    }")
    srv = next(f for f in generate(comp, "ros2").files if f.path.endswith("srv/Diagnostics.srv"))
    assert srv.text.split("\n", 2)[2] == "string cmd\n---\nstring result\nint32 r\n"


def test_the_json_form_keeps_a_flat_diagnostics_body_in_its_written_order(tmp_path: Path) -> None:
    comp = _comp(LISTING1)
    from iface.forms.jsonform import from_json
    text = from_json(json.loads(json.dumps(to_json(comp.interface))))
    assert "service diagnostics {\n    string result,\n    i32 r,\n    string cmd\n}" in text


def test_check_prints_one_line_on_success_and_nothing_with_quiet() -> None:
    done = run_main("check", str(ARM))
    assert done.returncode == 0 and done.stdout == "ok: 2 files, 16 definitions\n"
    assert run_main("check", "-q", str(ARM)).stdout == ""
    flat = run_main("check", str(LISTING1))
    assert flat.stdout.splitlines()[-1] == "ok: 1 file, 9 definitions, 11 warnings"
    quiet = run_main("check", "-q", str(LISTING1))
    assert quiet.returncode == 0 and quiet.stdout == ""


def test_the_examples_check_without_warnings() -> None:
    done = run_main("check", *(str(p) for p in sorted((ROOT / "examples").glob("*.iface"))))
    assert done.returncode == 0
    assert not [line for line in done.stdout.splitlines() if "warning[" in line or "error[" in line], done.stdout
    files = len(list((ROOT / "examples").glob("*.iface")))
    assert done.stdout.splitlines()[-1].startswith(f"ok: {files} files, ")
