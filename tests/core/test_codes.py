"""A fixture per diagnostic code: the finding appears on the marked line, nothing else is an error."""

from __future__ import annotations

from pathlib import Path

import pytest

from iface.model.diagnostics import CODES, Severity

from .helpers import DATA, compile_file, expectations

INVALID = sorted(p for p in (DATA / "invalid").iterdir() if p.is_file())
#: codes tested programmatically in test_bad_input.py (too-many-findings: the server's, tests/lsp/test_limits.py)
BAD_INPUT_CODES = {"invalid-encoding", "binary-file", "file-too-large", "empty-file", "cannot-read",
                   "include-too-deep", "too-many-findings"}


def test_every_code_has_a_fixture() -> None:
    named = {p.name.split("_", 1)[0] for p in INVALID}
    missing = set(CODES) - named - BAD_INPUT_CODES
    assert not missing, f"codes without a fixture: {sorted(missing)}"


@pytest.mark.parametrize("path", [p for p in INVALID if expectations(p)], ids=lambda p: p.name)
def test_fixture_reports_its_code(path: Path) -> None:
    comp = compile_file(path)
    found = {(d.location()[0], d.code) for d in comp.diagnostics}
    wanted = expectations(path)
    assert wanted <= found, f"missing {sorted(wanted - found)}; got {sorted(found)}"
    code = path.name.split("_", 1)[0]
    assert code in CODES
    # every error the file has is one it was written to have
    unexpected = {(line, c) for line, c in found if CODES[c][0] == Severity.ERROR and c != "include-error"} - wanted
    if code not in ("include-cycle",):
        assert not unexpected, f"unexpected errors {sorted(unexpected)}"


def test_codes_have_stable_severity_and_summary() -> None:
    for code, (severity, summary) in CODES.items():
        assert code == code.lower() and " " not in code
        assert isinstance(severity, Severity)
        assert summary.endswith(".")


def test_unknown_type_suggests_a_close_name() -> None:
    comp = compile_file(DATA / "invalid" / "unknown-type_typo.iface")
    d = next(d for d in comp.diagnostics if d.code == "unknown-type" and "Pos'" in d.message)
    assert d.data["suggestions"] == ["Pose"]
    assert "did you mean 'Pose'" in d.message


def test_include_cycle_is_reported_once_per_file_and_terminates() -> None:
    comp = compile_file(DATA / "invalid" / "include-cycle_a.iface")
    codes = [(Path(d.path).name, d.code) for d in comp.all_diagnostics()]
    assert ("include-cycle_b.iface", "include-cycle") in codes


def test_related_locations_point_at_the_first_definition() -> None:
    comp = compile_file(DATA / "invalid" / "duplicate-definition_struct.iface")
    (d,) = [d for d in comp.diagnostics if d.code == "duplicate-definition"]
    (rel,) = d.related
    assert rel.source.position(rel.span.start) == (0, 7)
