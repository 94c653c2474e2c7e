"""Try the checker on the shared corpus of real interface files (not part of the tests).

    python scripts/try_corpus.py [CORPUS_DIR]

Prints one line per Thrift file that does not check cleanly and a summary
"N of M Thrift files check without error"; BrokenConstants.thrift is expected
to fail on line 21. Exit 1 when anything else fails.
"""

from __future__ import annotations

import sys
from pathlib import Path

from iface.model.diagnostics import Severity
from iface.semantics.compile import Workspace


def main() -> int:
    root = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parents[2] / "shared" / "corpus")
    files = sorted((root / "thrift").rglob("*.thrift"))
    if not files:
        print(f"no Thrift files under {root}", file=sys.stderr)
        return 2
    ws = Workspace()
    clean = 0
    unexpected = 0
    for f in files:
        errors = [d for d in ws.compile_path(str(f)).all_diagnostics() if d.severity == Severity.ERROR]
        if not errors:
            clean += 1
            continue
        expected = f.name == "BrokenConstants.thrift" and [d.location()[0] for d in errors] == [21]
        unexpected += not expected
        tag = "expected" if expected else "UNEXPECTED"
        for d in errors:
            print(f"{tag}: {d.format()}")
    print(f"{clean} of {len(files)} Thrift files check without error")
    return 1 if unexpected else 0


if __name__ == "__main__":
    sys.exit(main())
