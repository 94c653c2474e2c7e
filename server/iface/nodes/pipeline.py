"""One pipeline for both node targets: what ``generate --target rclpy`` and ``--target rclcpp`` do, step by step.

1. lower the interface to its ROS 2 package and describe the node (``nodepkg.prepare``); stop on errors;
2. an interface package without a node (nothing wired): that package alone;
3. the language's view of the node (``NodeLanguage.view``), and what the language refuses in it;
4. the user's file in the output folder, checked against the interface (``generate --check``: errors);
5. the shared packages (``shared``), the interface package, and the component package: the files every
   component package has (parameter file, launch file, the interface as JSON) and the language's own
   (``NodeLanguage.files``, each rendered from its template with the header in its comment syntax).

A ``NodeLanguage`` holds what differs; ``rclpy`` and ``rclcpp`` each define one.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

from ..emit.base import GeneratedFile, Result, Target, TemplateSet, header_lines, sorted_files
from ..emit.json import generate as generate_json
from ..emit.ros2 import TEMPLATES as ROS2_TEMPLATES
from ..emit.ros2 import render_package
from ..emit.ros2.render import FILTERS as ROS2_FILTERS
from ..model.diagnostics import Diagnostic
from ..semantics.compile import Compilation
from .component import ComponentSpec
from .nodepkg import launch_text, prepare, read_user_file, types_only
from .shared import shared_files
from .template_data import NodeView

#: The comment a generated header takes, by its opening (XML's closes too).
_HEADER_ENDS = {"<!--": " -->"}


@dataclass(frozen=True, slots=True)
class PackageFile:
    """A file of the component package: its path (``{pkg}`` is the package's name), its template, the comment
    its header is written in (``None``: the user's file, written once and never overwritten, without one)."""

    path: str
    template: str
    comment: str | None


class UserCheck(Protocol):
    """Where the user's file ``text`` (at ``path``) does not match the interface; errors when ``strict``."""

    def __call__(self, spec: ComponentSpec, path: str, text: str, *, strict: bool) -> list[Diagnostic]: ...


def _refuses_nothing(view: NodeView[Any], comp: Compilation) -> list[Diagnostic]:
    return []


@dataclass(frozen=True, slots=True)
class NodeLanguage:
    """What a node target's language makes of the pipeline's steps.

    ``target`` names the target (``rclpy``), its templates (``nodes/<target>/templates/``) and the client
    library the node is written on; ``language`` (``python``, ``c++``) decides which keywords names must avoid.
    """

    target: str
    language: str
    #: The files of the component package the language writes; exactly one is the user's (comment None).
    files: tuple[PackageFile, ...]
    filters: dict[str, Callable[..., Any]]
    #: How the launch file starts the node: ``python -m {pkg}``, ``ros2 run {pkg} {pkg}``.
    start_command: str
    view: Callable[[ComponentSpec], NodeView[Any]]
    check_user: UserCheck
    #: What every component package needs beside the message packages it uses (the templates' ``depends``).
    runtime_depends: tuple[str, ...]
    #: What the language cannot generate for this node (errors: nothing is written).
    refuse: Callable[[NodeView[Any], Compilation], list[Diagnostic]] = _refuses_nothing
    #: How ``iface-lsp targets`` names the language beside the package: "" or " in C++".
    written_in: str = ""

    @property
    def templates(self) -> Path:
        """The language's templates: ``nodes/<target>/templates/``."""
        return Path(__file__).parent / self.target / "templates"

    @property
    def user_file(self) -> PackageFile:
        """The user's file: written once, never overwritten."""
        return next(f for f in self.files if f.comment is None)

    def target_descriptor(self) -> Target:
        """The ``Target`` the registry lists for this language."""
        description = (f"ROS 2 component package{self.written_in} ({self.target} lifecycle node: parameters, QoS, "
                       "state save/restore, diagnostics, launch file) beside its interface package")
        return Target(name=self.target, description=description,
                      generate=lambda comp, options: generate(self, comp, options), templates=str(self.templates))


def user_file_path(language: NodeLanguage, out: str, spec: ComponentSpec) -> str:
    """Where the user's file of ``spec`` is under the output folder ``out``."""
    return os.path.join(out, spec.package, *language.user_file.path.format(pkg=spec.package).split("/"))


def generate(language: NodeLanguage, comp: Compilation, options: dict[str, Any]) -> Result:
    """The interface package, the shared packages and the component package of ``comp`` in ``language``."""
    result, pkg, spec = prepare(comp, language.language)
    if pkg is None or spec is None:
        return result
    ros2 = TemplateSet(ROS2_TEMPLATES, "ros2", filters=ROS2_FILTERS)
    if types_only(spec):
        result.files = sorted_files(render_package(pkg, ros2))
        return result
    view = language.view(spec)
    refused = language.refuse(view, comp)
    if refused:
        result.diagnostics.extend(refused)
        return result
    out = options.get("out")
    if isinstance(out, str):
        path = user_file_path(language, out, spec)
        text = read_user_file(path)
        if text is not None:
            result.diagnostics.extend(language.check_user(spec, path, text, strict=bool(options.get("check"))))
    shared, result.notes = shared_files(language.target, out if isinstance(out, str) else None)
    templates = TemplateSet(language.templates, language.target, filters=language.filters,
                            override=options.get("templates"))
    result.files = sorted_files([*shared, *render_package(pkg, ros2),
                                 *component_package(language, view, comp, templates, ros2)])
    return result


def component_package(language: NodeLanguage, view: NodeView[Any], comp: Compilation, templates: TemplateSet,
                      ros2: TemplateSet) -> list[GeneratedFile]:
    """The component package: the files every one has, and the language's."""
    spec = view.spec
    root = view.pkg
    origin = (spec.ros.name_source, spec.ros.node_span)
    (interface,) = generate_json(comp, {}).files
    hash_header = header_lines("#", spec.source_name).rstrip("\n")
    params_pkg = dataclasses.replace(spec.ros, node="/**")
    context: dict[str, Any] = {"v": view, "interface_file": interface.path, "msg_depends": sorted(set(spec.depends)),
                               "depends": sorted(set(language.runtime_depends) | set(spec.depends))}
    files = [
        GeneratedFile(f"{root}/config/{view.params_file}",
                      ros2.render("params.yaml.j2", package=params_pkg, header=hash_header), origin),
        GeneratedFile(f"{root}/launch/{view.launch_file}",
                      launch_text(view, hash_header, language.start_command.format(pkg=root)), origin),
        GeneratedFile(f"{root}/{interface.path}", interface.text, origin),
    ]
    for f in language.files:
        header = "" if f.comment is None else header_lines(
            f.comment, spec.source_name, end=_HEADER_ENDS.get(f.comment, "")).rstrip("\n")
        text = templates.render(f.template, **context, header=header)
        files.append(GeneratedFile(f"{root}/{f.path.format(pkg=root)}", text, origin, once=f.comment is None))
    return files


__all__ = ["NodeLanguage", "PackageFile", "component_package", "generate", "user_file_path"]
