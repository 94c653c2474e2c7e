"""``iface-lsp hash FILE [--manifest] [--key KEYFILE] [--verify MANIFEST]``"""

from __future__ import annotations

import argparse
import json
import sys

from ..compat.canon import interface_hash
from ..compat.manifest import make_manifest, verify_manifest
from .common import UsageError
from .load import load_checked


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("file", metavar="FILE", help="an .iface or .thrift file")
    p.add_argument("--manifest", action="store_true",
                   help="print a JSON manifest (interface hash, file checksums, signature with --key)")
    p.add_argument("--verify", metavar="MANIFEST", help="check FILE against a manifest: exit 0 when it matches")
    p.add_argument("--key", metavar="KEYFILE", help="a file whose bytes are the HMAC-SHA256 key")
    p.add_argument("-I", "--include-path", action="append", default=[], metavar="DIR",
                   help="a folder to search for included files")


def _read_key(path: str | None) -> bytes | None:
    if path is None:
        return None
    try:
        with open(path, "rb") as f:
            key = f.read().strip()
    except OSError as e:
        raise UsageError(f"{path}: cannot read the key ({e.strerror})") from e
    if not key:
        raise UsageError(f"{path}: the key file is empty")
    return key


def run(args: argparse.Namespace) -> int:
    """Print ``sha256:<hex>``; with --verify exit 1 when FILE does not match; 2 on a tool error."""
    try:
        (comp,) = load_checked([args.file], args.include_path, "hash")
        key = _read_key(args.key)
        manifest = None
        if args.verify:
            try:
                with open(args.verify, encoding="utf-8") as f:
                    manifest = json.load(f)
            except (OSError, ValueError) as e:
                raise UsageError(f"{args.verify}: cannot read the manifest ({e})") from e
            if not isinstance(manifest, dict):
                raise UsageError(f"{args.verify}: a manifest is a JSON object")
    except UsageError as e:
        print(f"iface-lsp hash: {e}", file=sys.stderr)
        return 2
    if manifest is not None:
        problems = verify_manifest(manifest, comp, key)
        for p in problems:
            print(f"{args.file}: {p}", file=sys.stderr)
        print(f"{args.file}: {'does not match' if problems else 'matches'} {args.verify}")
        return 1 if problems else 0
    if args.manifest:
        json.dump(make_manifest(comp, key), sys.stdout, indent=2, sort_keys=True, ensure_ascii=False)
        sys.stdout.write("\n")
        return 0
    print(interface_hash(comp))
    return 0
