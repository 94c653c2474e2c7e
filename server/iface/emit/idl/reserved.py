"""OMG IDL keywords, and the escape the idl and ardupilot targets write for names that collide with one.

OMG IDL 4.2, 7.2.4 (Table 7-6) lists the keywords; 7.2.3 makes an identifier that collides
with one, case-insensitively, illegal, and lets any identifier be escaped with a leading
underscore that "only turns off keyword checking" (``_struct`` declares ``struct``; CORBA 3
numbered the rule 3.2.3.1). So every such name is written escaped; IDL compilers (Cyclone DDS's
idlc, Fast-DDS-Gen) strip the underscore. Two limits remain: rosidl_parser and rosbags read no
escaped identifier (the idl target warns), and Fast-DDS-Gen 2.3.0, whose fork Micro-XRCE-DDS-Gen
ArduPilot builds with, resolves no reference to an escaped type name (the ardupilot target refuses one).
"""

from __future__ import annotations

from collections.abc import Iterator

from ...model.diagnostics import Diagnostic
from ...model.source import Source, Span
from ..ros2.codes import diag
from ..ros2.package import RosPackage

#: The keywords of OMG IDL 4.2 (Table 7-6), as the spec spells them.
IDL_KEYWORDS: frozenset[str] = frozenset("""
abstract any alias attribute bitfield bitmask bitset boolean case char component connector const consumes
context custom default double exception emits enum eventtype factory FALSE finder fixed float getraises getter
home import in inout interface local long manages map mirrorport module multiple native Object octet oneway
out primarykey private port porttype provides public publishes raises readonly setraises setter sequence short
string struct supports switch TRUE truncatable typedef typeid typename typeprefix unsigned union uses ValueBase
valuetype void wchar wstring int8 uint8 int16 int32 int64 uint16 uint32 uint64
""".split())
#: Words Fast-DDS-Gen 2.3.0 (ArduPilot builds with its fork Micro-XRCE-DDS-Gen) lexes as keywords, case-insensitively,
#: beyond the spec's: escaped too, which the spec allows for any identifier.
DDS_GEN_KEYWORDS: frozenset[str] = frozenset({"set"})
_FOLDED: dict[str, str] = {k.lower(): k for k in IDL_KEYWORDS | DDS_GEN_KEYWORDS}


def keyword_of(name: str) -> str | None:
    """The IDL keyword ``name`` collides with (case-insensitively), None when it is free."""
    return _FOLDED.get(name.lower())


def idl_name(name: str) -> str:
    """``name`` as an IDL identifier: escaped with a leading underscore where it collides with a keyword."""
    return f"_{name}" if keyword_of(name) is not None else name


def _escaped(pkg: RosPackage) -> Iterator[tuple[str, str, str, Source, Span]]:
    """(what, name, keyword, source, span) of each name written escaped, once per place."""
    seen: set[tuple[str, int, int]] = set()
    for what, name, source, span in pkg.identifiers():
        keyword = keyword_of(name)
        key = (source.path, span.start, span.end)
        if keyword is not None and key not in seen:
            seen.add(key)
            yield what, name, keyword, source, span


def check_idl_names(pkg: RosPackage) -> Iterator[Diagnostic]:
    """A warning for each name written escaped: ROS 2's IDL readers take no escape."""
    for what, name, keyword, source, span in _escaped(pkg):
        yield diag("idl-escaped-name", f"{what} collides with the IDL keyword '{keyword}', so it is written "
                   f"'_{name}' (IDL's escape, which IDL compilers strip); rosidl_parser and rosbags read no "
                   "escaped name: for a ROS 2 package use the ros2 target", source, span)


def check_ap_idl_names(pkg: RosPackage) -> Iterator[Diagnostic]:
    """An error for each field whose type's scoped name has a keyword part: that reference cannot be written."""
    for ri in pkg.interfaces:
        for sec in ri.sections:
            for f in sec.fields:
                if f.type.primitive is not None:
                    continue
                parts = (f"message '{f.type.name}'", f.type.name or ""), (f"package '{f.type.package}'",
                                                                         f.type.package or "")
                for what, name in parts:
                    keyword = keyword_of(name)
                    if keyword is not None:
                        yield diag("idl-reserved-name", f"field '{f.name}' of {ri.kind}/{ri.name} has a type of "
                                   f"{what}, which collides with the IDL keyword '{keyword}': IDL compilers refuse "
                                   "it as written and Fast-DDS-Gen (ArduPilot's Micro-XRCE-DDS-Gen is its fork) "
                                   f"resolves no escaped reference '_{name}'; rename the {what.split()[0]}",
                                   f.source, f.span)
