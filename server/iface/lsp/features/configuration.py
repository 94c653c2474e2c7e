"""Settings (initializationOptions, workspace/didChangeConfiguration), start-up and warm-up."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from lsprotocol import types as lsp

from ..documents import uri_to_path

if TYPE_CHECKING:
    from ..server import IfaceServer


def register(server: IfaceServer) -> None:
    """Register initialize, initialized and configuration handlers."""
    project = server.project

    @server.feature(lsp.INITIALIZE)
    def initialize(ls: IfaceServer, params: lsp.InitializeParams) -> None:
        roots = [uri_to_path(f.uri) for f in params.workspace_folders or []]
        if not roots and params.root_uri:
            roots = [uri_to_path(params.root_uri)]
        elif not roots and params.root_path:
            roots = [params.root_path]
        project.roots = roots
        _apply(ls, params.initialization_options, initial=True)

    @server.feature(lsp.INITIALIZED)
    def initialized(ls: IfaceServer, params: lsp.InitializedParams) -> None:
        project.submit(warm_up)
        from ..index import WorkspaceIndex
        from ..progress import Progress
        project.workspace_index = WorkspaceIndex(project, lambda: Progress(ls, "Indexing interface files"))
        project.workspace_index.start()

    @server.feature(lsp.WORKSPACE_DID_CHANGE_WORKSPACE_FOLDERS)
    def folders(ls: IfaceServer, params: lsp.DidChangeWorkspaceFoldersParams) -> None:
        removed = {uri_to_path(f.uri) for f in params.event.removed}
        roots = [r for r in project.roots if r not in removed]
        roots += [uri_to_path(f.uri) for f in params.event.added if uri_to_path(f.uri) not in roots]
        project.roots = roots
        if project.workspace_index is not None:
            project.workspace_index.start()

    @server.feature(lsp.WORKSPACE_DID_CHANGE_CONFIGURATION)
    def changed(ls: IfaceServer, params: lsp.DidChangeConfigurationParams) -> None:
        _apply(ls, params.settings)


def _apply(ls: IfaceServer, options: Any, initial: bool = False) -> None:
    project = ls.project
    old = project.settings
    new = old.updated(options)
    project.settings = new
    for problem in new.problems:
        ls.window_log_message(lsp.LogMessageParams(type=lsp.MessageType.Warning,
                                                   message=f"iface settings: {problem}; the old value is kept"))
    if initial:
        return
    if new.include_paths != old.include_paths:
        project.submit(project.reset_workspace)
    if new.compat_baseline != old.compat_baseline:
        project.submit(project.findings.forget)
    project.recheck_all()


def warm_up() -> None:
    """Build the parser and its error messages before the first edit needs them (model thread)."""
    from ...syntax.grammar import terminal_descriptions
    from ...syntax.parse import chunk_parser

    terminal_descriptions(chunk_parser().parser)
