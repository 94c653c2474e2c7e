"""Did-you-mean for unknown type names: other languages' spellings of the builtin types, then close names.

Three steps, each bounded, so a file's suggestions cost time linear in the file
however many names are unknown:

1. *Spellings*: the name as ROS, C, C++, Python, Rust, Java or protobuf write a
   builtin type (``f64``, ``Float64``, ``int32_t``, ``str``, ``boolean``) leads
   to the ``.iface`` type (docs/language.md, "Types").
2. *Case*: a definition whose name differs only in case (``pose`` → ``Pose``).
3. *Close names*: ``difflib`` over every name in reach while a per-file budget of
   comparisons lasts (the quality of a full scan for ordinary files); after it,
   a deletion index (names one deletion apart on either side: one typo, one
   missing or extra letter, one swap) gives the candidates, ranked the same way.

Suggestions are memoized per name.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable

from ..model import nodes as m

#: Spellings of builtin types in other languages, lower case -> the ``.iface`` types they mean.
FOREIGN_TYPES: dict[str, tuple[str, ...]] = {
    # Rust, Zig, Swift-style short names
    "f32": ("float32",), "f64": ("float64",), "usize": ("u64",), "isize": ("i64",), "str": ("string",),
    # C and C++ (<cstdint>, <cstddef>)
    "int8_t": ("i8",), "int16_t": ("i16",), "int32_t": ("i32",), "int64_t": ("i64",),
    "uint8_t": ("u8",), "uint16_t": ("u16",), "uint32_t": ("u32",), "uint64_t": ("u64",),
    "int": ("i32", "i64"), "short": ("i16",), "long": ("i64", "i32"), "unsigned": ("u32",),
    "size_t": ("u64",), "ssize_t": ("i64",), "_bool": ("bool",), "float32_t": ("float32",),
    "float64_t": ("float64",),
    # Python, Java, C#, OMG IDL
    "bytes": ("binary",), "bytearray": ("binary",), "boolean": ("bool",), "integer": ("i32",),
    "sbyte": ("i8",), "ushort": ("u16",), "uint": ("u32",), "ulong": ("u64",), "single": ("float32",),
    # protobuf
    "sint32": ("i32",), "sint64": ("i64",), "fixed32": ("u32",), "fixed64": ("u64",),
    "sfixed32": ("i32",), "sfixed64": ("i64",),
}

#: Comparisons a file may spend on full scans before close names come from the index.
SCAN_BUDGET = 50_000
#: Names longer than this are not put in the deletion index (their deletions would cost too much).
INDEX_MAX_LEN = 40
CUTOFF = 0.6
MAX_SUGGESTIONS = 3


def builtin_spelling(name: str) -> list[str]:
    """The ``.iface`` builtin types ``name`` means when it is another language's spelling of one."""
    low = name.lower()
    if low in m.BASE_ALIASES:
        return [low]  # Float64, String, UInt8: the language's own spelling, lower case
    return list(FOREIGN_TYPES.get(low, ()))


class Suggester:
    """Close names for unknown names among ``names``; ``comparisons`` counts the work done (for tests)."""

    def __init__(self, names: Iterable[str]) -> None:
        self.names = list(dict.fromkeys(names))
        self.by_lower: dict[str, str] = {}
        for n in self.names:
            self.by_lower.setdefault(n.lower(), n)
        self.budget = SCAN_BUDGET
        self.comparisons = 0
        self._memo: dict[str, list[str]] = {}
        self._index: dict[str, list[str]] | None = None

    def suggest(self, name: str) -> list[str]:
        """Up to three names ``name`` may have meant, best first."""
        found = self._memo.get(name)
        if found is None:
            found = builtin_spelling(name)
            if not found:
                same = self.by_lower.get(name.lower())
                found = [same] if same is not None and same != name else self._close(name)
            self._memo[name] = found
        return found

    def _close(self, name: str) -> list[str]:
        if len(self.names) <= self.budget:
            self.budget -= len(self.names)
            self.comparisons += len(self.names)
            n = len(name)
            slack = max(2, n // 3)
            pool = [c for c in self.names if abs(len(c) - n) <= slack]
            return difflib.get_close_matches(name, pool, n=MAX_SUGGESTIONS, cutoff=CUTOFF)
        return self._from_index(name)

    def _from_index(self, name: str) -> list[str]:
        """Candidates one deletion apart (either side), ranked by difflib's ratio."""
        index = self._index if self._index is not None else self._build_index()
        low = name.lower()
        candidates: dict[str, None] = {}
        for key in _deletions(low) if len(low) <= INDEX_MAX_LEN else (low,):
            for c in index.get(key, ()):
                candidates[c] = None
        matcher = difflib.SequenceMatcher()
        matcher.set_seq2(name)
        scored = []
        for c in candidates:
            self.comparisons += 1
            matcher.set_seq1(c)
            if matcher.real_quick_ratio() >= CUTOFF and matcher.quick_ratio() >= CUTOFF:
                score = matcher.ratio()
                if score >= CUTOFF:
                    scored.append((score, c))
        scored.sort(key=lambda sc: (-sc[0], sc[1]))
        return [c for _, c in scored[:MAX_SUGGESTIONS]]

    def _build_index(self) -> dict[str, list[str]]:
        index: dict[str, list[str]] = {}
        for n in self.names:
            low = n.lower()
            if len(low) > INDEX_MAX_LEN:
                index.setdefault(low, []).append(n)
                continue
            self.comparisons += len(low) + 1
            for key in _deletions(low):
                index.setdefault(key, []).append(n)
        self._index = index
        return index


def _deletions(word: str) -> set[str]:
    """``word`` and every string one deletion from it."""
    return {word, *(word[:i] + word[i + 1:] for i in range(len(word)))}
