"""A manifest for trusting a dynamically loaded component: its interface hash, the checksums
of its interface files and, with a shared key, an HMAC-SHA256 signature."""

from __future__ import annotations

import hashlib
import hmac
import json
import os
from typing import Any

from ..semantics.compile import Compilation
from .canon import interface_hash

MANIFEST_ID = "iface-manifest/1"


def _files(comp: Compilation) -> list[dict[str, str]]:
    base = os.path.dirname(os.path.abspath(comp.path))
    out = []
    for c in comp.closure():
        rel = os.path.relpath(os.path.abspath(c.path), base).replace(os.sep, "/")
        out.append({"path": rel, "sha256": hashlib.sha256(c.source.text.encode("utf-8")).hexdigest()})
    return sorted(out, key=lambda f: f["path"])


def _payload(manifest: dict[str, Any]) -> bytes:
    body = {k: v for k, v in manifest.items() if k != "signature"}
    return json.dumps(body, sort_keys=True, separators=(",", ":"), ensure_ascii=False).encode("utf-8")


def make_manifest(comp: Compilation, key: bytes | None = None) -> dict[str, Any]:
    """The manifest of a compiled interface, signed when ``key`` is given."""
    iface = comp.interface
    manifest: dict[str, Any] = {"manifest": MANIFEST_ID, "component": iface.name, "version": iface.version,
                                "interface_hash": interface_hash(comp), "files": _files(comp)}
    if key is not None:
        manifest["signature"] = {"algorithm": "hmac-sha256",
                                 "value": hmac.new(key, _payload(manifest), hashlib.sha256).hexdigest()}
    return manifest


def verify_manifest(manifest: dict[str, Any], comp: Compilation, key: bytes | None = None) -> list[str]:
    """Why ``comp`` does not match a trusted manifest (empty: it matches).

    The interface hash must match; a signed manifest needs the key and a valid
    signature. Changed file bytes with an equal interface hash (comments,
    layout) are accepted.
    """
    problems: list[str] = []
    if manifest.get("manifest") != MANIFEST_ID:
        return [f"not an {MANIFEST_ID} manifest"]
    signature = manifest.get("signature")
    if signature is not None:
        if key is None:
            problems.append("the manifest is signed: give --key to verify it")
        elif not isinstance(signature, dict) or signature.get("algorithm") != "hmac-sha256":
            problems.append("unknown signature algorithm")
        else:
            expected = hmac.new(key, _payload(manifest), hashlib.sha256).hexdigest()
            if not hmac.compare_digest(expected, str(signature.get("value", ""))):
                problems.append("the signature does not match: the manifest was changed or the key differs")
    elif key is not None:
        problems.append("the manifest is not signed, but a key was given")
    actual = interface_hash(comp)
    if manifest.get("interface_hash") != actual:
        problems.append(f"interface hash {actual} differs from the manifest's {manifest.get('interface_hash')}")
    return problems
