"""Benchmark clients: accept the server's ``$/progress`` (work done) reports and hear each one's kind."""

from __future__ import annotations

from collections.abc import Callable

from lsprotocol import types as lsp
from pygls.lsp.client import LanguageClient


def on_progress(client: LanguageClient, heard: Callable[[str], None]) -> None:
    """Answer ``window/workDoneProgress/create`` and call ``heard`` with each report's kind (begin, report, end)."""

    @client.feature(lsp.WINDOW_WORK_DONE_PROGRESS_CREATE)
    def create(params: lsp.WorkDoneProgressCreateParams) -> None:
        return None

    @client.feature(lsp.PROGRESS)
    def progress(params: lsp.ProgressParams) -> None:
        value = params.value
        heard(str(value.get("kind", "?") if isinstance(value, dict) else getattr(value, "kind", "?")))
