"""The language server: ``iface-lsp --stdio`` or ``--tcp HOST:PORT``.

Handlers are thin: each feature module registers its handlers on the server
and answers from the shared model through ``project.Project``. Only the
capabilities of registered handlers are advertised (pygls builds them from
the registered features).
"""

from __future__ import annotations

import logging
import sys
from collections.abc import Generator
from functools import partial
from typing import Any

from lsprotocol import types as lsp
from pygls.exceptions import JsonRpcException, JsonRpcInvalidRequest, JsonRpcServerNotInitialized
from pygls.lsp.server import LanguageServer
from pygls.protocol import LanguageServerProtocol, lsp_method

from .. import __version__
from ..live.stdout import real_stdout_for_good
from .convert import ENCODINGS, UTF16
from .project import Project

log = logging.getLogger("iface.lsp")

#: Feature modules, each with ``register(server)``.
FEATURES = (
    "configuration", "diagnostics", "hover", "completion", "navigation", "rename", "symbols", "folding",
    "selection", "semantic_tokens", "formatting", "code_actions", "code_lens", "commands",
)


class Refusal(JsonRpcException):
    """A JSON-RPC error that is the answer to a request, not a failure of the server (a rename where there is
    no name, a command asked with a wrong argument): the client gets the error, the log one line at info
    level; no traceback, no error in the client's log. Mixed with the error class that gives its code."""


class IfaceProtocol(LanguageServerProtocol):
    """pygls' protocol, with UTF-32 positions when offered and a reply to requests it cannot read."""

    @lsp_method(lsp.INITIALIZE)
    def lsp_initialize(self, params: lsp.InitializeParams) -> Generator[Any, Any, lsp.InitializeResult]:
        """Prefer UTF-32 positions (no conversion needed), then the client's own order."""
        general = params.capabilities.general
        offered = list(general.position_encodings or []) if general is not None else []
        if lsp.PositionEncodingKind.Utf32 in offered and general is not None:
            general.position_encodings = [lsp.PositionEncodingKind.Utf32]
        result = yield from super().lsp_initialize(params)
        self.initialized = True
        chosen = result.capabilities.position_encoding or lsp.PositionEncodingKind.Utf16
        server = self._server
        assert isinstance(server, IfaceServer)
        # lsprotocol types the choice as PositionEncodingKind | str; its members are str and hash as their value
        by_kind: dict[str, str] = {v: k for k, v in ENCODINGS.items()}
        server.project.encoding = by_kind.get(chosen, UTF16)
        return result

    # The project keeps its own documents (LSP line breaks, code point offsets),
    # so pygls' copies, re-split on every change, are not kept.
    @lsp_method(lsp.TEXT_DOCUMENT_DID_OPEN)
    def lsp_text_document__did_open(self, params: lsp.DidOpenTextDocumentParams) -> Generator[Any, Any, None]:
        """Hand the document to the user handler only."""
        if (handler := self.fm.features.get(lsp.TEXT_DOCUMENT_DID_OPEN)) is not None:
            yield handler, (params,), None

    @lsp_method(lsp.TEXT_DOCUMENT_DID_CHANGE)
    def lsp_text_document__did_change(self, params: lsp.DidChangeTextDocumentParams) -> Generator[Any, Any, None]:
        """Hand the change to the user handler only."""
        if (handler := self.fm.features.get(lsp.TEXT_DOCUMENT_DID_CHANGE)) is not None:
            yield handler, (params,), None

    @lsp_method(lsp.TEXT_DOCUMENT_DID_CLOSE)
    def lsp_text_document__did_close(self, params: lsp.DidCloseTextDocumentParams) -> Generator[Any, Any, None]:
        """Hand the closing to the user handler only."""
        if (handler := self.fm.features.get(lsp.TEXT_DOCUMENT_DID_CLOSE)) is not None:
            yield handler, (params,), None

    #: Set once ``initialize`` has been answered; before it only ``initialize`` and ``exit`` are served.
    initialized = False

    def handle_message(self, message: Any) -> None:
        """LSP's rules around the session: a request before ``initialize`` gets -32002 (ServerNotInitialized),
        one after ``shutdown`` gets InvalidRequest; notifications then are dropped, ``exit`` always works."""
        method = getattr(message, "method", None)
        is_request = method is not None and getattr(message, "id", None) is not None
        if method == lsp.EXIT or (not self.initialized and method == lsp.INITIALIZE and not self._shutdown):
            super().handle_message(message)
            return
        if self._shutdown and method is not None:
            if is_request:
                self._send_response(message.id, None, JsonRpcInvalidRequest(
                    f"the server is shut down: only 'exit' is accepted, not '{method}'").to_response_error())
            return
        if not self.initialized and method is not None:
            if is_request:
                self._send_response(message.id, None, JsonRpcServerNotInitialized(
                    f"'{method}' before 'initialize': send 'initialize' first").to_response_error())
            return
        super().handle_message(message)

    def _send_handler_result(self, future: Any, *, msg_id: Any) -> None:
        """Send a handler's result as pygls does; a ``Refusal`` is sent as the error it is, logged as an answer."""
        refused = None if future.cancelled() else future.exception()
        if not isinstance(refused, Refusal):
            super()._send_handler_result(future, msg_id=msg_id)
            return
        self._request_futures.pop(msg_id, None)
        log.info("refused: %s", refused)
        self._send_response(msg_id, error=refused.to_response_error())

    def _execute_handler(self, msg_id: Any, *args: Any, **kwargs: Any) -> None:
        """Run a handler as pygls does, then forget its future once done.

        pygls keeps the future of a generator, coroutine or threaded handler in ``_request_futures``
        until it sends the response; a notification (its id a fresh uuid) has none, so every
        didOpen, didChange and didClose left one future behind: memory grew with every keystroke.
        """
        super()._execute_handler(msg_id, *args, **kwargs)
        future = self._request_futures.get(msg_id)
        if future is not None:
            future.add_done_callback(partial(self._forget_future, msg_id))

    def _forget_future(self, msg_id: Any, done: Any) -> None:
        if self._request_futures.get(msg_id) is done:
            self._request_futures.pop(msg_id, None)

    def structure_message(self, data: dict[str, Any]) -> Any:
        """Read a message; a request whose parameters cannot be read is answered with an error."""
        try:
            return super().structure_message(data)
        except JsonRpcException as e:
            if isinstance(data, dict) and "id" in data and "method" in data:
                self._send_response(data["id"], None, e.to_response_error())
            raise


class IfaceServer(LanguageServer):
    """The iface language server."""

    def __init__(self) -> None:
        super().__init__("iface-lsp", __version__, text_document_sync_kind=lsp.TextDocumentSyncKind.Incremental,
                         protocol_cls=IfaceProtocol)
        self.project = Project(self.publish)

    def publish(self, uri: str, version: int | None, diagnostics: list[lsp.Diagnostic]) -> None:
        """Send diagnostics of one document."""
        self.text_document_publish_diagnostics(
            lsp.PublishDiagnosticsParams(uri=uri, diagnostics=diagnostics, version=version))

    def report_server_error(self, error: Exception, source: Any) -> None:
        """Log failures (handlers already answered with an error); never pop up a message per failure."""
        log.error("%s: %s", getattr(source, "__name__", source), error)
        try:
            self.window_log_message(lsp.LogMessageParams(type=lsp.MessageType.Error, message=f"iface: {error}"))
        except Exception:  # the connection itself may be what failed
            pass

    def log_info(self, message: str) -> None:
        """A message for the client's log."""
        self.window_log_message(lsp.LogMessageParams(type=lsp.MessageType.Info, message=message))


def build() -> IfaceServer:
    """A server with every feature registered."""
    import importlib

    server = IfaceServer()
    for name in FEATURES:
        importlib.import_module(f"{__package__}.features.{name}").register(server)
    return server


def serve(tcp: str | None = None) -> int:
    """Run the server on stdio, or on ``HOST:PORT``; returns the exit code."""
    logging.basicConfig(level=logging.WARNING, stream=sys.stderr, format="iface-lsp %(levelname)s: %(message)s")
    # a request must not wait long for the model thread to hand over the interpreter
    sys.setswitchinterval(0.001)
    server = build()
    if tcp is None:
        # the messages go to the real stdout; what anything else writes there (Fast DDS's log, while a command
        # reads the ROS graph) goes to stderr
        out = real_stdout_for_good()
        if out is None or sys.stdin is None:
            if sys.stderr is not None:
                print("iface-lsp: --stdio needs standard input, output and error open", file=sys.stderr)
            return 2
        server.start_io(sys.stdin.buffer, out)
        return 0
    host, sep, port = tcp.rpartition(":")
    if not sep or not port.isdigit():
        print(f"iface-lsp: --tcp needs HOST:PORT, not {tcp!r}", file=sys.stderr)
        return 2
    server.start_tcp(host or "127.0.0.1", int(port))
    return 0

