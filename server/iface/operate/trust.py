"""Trust in a component package: ed25519 signatures over the digests of its files.

``sign(folder, key)`` writes ``folder/iface-signature.json``::

    {"format": "iface-signature/1", "algorithm": "ed25519", "key_id": "sha256:…",
     "files": {"relative/path": "sha256:…", …}, "signature": "<base64>"}

The signature covers the canonical JSON of everything but ``signature`` (keys sorted, no
spaces), so it covers each file's path and digest, the key id and the format. Python's byte-code
caches (``__pycache__``, ``*.pyc``) are left out: running a package writes them. ``verify(folder,
store)`` checks the file against a *trust store*, a folder of public keys (``*.pub``, PEM), and
says what is wrong: no signature, a key the store does not hold, a bad signature, a file
changed, added or removed since signing.

Keys are PEM files: ``keygen(path)`` writes the private key to ``path`` (mode 0600) and the public
key to ``path.pub``; copy the ``.pub`` into the trust store of each machine that should load
packages signed with it.
"""

from __future__ import annotations

import base64
import hashlib
import json
import os
from pathlib import Path
from typing import Any

SIGNATURE_FILE = "iface-signature.json"
FORMAT = "iface-signature/1"
_SKIPPED_DIRS = {"__pycache__"}


class TrustError(Exception):
    """A key or package cannot be used: the message says why."""


def _crypto() -> Any:
    try:
        from cryptography.hazmat.primitives import serialization
        from cryptography.hazmat.primitives.asymmetric import ed25519
    except ImportError as e:  # pragma: no cover - a dependency of iface
        raise TrustError(f"signing needs the 'cryptography' package ({e}): pip install cryptography") from e
    return serialization, ed25519


def _digest(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return "sha256:" + h.hexdigest()


def digests(folder: Path) -> dict[str, str]:
    """``sha256:`` digest of every file under ``folder`` (POSIX relative paths), but the signature and caches.

    Every file of an install tree counts: scripts, executables, shared libraries. A symbolic link
    (a library's ``libx.so`` → ``libx.so.1``, or every file of a ``colcon --symlink-install``) counts
    as the content it leads to, under its own path, and a linked folder is walked (each real folder
    once); a link that leads nowhere is recorded as ``link:<target>``, so retargeting any link shows.
    """
    out: dict[str, str] = {}
    seen: set[str] = set()
    for root, dirs, files in os.walk(folder, followlinks=True):
        real = os.path.realpath(root)
        if real in seen:
            dirs[:] = []
            continue
        seen.add(real)
        dirs[:] = sorted(d for d in dirs if d not in _SKIPPED_DIRS)
        for name in sorted(files):
            path = Path(root) / name
            rel = path.relative_to(folder).as_posix()
            if rel == SIGNATURE_FILE or name.endswith(".pyc"):
                continue
            if path.is_file():
                out[rel] = _digest(path)
            elif path.is_symlink():
                out[rel] = "link:" + os.readlink(path)
    return out


def _canonical(doc: dict[str, Any]) -> bytes:
    body = {k: v for k, v in doc.items() if k != "signature"}
    return json.dumps(body, sort_keys=True, separators=(",", ":"), ensure_ascii=False).encode("utf-8")


def _public_bytes(public: Any) -> bytes:
    serialization, _ = _crypto()
    return public.public_bytes(serialization.Encoding.Raw, serialization.PublicFormat.Raw)


def key_id(public: Any) -> str:
    """A public key's id: the digest of its raw bytes."""
    return "sha256:" + hashlib.sha256(_public_bytes(public)).hexdigest()


def keygen(path: Path) -> tuple[Path, str]:
    """Write a new private key to ``path`` (0600) and its public key to ``path.pub``; the public path and key id."""
    serialization, ed25519 = _crypto()
    if path.exists():
        raise TrustError(f"{path} exists: not overwritten")
    key = ed25519.Ed25519PrivateKey.generate()
    private = key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                                serialization.NoEncryption())
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(fd, "wb") as f:
        f.write(private)
    pub = Path(str(path) + ".pub")
    pub.write_bytes(key.public_key().public_bytes(serialization.Encoding.PEM,
                                                  serialization.PublicFormat.SubjectPublicKeyInfo))
    return pub, key_id(key.public_key())


def _load_private(path: Path) -> Any:
    serialization, ed25519 = _crypto()
    try:
        key = serialization.load_pem_private_key(path.read_bytes(), password=None)
    except OSError as e:
        raise TrustError(f"cannot read the key {path}: {e.strerror or e}") from e
    except (ValueError, TypeError) as e:
        raise TrustError(f"{path} is not an unencrypted PEM private key ({e})") from e
    if not isinstance(key, ed25519.Ed25519PrivateKey):
        raise TrustError(f"{path} is not an ed25519 key")
    return key


def sign(folder: Path, key_path: Path) -> dict[str, Any]:
    """Sign the files of ``folder`` with the private key at ``key_path``; the signature document written."""
    if not folder.is_dir():
        raise TrustError(f"{folder} is not a folder")
    key = _load_private(key_path)
    doc: dict[str, Any] = {"format": FORMAT, "algorithm": "ed25519", "key_id": key_id(key.public_key()),
                           "files": digests(folder)}
    doc["signature"] = base64.b64encode(key.sign(_canonical(doc))).decode("ascii")
    (folder / SIGNATURE_FILE).write_text(json.dumps(doc, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    return doc


def trusted_keys(store: Path) -> dict[str, Any]:
    """The public keys of a trust store by id."""
    serialization, ed25519 = _crypto()
    if not store.is_dir():
        raise TrustError(f"the trust store {store} is not a folder")
    keys: dict[str, Any] = {}
    for pub in sorted(store.glob("*.pub")):
        try:
            key = serialization.load_pem_public_key(pub.read_bytes())
        except (OSError, ValueError) as e:
            raise TrustError(f"{pub} is not a PEM public key ({e})") from e
        if isinstance(key, ed25519.Ed25519PublicKey):
            keys[key_id(key)] = key
    return keys


def verify(folder: Path, store: Path) -> list[str]:
    """What is wrong with the signature of ``folder`` against the trust store; empty when it is trusted."""
    sig = folder / SIGNATURE_FILE
    if not sig.is_file():
        return [f"{folder} is not signed (no {SIGNATURE_FILE}; sign it with `iface-lsp sign`)"]
    try:
        doc = json.loads(sig.read_text(encoding="utf-8"))
        signature = base64.b64decode(doc["signature"], validate=True)
        files = dict(doc["files"])
        kid = str(doc["key_id"])
    except (OSError, ValueError, KeyError, TypeError) as e:
        return [f"{sig} is not a signature file ({e})"]
    if doc.get("format") != FORMAT or doc.get("algorithm") != "ed25519":
        return [f"{sig}: unknown format {doc.get('format')!r} / algorithm {doc.get('algorithm')!r}"]
    keys = trusted_keys(store)
    key = keys.get(kid)
    if key is None:
        return [f"{folder} is signed with key {kid}, which the trust store {store} does not hold"]
    from cryptography.exceptions import InvalidSignature

    try:
        key.verify(signature, _canonical(doc))
    except InvalidSignature:
        return [f"{folder}: the signature does not match its contents (signed by {kid})"]
    now = digests(folder)
    problems = [f"{folder}/{p}: changed since it was signed" for p in sorted(files) if p in now and now[p] != files[p]]
    problems += [f"{folder}/{p}: removed since it was signed" for p in sorted(files) if p not in now]
    problems += [f"{folder}/{p}: not covered by the signature (added after signing)" for p in sorted(now)
                 if p not in files]
    return problems
