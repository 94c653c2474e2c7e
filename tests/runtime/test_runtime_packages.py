"""The runtime packages as real source: copied verbatim, their constants and rules tied to iface's, versioned.

``iface_runtime_py`` and ``iface_runtime_cpp`` live in ``server/iface/nodes/runtimes/`` as the packages
they are; ``generate`` copies their files and adds a generated-file header to each. Their unit tests:
test_runtime_py.py (Python, everywhere) and the C++ programs of ``iface_runtime_cpp/test/``, built and run
by test_rclcpp_e2e.py.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from pathlib import Path

import pytest
from iface_runtime_py import protocol as py_protocol
from iface_runtime_py import state as py_state

from iface.compat.values import widens as compat_widens
from iface.emit.base import GENERATED_MARK
from iface.nodes import protocol, shared
from iface.nodes.component import HANDLER_PREFIXES

from ..ros_harness.ros import DATA

RUNTIMES = ("iface_runtime_py", "iface_runtime_cpp")
#: The version → content hash of each runtime package as generate writes it: a change to its files must
#: come with a new version (``UPDATE_GOLDEN=1`` records a new version's hash).
LOCK = DATA / "runtime_versions.json"
CPP_PROTOCOL = shared.RUNTIMES / "iface_runtime_cpp" / "include" / "iface_runtime_cpp" / "protocol.hpp"
WIDENING = shared.RUNTIMES / "iface_runtime_cpp" / "test" / "widening.txt"


@pytest.mark.parametrize("name", RUNTIMES)
def test_generate_copies_the_package_as_it_is_with_a_header(name: str) -> None:
    package = shared.runtime_package(name)
    sources = shared.source_files(name)
    assert [f.path for f in package.files] == [f"{name}/{path}" for path, _ in sources]
    assert not [p for p, _ in sources if "__pycache__" in p or p.endswith(".pyc")]
    for f, (path, text) in zip(package.files, sources, strict=True):
        header = next(line for line in f.text.splitlines() if GENERATED_MARK in line)
        assert f"{GENERATED_MARK} from {name} {package.version} — do not edit" in header, f.path
        assert f.text.replace(header + "\n", "", 1) == text, f"{f.path} is not the source file plus its header"
    xml = next(f.text for f in package.files if f.path == f"{name}/package.xml").splitlines()
    assert xml[0].startswith("<?xml") and GENERATED_MARK in xml[2]  # after the declarations


def test_a_file_of_an_unknown_kind_is_refused_not_given_a_wrong_comment() -> None:
    with pytest.raises(ValueError, match="no comment syntax for notes.md"):
        shared.with_header("notes.md", "x\n", "iface_runtime_py 1.0.0")


@pytest.mark.parametrize("name", RUNTIMES)
def test_the_version_is_written_once_in_package_xml(name: str) -> None:
    version = shared.source_version(name)
    assert shared.runtime_package(name).version == version
    texts = {path: text for path, text in shared.source_files(name) if path != "package.xml"}
    assert not [p for p, t in texts.items() if version in t], "the version is package.xml's alone"
    if name == "iface_runtime_cpp":
        cmake = texts["CMakeLists.txt"]
        assert "ament_package_xml()" in cmake
        assert 'IFACE_RUNTIME_CPP_VERSION="${${PROJECT_NAME}_VERSION}"' in cmake
    else:
        assert "package.xml" in texts["setup.py"]


def _content_hash(name: str) -> str:
    digest = hashlib.sha256()
    for path, text in shared.source_files(name):
        digest.update(path.encode() + b"\0" + text.encode() + b"\0")
    return "sha256:" + digest.hexdigest()


def test_a_change_to_a_runtime_comes_with_a_new_version() -> None:
    """The lock file holds each runtime's version and the hash of its files; changed files with the same version
    fail (an output folder with the old copy would keep it: generate reuses a copy of the same version)."""
    lock = json.loads(LOCK.read_text(encoding="utf-8"))
    problems, update = [], {}
    for name in RUNTIMES:
        version, digest = shared.source_version(name), _content_hash(name)
        locked = lock.get(name, {})
        if locked.get("version") == version:
            if locked.get("hash") != digest:
                problems.append(f"the files of {name} changed but its version ({version}) did not: raise <version> "
                                f"in {shared.RUNTIMES / name / 'package.xml'}, then run this test with "
                                "UPDATE_GOLDEN=1 to record it in " + str(LOCK))
            continue
        if locked and shared.version_key(version) <= shared.version_key(locked["version"]):  # type: ignore[operator]
            problems.append(f"{name} {version} is not newer than the recorded {locked['version']}")
            continue
        update[name] = {"version": version, "hash": digest}
    if update and not problems and os.environ.get("UPDATE_GOLDEN") == "1":
        LOCK.write_text(json.dumps({**lock, **update}, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    elif update:
        problems += [f"{name} {u['version']} is not recorded in {LOCK}: run this test with UPDATE_GOLDEN=1"
                     for name, u in update.items()]
    assert problems == []


# ---- the constants: one place in each runtime, tied to iface.nodes.protocol --------------------------------


def test_the_python_runtimes_constants_are_the_protocols() -> None:
    assert py_protocol.PROTOCOL_VERSION == protocol.PROTOCOL_VERSION
    assert py_protocol.STATE_FORMAT == protocol.STATE_FORMAT
    assert py_protocol.DIAGNOSTICS_TOPIC == protocol.DIAGNOSTICS_TOPIC
    assert py_protocol.DEFAULT_TIMEOUT_SEC == protocol.DEFAULT_TIMEOUT_SEC
    assert py_protocol.ALIGN_SEC == protocol.ALIGN_SEC
    assert (py_protocol.STATUS, py_protocol.PAUSE, py_protocol.RESUME, py_protocol.SAVE) == (
        protocol.STATUS, protocol.PAUSE, protocol.RESUME, protocol.SAVE)
    assert py_protocol.HANDLER_PREFIXES == HANDLER_PREFIXES


def cpp_constants(text: str) -> dict[str, str]:
    """``inline constexpr T NAME = value`` (and ``A = 1, B = 2``) of a header, as written."""
    out: dict[str, str] = {}
    for declaration in re.findall(r"^inline constexpr [\w:]+(?: \*)? (.+);$", text, re.MULTILINE):
        for name, value in re.findall(r"(\w+) = (\"[^\"]*\"|[^,]+)", declaration):
            out[name] = value.strip()
    return out


def test_the_cpp_runtimes_constants_are_the_protocols() -> None:
    found = cpp_constants(CPP_PROTOCOL.read_text(encoding="utf-8"))
    assert found == {
        "STATE_FORMAT": f'"{protocol.STATE_FORMAT}"', "PROTOCOL_VERSION": f'"{protocol.PROTOCOL_VERSION}"',
        "DIAGNOSTICS_TOPIC": f'"{protocol.DIAGNOSTICS_TOPIC}"', "DEFAULT_TIMEOUT_SEC": repr(protocol.DEFAULT_TIMEOUT_SEC),
        "ALIGN_SEC": repr(protocol.ALIGN_SEC), "STATUS": str(protocol.STATUS), "PAUSE": str(protocol.PAUSE),
        "RESUME": str(protocol.RESUME), "SAVE": str(protocol.SAVE)}
    assert cpp_constants('inline constexpr uint8_t A = 1, B = 2;\ninline constexpr const char * C = "x, y";\n') == \
        {"A": "1", "B": "2", "C": '"x, y"'}


def test_no_runtime_source_holds_a_template() -> None:
    jinja = re.compile(r"\{\{ *[A-Za-z_][\w.|()\[\]\"' ]* *\}\}|\{%")
    assert jinja.search('x = "{{ state_format }}"') and not jinja.search('choices = {{"IDLE", 0}};')
    for name in RUNTIMES:
        for path, text in shared.source_files(name):
            assert not jinja.search(text), f"{name}/{path}"


# ---- the widening rule: one table, three implementations ------------------------------------------------

#: The state document's spelling of each iface base type the rule covers (``component.schema_type``).
IFACE_NAMES = {"bool": "bool", "byte": "octet", "char": "char", "int8": "i8", "uint8": "u8", "int16": "i16",
               "uint16": "u16", "int32": "i32", "uint32": "u32", "int64": "i64", "uint64": "u64",
               "float32": "float32", "float64": "float64", "string": "string", "wstring": "wstring"}


def widening_table() -> dict[tuple[str, str], bool]:
    """(old, new) → may a value saved as old be restored as new, from iface_runtime_cpp/test/widening.txt."""
    rows = [line.split() for line in WIDENING.read_text(encoding="utf-8").splitlines()
            if line.strip() and not line.startswith("#")]
    columns, out = rows[0], {}
    for row in rows[1:]:
        assert len(row) == len(columns) + 1, row
        out.update({(row[0], column): mark == "x" for column, mark in zip(columns, row[1:], strict=True)})
    return out


def test_the_table_covers_every_pair_of_the_state_documents_primitives() -> None:
    table = widening_table()
    assert set(table) == {(a, b) for a in IFACE_NAMES for b in IFACE_NAMES}
    assert all(table[(t, t)] for t in IFACE_NAMES)


@pytest.mark.parametrize("rule", ["compat", "iface_runtime_py"])
def test_compat_and_the_python_runtime_widen_as_the_table_says(rule: str) -> None:
    """compat decides a hand-over (state-type-widened); the runtime restores; the C++ runtime's test_state reads
    the same table. (wchar is not in it: the state document has no rule of its own for it.)"""
    def widens(old: str, new: str) -> bool:
        if rule == "compat":
            return compat_widens(IFACE_NAMES[old], IFACE_NAMES[new])
        return py_state.widens(old, new)

    wrong = [f"{old} → {new}: table {'x' if want else '.'}" for (old, new), want in widening_table().items()
             if widens(old, new) != want]
    assert wrong == []


def test_the_table_catches_a_rule_that_differs(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(py_state._BITS, "uint32", 31)  # a rule that would let uint32 into int32
    assert py_state.widens("uint32", "int32") != widening_table()[("uint32", "int32")]


def test_the_widening_table_is_in_the_generated_cpp_package() -> None:
    files = {f.path: f.text for f in shared.runtime_cpp_package().files}
    text = files["iface_runtime_cpp/test/widening.txt"]
    assert text.splitlines()[0].startswith("# " + GENERATED_MARK)
    assert Path(WIDENING).read_text(encoding="utf-8") in text
