"""Keywords as names: C/C++ ones refused by px4 and ardupilot, warned about by ros2; IDL's escaped; rosidl names."""

from __future__ import annotations

import keyword
import re
from pathlib import Path

import pytest

from iface.emit import generate
from iface.emit.idl.reserved import keyword_of
from iface.emit.keywords import C_FAMILY_KEYWORDS, CPP_KEYWORDS, PYTHON_KEYWORDS, c_family_keyword

from .helpers import compile_text
from .idl_oracle import FASTDDSGEN, IDLC, NO_FASTDDSGEN, NO_IDLC, code_of, escaped_names, fastddsgen, idlc_header, \
    unescaped

KW = "component kw\nmessage Kw { u64 timestamp, i32 class, i32 sequence, float32 delete }\npublishes Kw on \"/kw\"\n"


def at(comp, result, code: str) -> list[str]:
    """The source text at each diagnostic ``code``."""
    text = comp.interface.source.text
    return sorted(text[d.span.start:d.span.end] for d in result.diagnostics if d.code == code)


def test_the_keyword_tables() -> None:
    assert {"class", "delete", "co_await", "char8_t", "requires", "and_eq", "consteval"} <= CPP_KEYWORDS
    assert len(CPP_KEYWORDS) == 92  # C++20 [lex.key] (81) and the 11 alternative tokens
    assert "restrict" in C_FAMILY_KEYWORDS - CPP_KEYWORDS
    assert PYTHON_KEYWORDS == frozenset(keyword.kwlist)


def test_px4_refuses_cpp_keyword_fields_at_the_field() -> None:
    comp = compile_text(KW, "kw.iface")
    result = generate(comp, "px4")
    assert result.has_errors and result.files == []
    assert at(comp, result, "px4-reserved-name") == ["class", "delete"]
    assert all("C++ keyword" in d.message for d in result.diagnostics if d.code == "px4-reserved-name")


def test_px4_refuses_a_cpp_keyword_constant() -> None:
    comp = compile_text("component kw\nmessage K { u64 timestamp, const i32 and = 1 }\npublishes K on \"/k\"\n",
                        "kw.iface")
    result = generate(comp, "px4")
    # uORB constants are UPPER_CASE (AND), which no keyword is: nothing to refuse
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    assert "int32 AND = 1" in next(f.text for f in result.files if f.path == "msg/K.msg")


def test_ardupilot_refuses_cpp_keyword_fields_at_the_field() -> None:
    comp = compile_text(KW, "kw.iface")
    result = generate(comp, "ardupilot")
    assert result.has_errors and result.files == []
    assert at(comp, result, "ap-reserved-name") == ["class", "delete"]
    assert at(comp, result, "idl-reserved-name") == []  # sequence, an IDL keyword, is written escaped


@pytest.mark.parametrize("target", ["ros2", "idl"])
def test_ros2_warns_about_cpp_and_python_keywords(target: str) -> None:
    src = "component kw\nmessage Kw { i32 class, i32 restrict, i32 lambda, i32 fine }\n"
    comp = compile_text(src, "kw.iface")
    result = generate(comp, target)
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    assert at(comp, result, "ros2-reserved-name") == ["class", "restrict"]
    assert at(comp, result, "ros2-python-keyword") == ["lambda"]
    (d,) = [d for d in result.diagnostics if d.code == "ros2-python-keyword"]
    assert "rosidl_generator_py" in d.message
    assert all(d.severity == 2 for d in result.diagnostics if d.code.startswith("ros2-"))


def test_a_package_named_like_a_keyword_is_warned_about(tmp_path: Path) -> None:
    comp = compile_text("message M { i32 x }\n", "delete.iface", tmp_path)
    result = generate(comp, "ros2")
    assert any(d.code == "ros2-reserved-name" and "package 'delete'" in d.message for d in result.diagnostics)


def test_ros2_refuses_a_type_name_too_long_for_rosidl_files() -> None:
    fits, too_long = "A" * 213, "A" * 214
    ok = generate(compile_text(f"component c\nmessage {fits} {{ i32 x }}\n", "names.iface"), "ros2")
    assert not ok.has_errors, [d.format() for d in ok.diagnostics]
    comp = compile_text(f"component c\nmessage {too_long} {{ i32 x }}\n", "names.iface")
    result = generate(comp, "ros2")
    assert result.has_errors and result.files == []
    assert at(comp, result, "ros2-name-too-long") == [too_long]
    camel = "Ab" * 107  # 214 characters, 320 in snake_case (ab_ab_…)
    assert generate(compile_text(f"component c\nmessage {camel} {{ i32 x }}\n", "names.iface"), "ros2").has_errors


# ---- every keyword of .iface, Thrift and IDL as a name, through every target ---------------------------

#: Thrift's keywords (compiler/cpp/src/thrift/thriftl.ll of Apache Thrift 0.20, with uuid of 0.19).
THRIFT_KEYWORDS = frozenset("""
false true namespace cpp_namespace cpp_include cpp_type java_package csharp_namespace delphi_namespace
php_namespace py_module perl_package ruby_namespace smalltalk_category smalltalk_prefix xsd_all xsd_optional
xsd_nillable xsd_namespace xsd_attrs include void bool byte i8 i16 i32 i64 double string binary uuid slist senum
map list set oneway typedef struct union exception extends throws service enum const required optional async
""".split())


def _all_keywords() -> list[str]:
    from iface.emit.idl.reserved import IDL_KEYWORDS
    from iface.semantics.query import RESERVED

    return sorted(RESERVED | THRIFT_KEYWORDS | IDL_KEYWORDS)


ROLES = {
    "field": "component kw\nmessage M {{ u64 timestamp, i32 {k} }}\npublishes M on \"/m\"\n",
    "constant": "component kw\nmessage M {{ u64 timestamp, const i32 {k} = 1 }}\npublishes M on \"/m\"\n",
    "type": "component kw\nmessage {k} {{ u64 timestamp, i32 x }}\npublishes {k} on \"/m\"\n",
}
TARGETS = ["ros2", "idl", "json", "markdown", "px4", "ardupilot"]
#: The targets that write IDL's escape (``_struct``) for a name colliding with an IDL keyword.
ESCAPING = ("idl", "ardupilot")


def _read_back(target: str, path: str, text: str) -> None:
    """The written file as the target platform's parser reads it (raises when it refuses)."""
    if path.endswith(".msg") and target == "ros2":
        from mcap_ros2._vendor.rosidl_adapter.parser import parse_message_string

        parse_message_string("kw", Path(path).stem, text)
    elif path.endswith(".msg") and target == "px4":
        import genmsg
        import genmsg.msg_loader

        genmsg.msg_loader.load_msg_from_string(genmsg.MsgContext.create_default(), text, f"px4_msgs/{Path(path).stem}")
    elif path.endswith(".idl"):
        from iface.importers.idl import read_idl

        # rosbags reads no escaped name (_struct): it reads the text as IDL's lexical rule makes it
        read_idl(unescaped(text) if target in ESCAPING else text)
    elif path.endswith(".json"):
        import json

        json.loads(text)


@pytest.mark.parametrize("role", sorted(ROLES))
def test_every_keyword_as_a_name_is_written_and_read_back_or_refused_at_the_name(role: str, tmp_path: Path) -> None:
    pytest.importorskip("rosbags")
    pytest.importorskip("mcap_ros2")
    pytest.importorskip("genmsg")
    keywords = _all_keywords()
    assert len(keywords) >= 120 and {"message", "oneway", "senum", "module", "wstring", "valuetype"} <= set(keywords)
    written: dict[str, int] = dict.fromkeys(TARGETS, 0)
    escapes: dict[str, int] = dict.fromkeys(ESCAPING, 0)
    refused_ap: list[str] = []
    for k in keywords:
        comp = compile_text(ROLES[role].format(k=k), f"{role}_{k}.iface", tmp_path)
        assert not [d for d in comp.all_diagnostics() if d.severity == 1], k
        text = comp.interface.source.text
        for target in TARGETS:
            result = generate(comp, target)
            errors = [d for d in result.diagnostics if d.severity == 1]
            if errors:  # refused: each error has a code and points at the keyword-named thing
                assert result.files == []
                if target == "ardupilot":  # C/C++ keywords only: IDL keywords are escaped
                    assert {d.code for d in errors} == {"ap-reserved-name"}, [d.format() for d in errors]
                    refused_ap.append(k)
                for d in errors:
                    assert d.code and k in text[d.span.start:d.span.end], (target, k, d.format())
                continue
            written[target] += 1
            assert any(k.lower() in f.text.lower() for f in result.files), (target, k)
            if target in ESCAPING:  # every escape is of a name colliding with an IDL keyword, and k is escaped
                idl = [f.text for f in result.files if f.path.endswith(".idl")]
                names = [n for text in idl for n in escaped_names(text)]
                assert all(keyword_of(n) for n in names), (target, k, names)
                # unless lowering renamed it (ValueBase → value_base): then it is in no identifier of the code
                assert keyword_of(k) is None or k.lower() in {n.lower() for n in names} or not any(
                    re.search(rf"(?<!\w){k}(?!\w)", code_of(text), re.I) for text in idl), (target, k)
                escapes[target] += len(names)
            for f in result.files:
                try:
                    _read_back(target, f.path, f.text)
                except Exception as e:  # the platform's parser refused what the target wrote
                    pytest.fail(f"{target} wrote {f.path} for {role} {k!r}, which its parser refuses: {e}")
    # targets without keyword limits write every one; the others refuse only what their language reserves
    assert written["json"] == written["markdown"] == written["ros2"] == written["idl"] == len(keywords), written
    assert all(n > 0 for n in written.values()), written
    assert written["ardupilot"] + len(refused_ap) == len(keywords) and all(c_family_keyword(k.lower())
                                                                            for k in refused_ap), refused_ap
    idl_keywords = sum(keyword_of(k) is not None for k in keywords)
    assert escapes["idl"] >= idl_keywords - 1 and escapes["ardupilot"] >= idl_keywords - 1 - len(refused_ap), escapes


def _idl_files(role: str, target: str, root: Path) -> dict[str, list[Path]]:
    """Every keyword's .idl files, for ``target`` in ``role``, written under ``root`` (the IDL include root)."""
    out: dict[str, list[Path]] = {}
    for k in _all_keywords():
        comp = compile_text(ROLES[role].format(k=k), f"{role}_{k}.iface", root.parent)
        result = generate(comp, target)
        for f in result.files:
            if f.path.endswith(".idl"):
                path = root / f.path.removeprefix("libraries/AP_DDS/Idl/")
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_text(f.text)
                out.setdefault(k, []).append(path)
    return out


@pytest.mark.skipif(IDLC is None, reason=NO_IDLC)
@pytest.mark.parametrize("target", ESCAPING)
@pytest.mark.parametrize("role", sorted(ROLES))
def test_every_keyword_name_compiles_with_idlc_which_strips_the_escape(role: str, target: str, tmp_path: Path) -> None:
    """Cyclone DDS's idlc compiles each file and declares the escaped names without their underscore."""
    files = _idl_files(role, target, tmp_path / "idl")
    assert len(files) >= (len(_all_keywords()) if target == "idl" else 100), len(files)
    stripped = 0
    for k, paths in files.items():
        for path in paths:
            proc, header = idlc_header(tmp_path / "idl", path, tmp_path / "c" / k)
            assert proc.returncode == 0, (k, path.read_text(), proc.stderr)
            for n in escaped_names(path.read_text()):
                assert re.search(rf"(?<![A-Za-z0-9_]){n}\b|[a-z]_{n}\b", header), (k, n, header)
                assert not re.search(rf"(?<![A-Za-z0-9])_{n}\b|__{n}\b", header), (k, n, header)
                stripped += 1
    assert stripped >= sum(keyword_of(k) is not None for k in files) - 1, stripped  # ValueBase: lowered apart


@pytest.mark.skipif(FASTDDSGEN is None, reason=NO_FASTDDSGEN)
@pytest.mark.parametrize("role", sorted(ROLES))
def test_every_keyword_name_builds_with_fastddsgen_as_ardupilot_builds_it(role: str, tmp_path: Path) -> None:
    """Fast-DDS-Gen (ArduPilot builds with its fork) reads every escaped declaration ardupilot writes."""
    root = tmp_path / "idl"
    files = _idl_files(role, "ardupilot", root)
    parts = sorted(p.relative_to(root).as_posix() for ps in files.values() for p in ps)
    assert len(parts) >= 100, len(parts)
    top = tmp_path / "together.idl"  # one file including all: one run of the generator reads every one
    top.write_text("".join(f'#include "{p}"\n' for p in parts))
    proc = fastddsgen(root, [top], tmp_path / "gen")
    assert proc.returncode == 0 and "error" not in proc.stdout.lower(), proc.stdout + proc.stderr
    header = (tmp_path / "gen" / "together.h").read_text()
    assert all(f'#include "{Path(p).with_suffix(".h").as_posix()}"' in header for p in parts), header[:2000]


@pytest.mark.skipif(FASTDDSGEN is None, reason=NO_FASTDDSGEN)
def test_fastddsgen_resolves_no_escaped_type_reference(tmp_path: Path) -> None:
    """The control behind ardupilot's idl-reserved-name: the idl target's escaped reference, refused."""
    src = 'component kw\nmessage Object { i32 x }\nmessage Holder { Object o }\npublishes Holder on "/h"\n'
    result = generate(compile_text(src, "kw.iface", tmp_path), "idl")
    for f in result.files:
        (tmp_path / f.path).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / f.path).write_text(f.text)
    holder = next(tmp_path.rglob("Holder.idl"))
    assert "      kw::msg::_Object o;\n" in holder.read_text()
    if IDLC is not None:  # the spec's form: idlc resolves it
        proc, header = idlc_header(tmp_path, holder, tmp_path / "c")
        assert proc.returncode == 0 and "struct kw_msg_Object o;" in header, proc.stderr + header
    proc = fastddsgen(tmp_path, [holder], tmp_path / "gen")
    assert "was not defined previously" in proc.stdout + proc.stderr, proc.stdout + proc.stderr


# ---- the node targets: each language's keywords, through the interface package and the node code ----------

#: The node targets and the language of their node code.
NODE_TARGETS = {"rclpy": "python", "rclcpp": "c++"}
#: The roles of ROLES, and the names only the node code takes: a parameter (its accessor) and a state field.
NODE_ROLES = {
    **ROLES,
    "parameter": "component kw\nmessage M {{ u64 timestamp, i32 x }}\nconfiguration params {{ i32 {k} = 1 }}\n"
                 "publishes M on \"/m\"\n",
    "state": "component kw\nmessage M {{ u64 timestamp, i32 x }}\nstate s {{ i32 {k} }}\npublishes M on \"/m\"\n",
}
#: The name that takes the keyword's place in the control run (no keyword of any language).
NEUTRAL = "zqname"
#: The interface package's codes each node target refuses (``runtime-reserved-name``) instead of warning.
REFUSED = {"rclpy": {"ros2-reserved-name", "ros2-python-keyword"}, "rclcpp": {"ros2-reserved-name"}}
_CPP_NOISE = re.compile(r'//[^\n]*|/\*.*?\*/|R"(\w*)\(.*?\)\1"|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)


def cpp_keyword_tokens(files: list) -> dict[str, int]:
    """How often each C++ keyword is a token of the component's C++ code (comments and literals left out)."""
    counts: dict[str, int] = {}
    for f in files:
        if f.path.endswith((".cpp", ".hpp")):
            for token in re.findall(r"[A-Za-z_]\w*", _CPP_NOISE.sub(" ", f.text)):
                if token in CPP_KEYWORDS:
                    counts[token] = counts.get(token, 0) + 1
    return counts


def python_errors(files: list) -> list[str]:
    """``path:line: message`` of each written .py file Python cannot compile."""
    out = []
    for f in files:
        if f.path.endswith(".py"):
            try:
                compile(f.text, f.path, "exec")
            except SyntaxError as e:
                out.append(f"{f.path}:{e.lineno}: {e.msg}")
    return out


def test_node_code_checks_can_fail() -> None:
    """The two checks below see a keyword where node code would take one."""
    from iface.emit.base import GeneratedFile

    assert python_errors([GeneratedFile("a/base.py", "from kw_msgs.msg import True as KwTrue\n")])
    hpp = "// class in a comment\nconst char * s = \"delete\";\nstruct A { int x; };\nvoid f(A & a) { a.class_ = 1; }\n"
    assert cpp_keyword_tokens([GeneratedFile("a.hpp", hpp)]) == {"const": 1, "char": 1, "struct": 1, "int": 1,
                                                                 "void": 1}
    assert cpp_keyword_tokens([GeneratedFile("a.cpp", "void f(A & a) { a.delete = 1; }\n")])["delete"] == 1


@pytest.mark.parametrize("target", sorted(NODE_TARGETS))
@pytest.mark.parametrize("role", sorted(NODE_ROLES))
def test_every_keyword_through_the_node_targets(role: str, target: str, tmp_path: Path) -> None:
    """Refused at the name exactly where the interface package's rule meets the node's language; else valid code.

    Written: every .py file compiles, and the C++ code has each C++ keyword as often as with a neutral
    name in its place (the keyword became no identifier; a full compile needs the generated messages).
    """
    keywords = _all_keywords()
    control = generate(compile_text(NODE_ROLES[role].format(k=NEUTRAL), f"{role}_{NEUTRAL}.iface", tmp_path), target)
    assert not control.has_errors and control.files, [d.format() for d in control.diagnostics]
    baseline = cpp_keyword_tokens(control.files)
    written, refused = 0, []
    for k in keywords:
        comp = compile_text(NODE_ROLES[role].format(k=k), f"{role}_{k}.iface", tmp_path)
        assert not [d for d in comp.all_diagnostics() if d.severity == 1], k
        text = comp.interface.source.text
        ros2 = generate(comp, "ros2")
        rule = sorted((d.span.start, d.span.end) for d in ros2.diagnostics if d.code in REFUSED[target])
        result = generate(comp, target)
        errors = [d for d in result.diagnostics if d.severity == 1]
        assert sorted((d.span.start, d.span.end) for d in errors) == rule, (k, [d.format() for d in errors])
        if errors:
            assert result.files == [] and {d.code for d in errors} == {"runtime-reserved-name"}, k
            assert all(k in text[d.span.start:d.span.end] for d in errors), (k, [d.format() for d in errors])
            refused.append(k)
            continue
        written += 1
        assert not python_errors(result.files), (target, role, k, python_errors(result.files))
        assert cpp_keyword_tokens(result.files) == baseline, (target, role, k)
        # the interface package's warnings that the node's language does not make errors are still given
        kept = {d.code for d in ros2.diagnostics if d.code in REFUSED["rclpy"] - REFUSED[target]}
        assert kept <= {d.code for d in result.diagnostics}, (k, kept)
    assert written + len(refused) == len(keywords) and written >= 100, (written, refused)
    if role in ("field", "state"):  # fields keep their (lower-case) name: the C/C++ keywords among them are refused
        assert {"true", "void", "struct", "namespace", "double", "TRUE"} <= set(refused), refused
        assert ("import" in refused) == ("async" in refused) == (target == "rclpy"), refused
    elif role == "type":  # types are CamelCase: only Python's True/False/None, and only for Python
        from iface.model.naming import ros_type_name

        python = [k for k in keywords if ros_type_name(k) in PYTHON_KEYWORDS]
        assert refused == (python if target == "rclpy" else []) and python == ["false", "true"], refused
    else:  # constants are UPPER_CASE; parameters take an escaped accessor in the node code
        assert refused == [], refused


def test_keyword_parameters_get_escaped_accessors(tmp_path: Path) -> None:
    src = NODE_ROLES["parameter"].format(k="class")
    comp = compile_text(src, "param_class.iface", tmp_path)
    py_base = next(f.text for f in generate(comp, "rclpy").files if f.path.endswith("/base.py"))
    assert "    def class_(self) -> int:" in py_base and "ParamSpec('class', " in py_base
    hpp = next(f.text for f in generate(comp, "rclcpp").files if f.path.endswith("/base.hpp"))
    assert re.search(r"\bclass_\(\) const", hpp), hpp


WIRED = """component kw
message M {{ u64 timestamp, i32 x }}
service S {{ request {{ i32 a }} response {{ i32 b }} }}
action A {{ goal {{ i32 g }} result {{ i32 r }} feedback {{ i32 f }} }}
publishes M on "/{a}"
subscribes M on "/{b}"
provides S on "/{b}"
calls S on "/{c}"
provides A on "/{d}"
calls A on "/{e}"
"""


@pytest.mark.parametrize("target", sorted(NODE_TARGETS))
def test_keyword_wire_names_take_prefixed_handler_names(target: str, tmp_path: Path) -> None:
    """``publishes M on "/true"``, a service named ``class``…: every derived name has a prefix or a suffix."""
    names = {"a": "true", "b": "class", "c": "import", "d": "def", "e": "delete"}
    comp = compile_text(WIRED.format(**names), "wired_kw.iface", tmp_path)
    control = generate(compile_text(WIRED.format(**dict.fromkeys(names, NEUTRAL)).replace(
        f'"/{NEUTRAL}"', '"/zq"', 1), "wired_zq.iface", tmp_path), target)
    result = generate(comp, target)
    assert not result.has_errors and not control.has_errors, [d.format() for d in result.diagnostics]
    assert not python_errors(result.files), python_errors(result.files)
    assert cpp_keyword_tokens(result.files) == cpp_keyword_tokens(control.files)
    code = "".join(f.text for f in result.files if f.path.endswith((".py", ".hpp", ".cpp")))
    for name in ("publish_true", "on_class", "handle_class", "call_import", "execute_def", "send_delete_goal"):
        assert re.search(rf"\b{name}\b", code), (target, name)


def test_a_message_named_like_a_builtin_the_node_code_raises_is_imported_under_an_alias(tmp_path: Path) -> None:
    src = 'component kw\nmessage NotImplementedError { i32 x }\nsubscribes NotImplementedError on "/m"\n'
    result = generate(compile_text(src, "builtin.iface", tmp_path), "rclpy")
    base = next(f.text for f in result.files if f.path.endswith("/base.py"))
    assert "import NotImplementedError as BuiltinNotImplementedError" in base, base
    assert "msg: BuiltinNotImplementedError" in base and "raise NotImplementedError('on_m')" in base
