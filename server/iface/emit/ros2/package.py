"""The lowered form: what a ROS 2 interface package holds, with ROS names, types and decoded values.

The ``ros2``, ``idl`` and ``ardupilot`` targets render these objects; ``lower`` builds them.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field, replace

from ...model.source import Source, Span

Scalar = bool | int | float | str
PyValue = Scalar | list[Scalar]
#: The integer type an enum field gets (Thrift enums are 32-bit).
ENUM_PRIMITIVE = "int32"


@dataclass(frozen=True, slots=True)
class RosType:
    """A ROS 2 field type: a primitive or a named message, maybe bounded, maybe an array."""

    primitive: str | None = None
    package: str | None = None
    name: str | None = None
    string_bound: int | None = None
    array: str | None = None
    size: int | None = None

    @property
    def element(self) -> RosType:
        """The type without its array suffix."""
        return replace(self, array=None, size=None)

    def core(self, package: str) -> str:
        """The element type as written in a .msg file of ``package``."""
        if self.primitive is not None:
            return self.primitive + (f"<={self.string_bound}" if self.string_bound is not None else "")
        return self.name if self.package == package else f"{self.package}/{self.name}"  # type: ignore[return-value]

    def msg(self, package: str) -> str:
        """The type as written in a .msg file of ``package``."""
        core = self.core(package)
        if self.array == "fixed":
            return f"{core}[{self.size}]"
        if self.array == "bounded":
            return f"{core}[<={self.size}]"
        if self.array == "unbounded":
            return f"{core}[]"
        return core


@dataclass(slots=True)
class RosField:
    """A field with its ROS name, type, decoded default and comment lines."""

    name: str
    type: RosType
    default: PyValue | None
    comments: list[str]
    source: Source
    span: Span


@dataclass(slots=True)
class RosConst:
    """A constant: primitive type, ROS name, decoded value."""

    name: str
    primitive: str
    value: Scalar
    comments: list[str]
    source: Source
    span: Span


@dataclass(slots=True)
class RosSection:
    """One part of an interface: the body of a message, a request, a goal…

    ``comments`` are the lines of the part's own doc comment (``/** … */ response { … }``).
    """

    name: str
    fields: list[RosField] = field(default_factory=list)
    consts: list[RosConst] = field(default_factory=list)
    comments: list[str] = field(default_factory=list)


@dataclass(slots=True)
class RosInterface:
    """One interface file: ``msg`` (one section), ``srv`` (two) or ``action`` (three)."""

    kind: str
    name: str
    sections: list[RosSection]
    comments: list[str]
    source: Source
    span: Span


@dataclass(slots=True)
class RosParam:
    """A parameter of the node: name as written, type, default (None: not in the YAML, for the reason in ``note``)."""

    name: str
    type: RosType
    value: PyValue | None
    comments: list[str]
    note: str = "no default, so not set here: every launch must set it"


@dataclass(slots=True)
class RosPackage:
    """Everything a ROS 2 interface package holds."""

    name: str
    component: str
    node: str
    version: str
    description: str
    maintainer: str
    maintainer_email: str
    license: str
    source_name: str
    #: Where the package name is stated (its ``namespace ros2``, else the start of the file).
    name_source: Source
    name_span: Span
    interfaces: list[RosInterface] = field(default_factory=list)
    depends: list[str] = field(default_factory=list)
    params: list[RosParam] = field(default_factory=list)
    #: Where the component (hence the node) is named, in ``name_source``.
    node_span: Span = field(default_factory=lambda: Span(0, 0))

    def of_kind(self, kind: str) -> list[RosInterface]:
        """The interfaces of one kind, by name."""
        return sorted((i for i in self.interfaces if i.kind == kind), key=lambda i: i.name)

    def identifiers(self) -> Iterator[tuple[str, str, Source, Span]]:
        """(what, name, source, span) of every identifier generated code declares from the model.

        The package, each message, and every field and constant; service and action
        types carry a suffix (``_Request``, ``_Goal``…) and are left out.
        """
        yield f"package '{self.name}'", self.name, self.name_source, self.name_span
        for ri in self.interfaces:
            if ri.kind == "msg":
                yield f"message '{ri.name}'", ri.name, ri.source, ri.span
            for sec in ri.sections:
                for f in sec.fields:
                    yield f"field '{f.name}' of {ri.kind}/{ri.name}", f.name, f.source, f.span
                for c in sec.consts:
                    yield f"constant '{c.name}' of {ri.kind}/{ri.name}", c.name, c.source, c.span
