"""Work done progress (``$/progress``) of server-initiated work, when the client can show it."""

from __future__ import annotations

import asyncio
import itertools
import logging
from typing import TYPE_CHECKING

from lsprotocol import types as lsp

if TYPE_CHECKING:
    from pygls.lsp.server import LanguageServer

log = logging.getLogger("iface.lsp")
_TOKENS = itertools.count(1)
#: How long to wait for the client to accept a progress token before working without one.
CREATE_TIMEOUT = 10.0


class Progress:
    """One piece of work shown to the user: ``begin``, ``report`` as it goes, ``end``.

    Nothing is sent when the client does not announce ``window.workDoneProgress``
    or refuses the token.
    """

    def __init__(self, server: LanguageServer, title: str) -> None:
        self.server = server
        self.title = title
        self.token: str | None = None
        self._shown = -1

    def supported(self) -> bool:
        """True when the client shows server-initiated progress."""
        window = self.server.client_capabilities.window
        return bool(window is not None and window.work_done_progress)

    async def begin(self, total: int) -> None:
        """Ask the client for a token, then say the work began."""
        if not self.supported():
            return
        token = f"iface-{self.title.split()[0].lower()}-{next(_TOKENS)}"
        try:
            await asyncio.wait_for(self.server.work_done_progress.create_async(token), CREATE_TIMEOUT)
        except Exception as e:  # a refusal or no answer: the work goes on without progress
            log.info("no progress for %s: %s", self.title, e)
            return
        self.token = token
        self.server.work_done_progress.begin(token, lsp.WorkDoneProgressBegin(
            title=self.title, cancellable=False, message=f"0/{total} files", percentage=0))

    def report(self, done: int, total: int) -> None:
        """Say how far the work is (at most once per percent)."""
        if self.token is None or total <= 0:
            return
        percent = done * 100 // total
        if percent == self._shown:
            return
        self._shown = percent
        self.server.work_done_progress.report(self.token, lsp.WorkDoneProgressReport(
            message=f"{done}/{total} files", percentage=percent))

    def end(self, message: str) -> None:
        """Say the work is done."""
        if self.token is None:
            return
        self.server.work_done_progress.end(self.token, lsp.WorkDoneProgressEnd(message=message))
        self.server.work_done_progress.tokens.pop(self.token, None)  # pygls keeps every token (its issue #607)
        self.token = None
