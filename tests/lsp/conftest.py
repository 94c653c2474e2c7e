"""Fixtures: one server per client profile (VS Code and Neovim capabilities) for the whole run.

The servers work on a copy of ``data/`` so that tests may write files.
"""

from __future__ import annotations

import shutil
from collections.abc import AsyncIterator
from pathlib import Path

import pytest
import pytest_lsp

from .harness import CONFIG, DATA, PROFILES, Client, start


@pytest.fixture(scope="session")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A writable copy of the test data."""
    root = tmp_path_factory.mktemp("ws")
    shutil.copytree(DATA, root, dirs_exist_ok=True)
    return root


@pytest_lsp.fixture(config=CONFIG, params=PROFILES, scope="session")
async def client(lsp_client: Client, request: pytest.FixtureRequest, workspace: Path) -> AsyncIterator[None]:
    """One server per client profile for the whole run (tests open their own documents)."""
    await start(lsp_client, workspace, request.param)
    yield
    await lsp_client.shutdown_session()
