"""Keywords of the languages generated code is compiled in: names a target must not write as identifiers.

A field named ``class`` or ``delete`` becomes a C++ struct member of that name in
the code PX4 (uORB), ROS 2 (rosidl_generator_cpp) and ArduPilot generate from the
files iface writes, and no C++ compiler accepts it; C adds ``restrict`` and the
C23 keywords. rosidl_generator_py cannot use Python keywords as member names.
The lists are spelled out (not read from the running Python) so that results do
not depend on the interpreter.
"""

from __future__ import annotations

#: C++20 keywords and alternative tokens (ISO/IEC 14882:2020, [lex.key], [lex.digraph]).
CPP_KEYWORDS: frozenset[str] = frozenset("""
alignas alignof and and_eq asm auto bitand bitor bool break case catch char char8_t char16_t char32_t class
compl concept const consteval constexpr constinit const_cast continue co_await co_return co_yield decltype
default delete do double dynamic_cast else enum explicit export extern false float for friend goto if inline
int long mutable namespace new noexcept not not_eq nullptr operator or or_eq private protected public register
reinterpret_cast requires return short signed sizeof static static_assert static_cast struct switch template
this thread_local throw true try typedef typeid typename union unsigned using virtual void volatile wchar_t
while xor xor_eq
""".split())

#: C keywords that C++ does not have (C99 ``restrict``, C23 ``typeof``/``typeof_unqual``); the
#: underscore-capital ones (``_Bool``…) cannot be interface names.
C_ONLY_KEYWORDS: frozenset[str] = frozenset({"restrict", "typeof", "typeof_unqual"})

#: Identifiers that C and C++ compilers refuse as member names.
C_FAMILY_KEYWORDS: frozenset[str] = CPP_KEYWORDS | C_ONLY_KEYWORDS

#: Python 3 keywords (``keyword.kwlist`` of Python 3.7 and later; soft keywords are valid names).
PYTHON_KEYWORDS: frozenset[str] = frozenset("""
False None True and as assert async await break class continue def del elif else except finally for from
global if import in is lambda nonlocal not or pass raise return try while with yield
""".split())


def c_family_keyword(name: str) -> bool:
    """True when ``name`` is a C or C++ keyword."""
    return name in C_FAMILY_KEYWORDS


def python_keyword(name: str) -> bool:
    """True when ``name`` is a Python keyword."""
    return name in PYTHON_KEYWORDS
