"""The canonical hash: equal exactly when compat says equivalent; the manifest."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from compat_support import DATA, cached, run_main

from iface.compat import compare, interface_hash


def _pairs() -> list[tuple[Path, Path]]:
    pairs = []
    for folder in ("rules", "thrift"):
        for case in sorted(p for p in (DATA / folder).iterdir() if p.is_dir()):
            pairs.append((next(case.glob("old.*")), next(case.glob("new.*"))))
    verdicts = sorted((DATA / "verdicts").glob("*.iface"))
    pairs += [(a, b) for a in verdicts for b in verdicts]
    return pairs


PAIRS = _pairs()


@pytest.mark.parametrize(("old", "new"), PAIRS, ids=[f"{a.parent.name}/{a.name}-{b.name}" for a, b in PAIRS])
def test_hash_equal_iff_equivalent(old: Path, new: Path) -> None:
    a, b = cached(old), cached(new)
    verdict = compare(a, b).verdict
    assert (interface_hash(a) == interface_hash(b)) == (verdict == "equivalent")


def test_equivalence_is_symmetric_on_fixtures() -> None:
    for old, new in PAIRS[:40]:
        a, b = cached(old), cached(new)
        assert (compare(a, b).verdict == "equivalent") == (compare(b, a).verdict == "equivalent")


def test_hash_cli_ignores_comments_and_layout() -> None:
    one = run_main("hash", "verdicts/arm_v1.iface")
    two = run_main("hash", "verdicts/arm_v1_relaid.iface")
    three = run_main("hash", "verdicts/arm_v2.iface")
    assert one.returncode == two.returncode == three.returncode == 0
    assert one.stdout == two.stdout != three.stdout
    assert one.stdout.startswith("sha256:") and len(one.stdout.strip()) == len("sha256:") + 64


def test_manifest_sign_and_verify(tmp_path: Path) -> None:
    key = tmp_path / "key"
    key.write_bytes(b"s3cret")
    signed = run_main("hash", "verdicts/arm_v1.iface", "--manifest", "--key", str(key))
    assert signed.returncode == 0
    manifest = json.loads(signed.stdout)
    assert manifest["component"] == "arm" and manifest["signature"]["algorithm"] == "hmac-sha256"
    assert [f["path"] for f in manifest["files"]] == ["arm_v1.iface"]
    path = tmp_path / "arm.manifest.json"
    path.write_text(signed.stdout)
    ok = run_main("hash", "verdicts/arm_v1_relaid.iface", "--verify", str(path), "--key", str(key))
    assert ok.returncode == 0 and "matches" in ok.stdout
    other = run_main("hash", "verdicts/arm_v2.iface", "--verify", str(path), "--key", str(key))
    assert other.returncode == 1 and "interface hash" in other.stderr
    key.write_bytes(b"other")
    forged = run_main("hash", "verdicts/arm_v1.iface", "--verify", str(path), "--key", str(key))
    assert forged.returncode == 1 and "signature does not match" in forged.stderr
    nokey = run_main("hash", "verdicts/arm_v1.iface", "--verify", str(path))
    assert nokey.returncode == 1 and "give --key" in nokey.stderr


def test_other_change_safety_net(monkeypatch: pytest.MonkeyPatch) -> None:
    """A canonical difference that no rule names still prevents 'equivalent'."""
    import iface.compat as compat
    a = cached(DATA / "verdicts" / "arm_v1.iface")
    b = cached(DATA / "verdicts" / "arm_v1_relaid.iface")
    real = compat.canonical
    monkeypatch.setattr(compat, "canonical", lambda c: dict(real(c), marker=c.path))
    report = compat.compare(a, b)
    assert [f.rule for f in report.findings] == ["other-change"]
    assert report.verdict == "replaceable" and "/marker" in report.findings[0].subject
