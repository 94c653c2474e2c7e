"""The IDL oracles themselves: Fast-DDS-Gen's runs kept in the test cache by the content they read."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from . import idl_oracle
from .idl_oracle import FASTDDSGEN, NO_FASTDDSGEN

GOOD = "module m { struct Reading { long value; }; };\n"


@pytest.fixture
def runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> list[Path]:
    """A cache of this test's own; the roots the generator really ran over, in order."""
    monkeypatch.setenv("IFACE_TEST_CACHE", str(tmp_path / "cache"))
    ran: list[Path] = []
    real = idl_oracle._run_fastddsgen

    def counted(root: Path, files: list[Path], out: Path) -> subprocess.CompletedProcess[str]:
        ran.append(root)
        return real(root, files, out)

    monkeypatch.setattr(idl_oracle, "_run_fastddsgen", counted)
    return ran


@pytest.mark.skipif(FASTDDSGEN is None, reason=NO_FASTDDSGEN)
def test_fastddsgen_runs_once_per_content_and_a_failed_run_is_never_kept(tmp_path: Path, runs: list[Path]) -> None:
    root = tmp_path / "idl"
    (root / "m").mkdir(parents=True)
    (root / "m" / "Reading.idl").write_text(GOOD)
    top = tmp_path / "top.idl"
    top.write_text('#include "m/Reading.idl"\n')
    for n in (1, 2):
        proc = idl_oracle.fastddsgen(root, [top], tmp_path / f"gen{n}")
        assert proc.returncode == 0, proc.stdout + proc.stderr
        assert '#include "m/Reading.h"' in (tmp_path / f"gen{n}" / "top.h").read_text()
    assert len(runs) == 1  # the second answer came from the cache, its files copied out

    (root / "m" / "Reading.idl").write_text(GOOD.replace("long value", "long long value"))
    assert idl_oracle.fastddsgen(root, [top], tmp_path / "gen3").returncode == 0
    assert len(runs) == 2  # an included file changed: another key

    (root / "m" / "Reading.idl").write_text(GOOD.replace("long value;", "long value"))  # a syntax error
    for n in (4, 5):
        proc = idl_oracle.fastddsgen(root, [top], tmp_path / f"gen{n}")
        assert proc.returncode != 0 or "error" in proc.stdout.lower(), proc.stdout + proc.stderr
    assert len(runs) == 4  # each failing run is run again
