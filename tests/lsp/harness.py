"""End-to-end harness: the real server over stdio (``python -m iface --stdio``), driven by pytest-lsp.

``Client`` records every publishDiagnostics, so tests wait for the
diagnostics of a version instead of sleeping.
"""

from __future__ import annotations

import asyncio
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, Union

from lsprotocol import types as lsp
from pygls.protocol import default_converter
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities
from pytest_lsp.client import DEFAULT_CLIENT_FEATURES, register_lsp_features

DATA = Path(__file__).parent / "data"
PROFILES = ("visual-studio-code", "neovim")
SERVER = [sys.executable, "-m", "iface", "--stdio"]
TIMEOUT = 30.0


class Client(LanguageClient):
    """A pytest-lsp client that keeps every publishDiagnostics it receives."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.published: list[lsp.PublishDiagnosticsParams] = []
        self.arrived = asyncio.Event()
        self.root: Path = DATA
        self.profile = ""
        self.versions: dict[str, int] = {}
        self.texts: dict[str, str] = {}

    # ---- documents --------------------------------------------------------------
    def uri(self, name: str) -> str:
        """The URI of a file of the test workspace."""
        return (self.root / name).as_uri()

    def open(self, name: str, text: str | None = None) -> str:
        """Open a workspace file (or ``text`` under its name); returns its URI."""
        uri = self.uri(name)
        body = (self.root / name).read_text(encoding="utf-8") if text is None else text
        self.versions[uri] = 1
        self.texts[uri] = body
        self.text_document_did_open(lsp.DidOpenTextDocumentParams(
            lsp.TextDocumentItem(uri=uri, language_id="iface", version=1, text=body)))
        return uri

    def replace(self, uri: str, text: str) -> int:
        """Send the whole new text; returns the new version."""
        version = self.versions[uri] + 1
        self.versions[uri] = version
        self.texts[uri] = text
        self.text_document_did_change(lsp.DidChangeTextDocumentParams(
            lsp.VersionedTextDocumentIdentifier(uri=uri, version=version),
            [lsp.TextDocumentContentChangeWholeDocument(text=text)]))
        return version

    def edit(self, uri: str, start: tuple[int, int], end: tuple[int, int], new_text: str) -> int:
        """Send one ranged change (positions in the negotiated encoding); returns the new version."""
        version = self.versions[uri] + 1
        self.versions[uri] = version
        rng = lsp.Range(start=lsp.Position(*start), end=lsp.Position(*end))
        self.text_document_did_change(lsp.DidChangeTextDocumentParams(
            lsp.VersionedTextDocumentIdentifier(uri=uri, version=version),
            [lsp.TextDocumentContentChangePartial(range=rng, text=new_text)]))
        return version

    def close(self, uri: str) -> None:
        """Close a document."""
        self.text_document_did_close(lsp.DidCloseTextDocumentParams(lsp.TextDocumentIdentifier(uri=uri)))

    # ---- diagnostics -------------------------------------------------------------------
    async def wait_diagnostics(self, uri: str, version: int | None = None, after: int = 0,
                               until: Callable[[list[lsp.Diagnostic]], bool] | None = None) -> list[lsp.Diagnostic]:
        """The diagnostics of ``uri`` for ``version`` (or the first ones after index ``after`` that
        satisfy ``until``)."""
        loop = asyncio.get_running_loop()
        deadline = loop.time() + TIMEOUT
        while True:
            self.arrived.clear()
            for p in self.published[after:]:
                if p.uri == uri and (version is None or p.version == version) and (
                        until is None or until(list(p.diagnostics))):
                    return list(p.diagnostics)
            remaining = deadline - loop.time()
            if remaining <= 0:
                raise AssertionError(f"no diagnostics for {uri} version {version}")
            await asyncio.wait_for(self.arrived.wait(), remaining)

    def mark(self) -> int:
        """An index to wait for diagnostics published from now on."""
        return len(self.published)

    # ---- positions ----------------------------------------------------------------------
    def pos(self, uri: str, needle: str, delta: int = 0, nth: int = 0) -> lsp.Position:
        """The position of the ``nth`` occurrence of ``needle`` (+ ``delta`` characters) in the sent text."""
        text = self.texts[uri]
        at = -1
        for _ in range(nth + 1):
            at = text.index(needle, at + 1)
        at += delta
        line = text.count("\n", 0, at)
        col = at - (text.rfind("\n", 0, at) + 1)
        return lsp.Position(line=line, character=col)

    def doc(self, uri: str) -> lsp.TextDocumentIdentifier:
        """A document identifier."""
        return lsp.TextDocumentIdentifier(uri=uri)


def _record(client: Client, params: lsp.PublishDiagnosticsParams) -> None:
    client.diagnostics[params.uri] = params.diagnostics
    client.published.append(params)
    client.arrived.set()


def _converter() -> Any:
    """lsprotocol's converter, reading a CodeAction that carries a command as a CodeAction.

    lsprotocol's own hook reads any object with a ``command`` key as a Command;
    editors decide by the key's type (a string for a Command), and so does this.
    """
    converter = default_converter()

    def code_action(obj: Any, _: type) -> lsp.Command | lsp.CodeAction:
        if isinstance(obj.get("command"), str):
            return converter.structure(obj, lsp.Command)
        return converter.structure(obj, lsp.CodeAction)

    converter.register_structure_hook(Union[lsp.Command, lsp.CodeAction], code_action)
    return converter


def make_client() -> Client:
    """A test client that records diagnostics."""
    client = Client(converter_factory=_converter)
    features = dict(DEFAULT_CLIENT_FEATURES)
    features[lsp.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS] = _record
    register_lsp_features(client, features)
    return client


CONFIG = ClientServerConfig(server_command=SERVER, client_factory=make_client)


async def start(client: Client, root: Path, profile: str, options: dict[str, Any] | None = None) -> None:
    """Initialize a session with a client profile on a workspace folder."""
    client.root = root
    client.profile = profile
    caps = client_capabilities(profile)
    await client.initialize_session(lsp.InitializeParams(
        capabilities=caps, root_uri=root.as_uri(),
        workspace_folders=[lsp.WorkspaceFolder(uri=root.as_uri(), name=root.name)],
        initialization_options={"diagnosticsDelay": 0, **(options or {})}))
