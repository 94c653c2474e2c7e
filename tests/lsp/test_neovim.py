"""A real editor: headless Neovim as the client of ``python -m iface --stdio``.

Debian's ``neovim`` (0.7) has no ``vim.lsp.start``: the Lua client uses
``start_client`` + ``buf_attach_client`` there and ``vim.lsp.start`` on 0.8+.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(shutil.which("nvim") is None,
                                reason="nvim is not on PATH (apt-get install neovim)")

HERE = Path(__file__).parent


def test_neovim_gets_diagnostics_hover_and_completion(tmp_path: Path) -> None:
    source = tmp_path / "broken.iface"
    shutil.copy(HERE / "data" / "broken.iface", source)
    out = tmp_path / "result.json"
    env = {**os.environ, "IFACE_FILE": str(source), "IFACE_OUT": str(out), "IFACE_PYTHON": sys.executable}
    subprocess.run(["nvim", "--headless", "--clean", "-n", "-c", f"luafile {HERE / 'nvim_client.lua'}"],
                   env=env, cwd=tmp_path, timeout=120, check=False, stdin=subprocess.DEVNULL,
                   capture_output=True)
    result = json.loads(out.read_text())
    assert "error" not in result, result.get("error")
    codes = {d["code"] for d in result["diagnostics"]}
    assert "unknown-type" in codes and "duplicate-definition" in codes
    typo = next(d for d in result["diagnostics"] if "flaot64" in d["message"])
    assert (typo["lnum"], typo["col"]) == (3, 4)
    assert "**message** `Reading`" in result["hover"]
    assert {"float64", "u8", "Reading"} <= set(result["completion"])
