"""From a component description to the text of the rclcpp package: C++ literals, names, includes, state codecs."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from ...emit.ros2.filenames import rosidl_snake
from ...emit.ros2.package import RosPackage
from ...emit.text import comment_lines, one_line
from ..component import ComponentSpec, ParamSpec, RosRef, schema_type
from ..qosmap import node_qos
from ..template_data import MemberView, NodeView, type_aliases

#: Names the runtime defines in the base class's scope: a type alias must not take them.
_TAKEN = frozenset({"ComponentNode", "Json", "Type", "ParamSpec", "Gate", "StateError", "Info"})


def cpp_str(text: str) -> str:
    """A C++ string literal (UTF-8 kept; quotes, backslashes and control characters escaped)."""
    out = []
    for ch in text:
        if ch in ('"', "\\"):
            out.append("\\" + ch)
        elif ch == "\n":
            out.append("\\n")
        elif ch == "\t":
            out.append("\\t")
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\{ord(ch):03o}")
        elif ch == "?":
            out.append("\\?")  # no trigraphs
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def cpp_comment(text: str) -> str:
    """Text safe inside a ``//`` or ``/* */`` comment."""
    return one_line(text).replace("*/", "* /").replace("\\", "/")


def cpp_double(value: float) -> str:
    """A C++ double literal."""
    if math.isnan(value):
        return "std::numeric_limits<double>::quiet_NaN()"
    if math.isinf(value):
        return ("-" if value < 0 else "") + "std::numeric_limits<double>::infinity()"
    text = repr(float(value))
    return text if any(c in text for c in ".e") else text + ".0"


def cpp_value(value: Any, kind: str) -> str:
    """An ``rclcpp::ParameterValue`` constructor argument for a parameter default of ``kind``."""
    if kind.endswith("_array"):
        element = kind[: -len("_array")]
        ctype = {"bool": "bool", "integer": "int64_t", "double": "double", "string": "std::string"}[element]
        items = ", ".join(cpp_value(v, element) for v in value)
        return f"std::vector<{ctype}>{{{items}}}"
    if kind == "bool":
        return "true" if value else "false"
    if kind == "integer":
        number = int(value)
        return f"int64_t{{{number}}}" if number > -(2 ** 63) else "std::numeric_limits<int64_t>::min()"
    if kind == "double":
        return cpp_double(float(value))
    return f"std::string({cpp_str(str(value))})"


def qos_map(qos: dict[str, str]) -> str:
    """The member's QoS as the runtime's ``qos()`` reads it: policy → value text (durations in seconds)."""
    from ...model import qos as rules

    pairs = [(k, repr(float(v)) if k in rules.DURATIONS else str(v)) for k, v in node_qos(qos)]
    return "{" + ", ".join(f"{{{cpp_str(k)}, {cpp_str(v)}}}" for k, v in pairs) + "}"


@dataclass
class StateMessage:
    """A message type of the state document: its C++ type and its fields (name, schema type)."""

    name: str
    cpp: str
    fields: list[tuple[str, str]]

    @property
    def namespace(self) -> str:
        """``robot_arm_msgs::msg``."""
        return self.cpp[2:].rsplit("::", 1)[0]


@dataclass
class CppPackage(NodeView[MemberView]):
    """Everything the templates of the C++ component package need."""

    state_messages: list[StateMessage] = field(default_factory=list)
    unsupported: list[str] = field(default_factory=list)

    client_library = "rclcpp"

    def comment(self, text: str) -> str:
        """One line, safe inside a ``//`` or ``/* */`` comment."""
        return cpp_comment(text)

    @property
    def plugin(self) -> str:
        """The rclcpp component's class: ``counter::Counter``."""
        return f"{self.pkg}::{self.cls}"

    @property
    def versioned(self) -> str:
        """The package's name with its version (``counter@2.0.0``): the component's second name in the ament index."""
        return f"{self.pkg}@{self.spec.ros.version}"

    @property
    def guard(self) -> str:
        return f"{self.pkg.upper()}__BASE_HPP_"

    @staticmethod
    def cpp(ref: RosRef) -> str:
        """``::robot_arm_msgs::msg::JointState``."""
        return f"::{ref.package}::{ref.kind}::{ref.name}"

    def includes(self) -> list[str]:
        """The headers of every interface type the node uses, sorted."""
        return sorted({f"{r.package}/{r.kind}/{rosidl_snake(r.name)}.hpp" for r in self.spec.types()})

    def params(self) -> list[tuple[ParamSpec, str]]:
        """(parameter, its C++ accessor name) in the file's order."""
        return [(p, _cpp_ident(p.accessor.rstrip("_"))) for p in self.spec.params]

    def param_literal(self, p: ParamSpec) -> list[str]:
        """Lines that fill an ``iface_runtime::ParamSpec`` named ``p``."""
        out = [f"p.name = {cpp_str(p.name)};", f"p.kind = {cpp_str(p.kind)};",
               f"p.description = {cpp_str(p.description)};", f"p.constraints = {cpp_str(p.constraints)};"]
        if p.default is not None:
            out.append(f"p.default_value = rclcpp::ParameterValue({cpp_value(p.default, p.kind)});")
        if p.unit:
            out.append(f"p.unit = {cpp_str(p.unit)};")
        for side, value in (("low", p.low), ("high", p.high)):
            if value is None:
                continue
            number = cpp_double(float(value))
            whole = f"int64_t{{{int(value)}}}" if isinstance(value, int) and value > -(2 ** 63) else \
                "std::numeric_limits<int64_t>::min()" if isinstance(value, int) else f"int64_t{{{math.ceil(value)}}}" \
                if side == "low" else f"int64_t{{{math.floor(value)}}}"
            out.append(f"p.{side} = iface_runtime::Bound{{{number}, {whole}, {cpp_str(str(value))}}};")
        if p.read_only:
            out.append("p.read_only = true;")
        for n, v in p.choices:
            out.append(f"p.choices.emplace_back({cpp_str(n)}, {v});")
        if p.max_length is not None:
            out.append(f"p.max_length = {p.max_length};")
        if p.size is not None:
            out.append(f"p.size = {p.size};")
            out.append(f"p.size_kind = {cpp_str(p.size_kind or '')};")
        return out

    def param_type(self, p: ParamSpec) -> tuple[str, str]:
        """(C++ type, ``rclcpp::Parameter`` getter) of a typed accessor."""
        return {"bool": ("bool", "as_bool"), "integer": ("int64_t", "as_int"), "double": ("double", "as_double"),
                "string": ("std::string", "as_string"), "bool_array": ("std::vector<bool>", "as_bool_array"),
                "integer_array": ("std::vector<int64_t>", "as_integer_array"),
                "double_array": ("std::vector<double>", "as_double_array"),
                "string_array": ("std::vector<std::string>", "as_string_array")}[p.kind]

    def executor_threads(self) -> str:
        return (f"4 + 2 * {len(self.of_kind('action_server'))} + "
                f"{1 if self.of_kind('client', 'action_client') else 0}")


_KEYWORDS = frozenset("""alignas alignof and and_eq asm auto bitand bitor bool break case catch char char8_t char16_t
char32_t class compl concept const consteval constexpr constinit const_cast continue co_await co_return co_yield
decltype default delete do double dynamic_cast else enum explicit export extern false float for friend goto if
inline int long mutable namespace new noexcept not not_eq nullptr operator or or_eq private protected public
register reinterpret_cast requires return short signed sizeof static static_assert static_cast struct switch
template this thread_local throw true try typedef typeid typename union unsigned using virtual void volatile
wchar_t while xor xor_eq""".split())  # noqa: SIM905 - the list as the standard prints it


def _cpp_ident(name: str) -> str:
    return name + "_" if name in _KEYWORDS else name


def _doc(text: str | None) -> list[str]:
    return [cpp_comment(line) if line else "" for line in comment_lines(text)]


def _state_messages(spec: ComponentSpec) -> tuple[list[StateMessage], list[str]]:
    """The message types the state document describes (nested ones too), and those it cannot (other packages)."""
    pkg: RosPackage = spec.ros
    by_name = {ri.name: ri for ri in pkg.interfaces if ri.kind == "msg"}
    out: dict[str, StateMessage] = {}
    unsupported: list[str] = []
    todo = [s.type for s in spec.state]
    while todo:
        text = todo.pop(0)
        base = text.split("[")[0].split("<=")[0]
        if "/" not in base or base in out:
            continue
        package, name = base.split("/", 1)
        ri = by_name.get(name) if package == pkg.name else None
        if ri is None:
            if base not in unsupported:
                unsupported.append(base)
            continue
        fields = [(f.name, schema_type(f.type, pkg.name)) for f in ri.sections[0].fields]
        out[base] = StateMessage(base, f"::{package}::msg::{name}", fields)
        todo.extend(t for _, t in fields)
    return sorted(out.values(), key=lambda s: s.name), unsupported


def build(spec: ComponentSpec) -> CppPackage:
    """The view of ``spec`` the templates render."""
    view = CppPackage(spec, spec.source_name, type_aliases(spec, _TAKEN))
    view.members = [MemberView(x, view.aliases[x.type], qos_map(x.qos), _doc("\n".join(x.doc)), view.comment(x.what))
                    for x in spec.all_members()]
    view.state_messages, view.unsupported = _state_messages(spec)
    return view


__all__ = ["CppPackage", "build", "cpp_comment", "cpp_double", "cpp_str"]
