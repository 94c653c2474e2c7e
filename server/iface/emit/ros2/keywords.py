"""Names rosidl's code generators cannot use: C and C++ keywords, Python keywords (warnings).

rosidl_generator_cpp writes every field as a C++ struct member named as in the
.msg file, without renaming, so a field ``class`` or ``delete`` makes the package
fail to compile (ros2/rosidl#272); a package named like a keyword fails the same
way as a C++ namespace. rosidl_generator_py does not support Python keywords as
member names either (it warns at build time and the Python module cannot be
imported; ros2/rosidl_python#95, #96), but the C and C++ code still builds.
Both are warnings: the .msg files themselves are valid, and packages that are
only read by other tools (or imported and generated back) keep their names.
"""

from __future__ import annotations

from collections.abc import Iterator

from ...model.diagnostics import Diagnostic
from ..keywords import c_family_keyword, python_keyword
from .codes import diag
from .package import RosPackage


def check_keywords(pkg: RosPackage) -> Iterator[Diagnostic]:
    """A warning for each name that is a C or C++ keyword or a Python keyword."""
    seen: set[tuple[str, int, int]] = set()
    for what, name, source, span in pkg.identifiers():
        key = (source.path, span.start, span.end)
        if key in seen:
            continue
        seen.add(key)
        if c_family_keyword(name):
            yield diag("ros2-reserved-name", f"{what} is a C/C++ keyword: rosidl_generator_cpp writes it unchanged "
                       "as a C++ identifier, so the package does not compile with colcon; rename it", source, span)
        elif python_keyword(name):
            yield diag("ros2-python-keyword", f"{what} is a Python keyword: rosidl_generator_py does not support "
                       "it and the Python module of the package cannot be imported; rename it for Python users",
                       source, span)
