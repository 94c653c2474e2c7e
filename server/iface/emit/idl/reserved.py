"""OMG IDL keywords: names the idl and ardupilot targets must not write as identifiers.

OMG IDL 4.2, 7.2.4 (Table 7-6) lists the keywords; 7.2.3 makes an identifier
that collides with one illegal, case-insensitively. A name equal to a keyword
breaks strict IDL compilers outright (DDS code generators such as the one
AP_DDS uses) and is an error; a name that differs from one only in case
(a ROS constant ``DEFAULT``) is a warning, since some tools accept it.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...model.diagnostics import Diagnostic
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
_FOLDED: dict[str, str] = {k.lower(): k for k in IDL_KEYWORDS}


def keyword_of(name: str) -> str | None:
    """The IDL keyword ``name`` collides with (case-insensitively), None when it is free."""
    return _FOLDED.get(name.lower())


def check_idl_names(pkg: RosPackage) -> Iterator[Diagnostic]:
    """An error for each name that is an IDL keyword, a warning for each that differs from one only in case."""
    seen: set[tuple[str, int, int]] = set()
    for what, name, source, span in pkg.identifiers():
        keyword = keyword_of(name)
        key = (source.path, span.start, span.end)
        if keyword is None or key in seen:
            continue
        seen.add(key)
        if keyword == name:
            yield diag("idl-reserved-name", f"{what} is an OMG IDL keyword, which IDL compilers refuse as a "
                       "name: rename it", source, span)
        else:
            yield diag("idl-reserved-name-case", f"{what} differs from the OMG IDL keyword '{keyword}' only in "
                       "case, which strict IDL compilers refuse: consider renaming it", source, span)
