"""Signing component packages: ed25519 over the files' digests, checked against a trust store."""

from __future__ import annotations

import json
import stat
import subprocess
from pathlib import Path

import pytest

from iface.operate.trust import SIGNATURE_FILE, TrustError, keygen, sign, verify
from tests.conftest import run_main


@pytest.fixture
def package(tmp_path: Path) -> Path:
    pkg = tmp_path / "pkg"
    (pkg / "counter").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package/>\n")
    (pkg / "counter" / "node.py").write_text("print('hi')\n")
    (pkg / "counter" / "__pycache__").mkdir()
    (pkg / "counter" / "__pycache__" / "node.cpython-311.pyc").write_bytes(b"\0cache")
    return pkg


@pytest.fixture
def store(tmp_path: Path) -> tuple[Path, Path]:
    key = tmp_path / "keys" / "me.key"
    key.parent.mkdir()
    pub, kid = keygen(key)
    assert kid.startswith("sha256:") and stat.S_IMODE(key.stat().st_mode) == 0o600
    trusted = tmp_path / "store"
    trusted.mkdir()
    (trusted / "me.pub").write_bytes(pub.read_bytes())
    return key, trusted


def test_a_signed_package_is_trusted(package: Path, store: tuple[Path, Path]) -> None:
    key, trusted = store
    doc = sign(package, key)
    assert sorted(doc["files"]) == ["counter/node.py", "package.xml"]  # caches are not signed
    assert verify(package, trusted) == []
    (package / "counter" / "__pycache__" / "other.pyc").write_bytes(b"x")  # running it writes caches
    assert verify(package, trusted) == []


def test_changed_added_and_removed_files_are_named(package: Path, store: tuple[Path, Path]) -> None:
    key, trusted = store
    sign(package, key)
    (package / "counter" / "node.py").write_text("print('evil')\n")
    (package / "extra.py").write_text("")
    (package / "package.xml").unlink()
    problems = verify(package, trusted)
    assert any("counter/node.py: changed" in p for p in problems)
    assert any("extra.py: not covered" in p for p in problems)
    assert any("package.xml: removed" in p for p in problems)


def test_unsigned_unknown_key_and_forged_signature_are_refused(package: Path, store: tuple[Path, Path],
                                                                tmp_path: Path) -> None:
    key, trusted = store
    assert "is not signed" in verify(package, trusted)[0]
    other = tmp_path / "other.key"
    keygen(other)
    sign(package, other)
    assert "does not hold" in verify(package, trusted)[0]
    sign(package, key)
    doc = json.loads((package / SIGNATURE_FILE).read_text())
    doc["files"]["counter/node.py"] = "sha256:" + "0" * 64  # a digest changed without the key
    (package / SIGNATURE_FILE).write_text(json.dumps(doc))
    assert "does not match" in verify(package, trusted)[0]


def test_keys_are_never_overwritten_and_bad_keys_are_clear_errors(tmp_path: Path, package: Path) -> None:
    key = tmp_path / "k.key"
    keygen(key)
    with pytest.raises(TrustError, match="exists"):
        keygen(key)
    bad = tmp_path / "bad.key"
    bad.write_text("not a key")
    with pytest.raises(TrustError, match="not an unencrypted PEM private key"):
        sign(package, bad)


def test_the_sign_command(tmp_path: Path, package: Path) -> None:
    def cli(*args: str) -> subprocess.CompletedProcess[str]:
        return run_main("sign", *args)

    key = tmp_path / "ci.key"
    made = cli("--keygen", str(key))
    assert made.returncode == 0 and "ci.key.pub" in made.stdout
    store = tmp_path / "trusted"
    store.mkdir()
    (store / "ci.pub").write_bytes((tmp_path / "ci.key.pub").read_bytes())
    assert cli(str(package), "--verify", "--trust-store", str(store)).returncode == 1
    signed = cli(str(package), "--key", str(key))
    assert signed.returncode == 0 and "signed 2 files" in signed.stdout
    assert cli(str(package), "--verify", "--trust-store", str(store)).returncode == 0
    assert cli(str(package)).returncode == 2  # no key
    missing = cli(str(package), "--key", str(tmp_path / "nope.key"))
    assert missing.returncode == 2 and missing.stderr.count("\n") == 1


def test_links_count_as_what_they_lead_to(tmp_path: Path, store: tuple[Path, Path]) -> None:
    """An install tree's library links and linked folders are signed: retargeting or changing them shows."""
    key, trusted = store
    pkg, elsewhere = tmp_path / "install" / "counter", tmp_path / "build"
    (pkg / "lib" / "counter").mkdir(parents=True)
    elsewhere.mkdir()
    (pkg / "lib" / "counter" / "counter").write_bytes(b"\x7fELF executable")
    (pkg / "lib" / "libcounter.so.1").write_bytes(b"\x7fELF library 1")
    (pkg / "lib" / "libother.so.1").write_bytes(b"\x7fELF library 2")
    (pkg / "lib" / "libcounter.so").symlink_to("libcounter.so.1")
    (elsewhere / "node.py").write_text("print('hi')\n")
    (elsewhere / "loop").symlink_to(elsewhere)  # a link cycle is walked once
    (pkg / "python").symlink_to(elsewhere)  # as colcon --symlink-install links a Python package
    (pkg / "gone").symlink_to("nowhere")
    doc = sign(pkg, key)
    assert sorted(doc["files"]) == ["gone", "lib/counter/counter", "lib/libcounter.so", "lib/libcounter.so.1",
                                    "lib/libother.so.1", "python/node.py"]
    assert doc["files"]["lib/libcounter.so"] == doc["files"]["lib/libcounter.so.1"]
    assert doc["files"]["gone"] == "link:nowhere"
    assert verify(pkg, trusted) == []
    (pkg / "lib" / "libcounter.so").unlink()
    (pkg / "lib" / "libcounter.so").symlink_to("libother.so.1")
    (elsewhere / "node.py").write_text("print('evil')\n")
    problems = verify(pkg, trusted)
    assert [p.split("/counter/", 1)[1] for p in problems] == ["lib/libcounter.so: changed since it was signed",
                                                              "python/node.py: changed since it was signed"]
