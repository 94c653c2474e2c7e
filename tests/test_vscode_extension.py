"""The VS Code extension (vscode-extension/): its own test suite and the real-editor e2e.

``npm test`` type-checks the TypeScript, bundles it with esbuild, runs the unit
tests, packages the .vsix with vsce and runs the TextMate grammar tests.
The e2e (``npm run e2e``) installs the .vsix into code-server and drives it with
headless Chromium; it is slow and needs Debian's chromium, so it runs only with
IFACE_E2E=1.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXTENSION = ROOT / "vscode-extension"


def _npm() -> str:
    npm = shutil.which("npm")
    if npm is None:
        pytest.skip("npm is not on PATH: the VS Code extension needs Node 20 and npm to build and test")
    return npm


def _run(args: list[str], timeout: int) -> subprocess.CompletedProcess[str]:
    return subprocess.run(args, cwd=EXTENSION, capture_output=True, text=True, timeout=timeout)


def _ensure_node_modules(npm: str) -> None:
    if not (EXTENSION / "node_modules").is_dir():
        result = _run([npm, "ci", "--no-audit", "--no-fund"], timeout=900)
        assert result.returncode == 0, f"npm ci failed:\n{result.stdout[-4000:]}\n{result.stderr[-4000:]}"


def test_npm_test() -> None:
    """Type-check, bundle, unit tests, vsce package and grammar tests all pass."""
    npm = _npm()
    _ensure_node_modules(npm)
    result = _run([npm, "test"], timeout=900)
    assert result.returncode == 0, f"npm test failed:\n{result.stdout[-6000:]}\n{result.stderr[-4000:]}"
    vsix = EXTENSION / "dist" / "iface.vsix"
    assert vsix.is_file()
    with zipfile.ZipFile(vsix) as z:
        names = set(z.namelist())
    # the graph panel's script and style travel in the package: the webview loads nothing from elsewhere
    assert {"extension/dist/extension.js", "extension/dist/webview/graph.js", "extension/media/graph.css"} <= names
    assert not any("node_modules" in n or n.endswith(".ts") for n in names)


def test_graph_fixture_of_the_unit_tests_is_what_the_server_answers() -> None:
    """vscode-extension/test/unit/fixtures/system-graph.json is `iface-lsp graph --format json` of the
    compat system fixtures: the extension's unit tests read the server's real, current data."""
    files = [f"tests/compat/data/system/{n}.iface" for n in ("camera", "detector", "logger")]
    done = subprocess.run([sys.executable, "-m", "iface", "graph", *files, "--format", "json"], cwd=ROOT,
                          capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 1, done.stderr  # the fixtures have conflicts on purpose
    fixture = EXTENSION / "test" / "unit" / "fixtures" / "system-graph.json"
    assert json.loads(done.stdout) == json.loads(fixture.read_text(encoding="utf-8")), (
        f"regenerate it: iface-lsp graph {' '.join(files)} --format json > {fixture.relative_to(ROOT)}")


#: The step whose first attempt the e2e run fails (``--fail-once``), to show that it is tried once more.
FAIL_ONCE = "compatibility-command-shows-the-report"


@pytest.fixture(scope="module")
def e2e_run() -> subprocess.CompletedProcess[str]:
    """One ``npm run e2e`` (real VS Code in code-server, headless Chromium) with ``--fail-once=FAIL_ONCE``: every
    step is checked, that one also when it is tried again (one editor run for both tests below)."""
    if os.environ.get("IFACE_E2E") != "1":
        pytest.skip("set IFACE_E2E=1 to run the VS Code end-to-end test")
    npm = _npm()
    _ensure_node_modules(npm)
    artifacts = EXTENSION / "e2e" / "artifacts"
    for old in [*artifacts.glob(f"failed-{FAIL_ONCE}*"), artifacts / "iface-e2e.png"]:
        old.unlink(missing_ok=True)
    return _run([npm, "run", "e2e", "--", f"--fail-once={FAIL_ONCE}"], timeout=2400)


@pytest.mark.e2e
def test_vscode_e2e(e2e_run: subprocess.CompletedProcess[str]) -> None:
    """The extension in real VS Code (code-server) with headless Chromium: every step passes, each at its first
    attempt but the one ``--fail-once`` fails.

    IFACE_E2E_SERVER picks the language server: auto (default; iface-lsp from
    PATH, server checks skipped without it), real, mock or none.
    """
    output = e2e_run.stdout + e2e_run.stderr
    assert e2e_run.returncode == 0, f"npm run e2e failed:\n{output[-8000:]}"
    assert " 0 failed" in output and output.count("(passed when tried again)") == 1, output[-8000:]
    assert (EXTENSION / "e2e" / "artifacts" / "iface-e2e.png").is_file()


@pytest.mark.e2e
def test_vscode_a_failed_step_is_tried_once_more_and_its_evidence_kept_and_named(
        e2e_run: subprocess.CompletedProcess[str]) -> None:
    """--fail-once=STEP fails the step's first attempt: it passes when tried again from a reset workbench,
    and the screenshot, code-server's log and the language server's log of the failure are kept and named."""
    output = e2e_run.stdout + e2e_run.stderr
    assert e2e_run.returncode == 0, f"npm run e2e failed:\n{output[-8000:]}"
    assert "PASS  compatibility command shows the report" in output and "(passed when tried again)" in output
    artifacts = EXTENSION / "e2e" / "artifacts"
    kept = [artifacts / f"failed-{FAIL_ONCE}{suffix}" for suffix in (".png", "-code-server.log", "-iface-lsp.log")]
    tried_again = next(line for line in output.splitlines() if "trying once more. Kept:" in line)
    for path in kept:
        assert path.is_file() and path.stat().st_size > 0, path
        assert str(path) in tried_again, tried_again
    assert kept[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    server_log = kept[2].read_text(encoding="utf-8", errors="replace")
    assert "no iface output channel log was written" not in server_log and "iface-lsp" in server_log, server_log
