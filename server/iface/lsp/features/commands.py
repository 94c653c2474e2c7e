"""workspace/executeCommand: generate, preview, export JSON, compatibility and the system graph.

Arguments are positional (``[uri, target]``) or one object (``[{"uri": …, "target": …}]``).
Answers are JSON objects: ``iface.preview`` gives ``{files: [{path, text}]}``
(a virtual document for the client to show, nothing written), ``iface.generate``
and ``iface.exportJson`` give ``{written, unchanged, refused, errors, files, folder}`` (``iface.generate``
also ``not_iface``: the refused files iface never wrote, as opposed to generated files edited by hand,
and ``kept``: files written once that are the user's now, such as a component's ``node.py``),
``iface.compat`` and ``iface.graph`` give ``{text}``; ``iface.verify [uris, timeout]`` ("Verify against the running
system") compares the running ROS 2 graph with the given files (else every component of the workspace), publishes
the findings as diagnostics on the files and gives ``{text, findings, nodes}``. A missing module or a bad
argument is answered with an error that says what is wrong.
"""

from __future__ import annotations

import asyncio
import os
from typing import TYPE_CHECKING, Any

from pygls.exceptions import JsonRpcInternalError, JsonRpcInvalidParams

from ..server import IfaceServer, Refusal  # noqa: E402  (resolved at run time: pygls reads the handlers' annotations)
from .. import convert
from ..documents import path_to_uri
from ..settings import DEFAULT_OUTPUT
from ..versions import CompiledVersion

if TYPE_CHECKING:
    from ...semantics.compile import Compilation
    from ..project import Project


class CommandError(Refusal, JsonRpcInvalidParams):
    """A command that cannot run as asked."""


def available_targets() -> list[str]:
    """Names of the installed generation targets ([] when the emitters are not installed)."""
    try:
        from ...emit import targets
    except ImportError:
        return []
    return sorted(targets())


def _args(arguments: Any, names: tuple[str, ...]) -> dict[str, Any]:
    """Positional or object arguments, by name."""
    args = list(arguments or [])
    if len(args) == 1 and isinstance(args[0], dict):
        return {k: args[0].get(k) for k in names}
    return {k: (args[i] if i < len(args) else None) for i, k in enumerate(names)}


def _text(value: Any, what: str, required: bool = True) -> str | None:
    if value is None and not required:
        return None
    if not isinstance(value, str) or not value:
        raise CommandError(f"{what} must be a non-empty string")
    return value


class Runner:
    """Runs the commands for one server."""

    def __init__(self, project: Project) -> None:
        self.project = project

    async def compilation(self, uri: str) -> CompiledVersion:
        """A current compiled version of ``uri`` (compiled now if needed)."""
        ver = await self.project.latest(uri, fresh=True)
        if ver is None or ver.comp is None:
            raise CommandError(f"cannot read {uri}")
        return ver

    def target(self, name: str | None) -> str:
        """The target asked for, or the first default one."""
        targets = available_targets()
        if not targets:
            raise JsonRpcInternalError(message="no generation target is installed (iface.emit is missing)")
        chosen = name or next((t for t in self.project.settings.targets if t in targets), None) or targets[0]
        if chosen not in targets:
            raise CommandError(f"unknown target '{chosen}'; available: {', '.join(targets)}")
        return chosen

    def out_dir(self, path: str, folder: str | None, target: str) -> str:
        """Where generated files go: the argument, the setting, or ``generated/<target>`` in the workspace."""
        base = self.project.roots[0] if self.project.roots else os.path.dirname(path)
        chosen = folder or self.project.settings.output_folder or DEFAULT_OUTPUT
        chosen = chosen if os.path.isabs(chosen) else os.path.join(base, chosen)
        return os.path.join(chosen, target)

    def _generate(self, comp: Compilation, target: str, *, strict: bool = True) -> tuple[list[Any], list[str]]:
        """The target's files and the errors; ``strict``: no files at all when there is an error.

        A preview is not strict: it shows what the target makes of the text so far beside the
        errors; generating and exporting write nothing from input with errors.
        """
        from ...emit import generate

        errors = [d.format() for d in comp.all_diagnostics() if int(d.severity) == 1]
        if errors and strict:
            return [], errors
        result = generate(comp, target)
        errors += [d.format() for d in result.diagnostics if int(d.severity) == 1]
        return ([] if errors and strict else result.files), errors

    async def preview(self, arguments: Any) -> dict[str, Any]:
        """``iface.preview [uri, target]``: the generated files, not written."""
        a = _args(arguments, ("uri", "target"))
        ver = await self.compilation(_text(a["uri"], "uri") or "")
        target = self.target(_text(a["target"], "target", required=False))

        def run() -> dict[str, Any]:
            assert ver.comp is not None
            files, errors = self._generate(ver.comp, target, strict=False)
            return {"target": target, "files": [{"path": f.path, "text": f.text} for f in files], "errors": errors}

        return await self.project.run(run)

    async def generate(self, arguments: Any) -> dict[str, Any]:
        """``iface.generate [uri, target, folder]``: write the generated files."""
        a = _args(arguments, ("uri", "target", "folder"))
        ver = await self.compilation(_text(a["uri"], "uri") or "")
        target = self.target(_text(a["target"], "target", required=False))
        out = self.out_dir(ver.path, _text(a["folder"], "folder", required=False), target)

        def run() -> dict[str, Any]:
            from ...emit.write import write_files

            assert ver.comp is not None
            files, errors = self._generate(ver.comp, target)
            if errors:
                return {"target": target, "folder": out, "written": [], "unchanged": [], "kept": [], "refused": [],
                        "errors": errors, "files": []}
            report = write_files(files, out)
            return {"target": target, "folder": out, "written": report.written, "unchanged": report.unchanged,
                    "kept": report.kept, "refused": report.refused, "not_iface": report.foreign, "errors": report.errors,
                    "files": [os.path.join(out, p) for p in report.written + report.unchanged]}

        return await self.project.run(run)

    async def export_json(self, arguments: Any) -> dict[str, Any]:
        """``iface.exportJson [uri, folder]``: the interface as JSON, written to the output folder."""
        a = _args(arguments, ("uri", "folder"))
        ver = await self.compilation(_text(a["uri"], "uri") or "")
        out = self.out_dir(ver.path, _text(a["folder"], "folder", required=False), "json")

        def run() -> dict[str, Any]:
            from ...emit.write import write_files

            assert ver.comp is not None
            files, errors = self._generate(ver.comp, "json")
            if errors:
                return {"written": [], "unchanged": [], "refused": [], "files": [], "folder": out, "errors": errors}
            report = write_files(files, out)
            return {"written": report.written, "unchanged": report.unchanged, "refused": report.refused,
                    "errors": report.errors, "folder": out,
                    "files": [{"path": os.path.join(out, f.path), "text": f.text} for f in files]}

        return await self.project.run(run)

    async def compat(self, arguments: Any) -> dict[str, Any]:
        """``iface.compat [uri, baseline]``: can this file replace its baseline (a file or ``git:REV``)?"""
        a = _args(arguments, ("uri", "baseline"))
        ver = await self.compilation(_text(a["uri"], "uri") or "")
        spec = _text(a["baseline"], "baseline", required=False) or self.project.settings.compat_baseline
        if not spec:
            raise CommandError("no baseline: pass one or set compat.baseline")

        def run() -> dict[str, Any]:
            try:
                from ...compat import compare, load_baseline
                from ...compat.report import render_text
            except ImportError as e:
                raise JsonRpcInternalError(message="compatibility checks are not installed (iface.compat)") from e
            assert ver.comp is not None
            old = load_baseline(ver.path, spec, list(self.project.workspace().include_paths))
            if old is None:
                raise CommandError(f"cannot read the baseline '{spec}'")
            report = compare(old, ver.comp)
            return {"text": render_text(report, _display(self.project)), "verdict": str(report.verdict)}

        return await self.project.run(run)

    async def graph(self, arguments: Any) -> dict[str, Any]:
        """``iface.graph [format]``: the system graph of the workspace's components (mermaid, dot, json or svg).

        With ``json`` the answer also holds ``graph``: the same data with absolute paths, which a
        client draws from (locations to go to when an element is clicked)."""
        a = _args(arguments, ("format",))
        fmt = _text(a["format"], "format", required=False) or "mermaid"
        if fmt not in ("mermaid", "dot", "json", "svg"):
            raise CommandError("format must be mermaid, dot, json or svg")
        if self.project.workspace_index is not None:
            await self.project.workspace_index.ready.wait()

        def run() -> dict[str, Any]:
            try:
                from ...compat import graph
            except ImportError as e:
                raise JsonRpcInternalError(message="the system graph is not installed (iface.compat.graph)") from e
            index = self.project.workspace_index
            comps = index.all_compilations() if index is not None else []
            comps = [c for c in comps if c.path.endswith(".iface") and c.interface.component is not None]
            g = graph.build(comps)
            extra: dict[str, Any] = {}
            if fmt == "dot":
                text = graph.render_dot(g)
            elif fmt == "json":
                text = graph.render_json(g, _display(self.project))
                extra["graph"] = graph.graph_json(g, os.path.abspath)
            elif fmt == "svg":
                from ...compat.svg import builtin_svg
                text = builtin_svg(graph.graph_json(g, _display(self.project)))
            else:
                text = graph.render_mermaid(g)
            return {"text": text, "format": fmt, "components": len(comps), **extra}

        return await self.project.run(run)


    async def verify(self, arguments: Any) -> dict[str, Any]:
        """``iface.verify [uris, timeout]``: the running system against its files, published as diagnostics."""
        a = _args(arguments, ("uris", "timeout"))
        uris = a["uris"] if a["uris"] is not None else []
        if isinstance(uris, str):
            uris = [uris]
        if not isinstance(uris, list) or not all(isinstance(u, str) and u for u in uris):
            raise CommandError("uris must be a list of file URIs")
        timeout = a["timeout"] if a["timeout"] is not None else 5.0
        if isinstance(timeout, bool) or not isinstance(timeout, (int, float)) or timeout <= 0:
            raise CommandError("timeout must be a number of seconds above 0")
        from ...live.graph import ros_missing
        why = ros_missing()
        if why:
            raise CommandError(why)
        comps: list[Compilation] = []
        if uris:
            for uri in uris:
                ver = await self.compilation(uri)
                assert ver.comp is not None
                comps.append(ver.comp)
        else:
            if self.project.workspace_index is not None:
                await self.project.workspace_index.ready.wait()
            index = self.project.workspace_index
            comps = index.all_compilations() if index is not None else []
        comps = [c for c in comps if c.path.endswith(".iface") and not c.has_errors]
        from ...live.graph import open_graph
        from ...live.report import render_text
        from ...live.verify import declared_all, read_live, verify

        decls = declared_all(comps)
        if not decls:
            raise CommandError("no component or system file without errors to verify")
        comps = [*comps, *(d.comp for d in decls)]

        def read() -> Any:
            with open_graph(float(timeout)) as graph:
                return read_live(graph, decls)

        live = await asyncio.to_thread(read)
        findings = verify(decls, live)
        sources = {c.path: c.source for c in comps}
        found: dict[str, list[Any]] = {path_to_uri(c.path): [] for c in comps if c.path.endswith(".iface")}
        for f in findings:
            source = sources.get(f.path)
            if source is None:
                continue
            start = source.offset(f.line - 1, f.column - 1)
            end = source.offset(f.end_line - 1, f.end_column - 1) if f.end_line else start
            index = self.project.index_of(source)
            found[path_to_uri(f.path)].append(
                convert.live_finding(f.code, f.severity, f"{f.message} [{f.node}]", index, start, end))
        self.project.set_live(found)
        return {"text": render_text(findings, _display(self.project), len(decls)), "nodes": len(decls),
                "findings": [{"code": f.code, "severity": f.severity, "message": f.message, "node": f.node,
                              "uri": path_to_uri(f.path) if f.path else None, "line": f.line, "column": f.column}
                             for f in findings]}


def _display(project: Project) -> Any:
    root = project.roots[0] if project.roots else None

    def display(path: str) -> str:
        if root is not None:
            try:
                rel = os.path.relpath(path, root)
            except ValueError:
                return path
            return path if rel.startswith("..") else rel
        return path
    return display


def register(server: IfaceServer) -> None:
    """Register the commands."""
    runner = Runner(server.project)

    @server.command("iface.preview")
    async def preview(ls: IfaceServer, *args: Any) -> dict[str, Any]:
        return await runner.preview(_flatten(args))

    @server.command("iface.generate")
    async def generate(ls: IfaceServer, *args: Any) -> dict[str, Any]:
        result = await runner.generate(_flatten(args))
        ls.log_info(f"iface: generated {len(result['written'])} file(s) into {result['folder']}")
        return result

    @server.command("iface.exportJson")
    async def export_json(ls: IfaceServer, *args: Any) -> dict[str, Any]:
        return await runner.export_json(_flatten(args))

    @server.command("iface.compat")
    async def compat(ls: IfaceServer, *args: Any) -> dict[str, Any]:
        return await runner.compat(_flatten(args))

    @server.command("iface.graph")
    async def graph(ls: IfaceServer, *args: Any) -> dict[str, Any]:
        return await runner.graph(_flatten(args))

    @server.command("iface.verify")
    async def verify(ls: IfaceServer, *args: Any) -> dict[str, Any]:
        result = await runner.verify(_flatten(args))
        ls.log_info(f"iface: verified {result['nodes']} node(s): {len(result['findings'])} finding(s)")
        return result


def _flatten(args: tuple[Any, ...]) -> list[Any]:
    """pygls passes the arguments list as one positional argument or spread; accept both."""
    if len(args) == 1 and isinstance(args[0], list):
        return args[0]
    return list(args)

