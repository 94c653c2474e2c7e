"""``iface-lsp sign DIR --key KEY``, ``--verify DIR --trust-store STORE``, ``--keygen KEY``: trust in component packages."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..operate.trust import SIGNATURE_FILE, TrustError, keygen, sign, verify


def add_arguments(p: argparse.ArgumentParser) -> None:
    """Declare the command's arguments."""
    p.add_argument("folder", metavar="DIR", nargs="?", type=Path,
                   help=f"a component package folder: {SIGNATURE_FILE} is written into it")
    p.add_argument("--key", type=Path, metavar="KEY", help="the ed25519 private key (PEM) to sign with")
    p.add_argument("--keygen", type=Path, metavar="KEY",
                   help="write a new private key to KEY (mode 0600) and its public key to KEY.pub")
    p.add_argument("--verify", action="store_true", help="check DIR's signature against --trust-store")
    p.add_argument("--trust-store", type=Path, metavar="STORE", help="a folder of trusted public keys (*.pub)")


def run(args: argparse.Namespace) -> int:
    """Exit 0 done (or trusted), 1 when --verify finds a problem, 2 on a usage or key error."""
    try:
        if args.keygen is not None:
            pub, kid = keygen(args.keygen)
            print(f"wrote {args.keygen} (private, keep it secret) and {pub} (public; copy it into trust stores): {kid}")
            return 0
        if args.folder is None:
            print("iface-lsp sign: name a package folder (or --keygen KEY)", file=sys.stderr)
            return 2
        if args.verify:
            if args.trust_store is None:
                print("iface-lsp sign: --verify needs --trust-store STORE", file=sys.stderr)
                return 2
            problems = verify(args.folder, args.trust_store)
            for p in problems:
                print(p)
            if not problems:
                print(f"trusted: {args.folder}")
            return 1 if problems else 0
        if args.key is None:
            print("iface-lsp sign: --key KEY is needed to sign (create one with --keygen KEY)", file=sys.stderr)
            return 2
        doc = sign(args.folder, args.key)
        print(f"signed {len(doc['files'])} files of {args.folder} with {doc['key_id']}: "
              f"{args.folder / SIGNATURE_FILE}")
        return 0
    except TrustError as e:
        print(f"iface-lsp sign: {e}", file=sys.stderr)
        return 2
