"""Every kind of ROS 2 field can be written, and the model keeps what was written."""

from __future__ import annotations

from iface.model import nodes as m

from .helpers import DATA, compile_file

ROS = DATA / "valid" / "ros_types.iface"


def test_ros_types_check_cleanly() -> None:
    comp = compile_file(ROS)
    assert [d.format() for d in comp.diagnostics] == []


def test_scalars_and_defaults() -> None:
    iface = compile_file(ROS).interface
    scalars = iface.symbols["Scalars"]
    types = {f.name: f.type.name for f in scalars.fields}
    assert types == {"flag": "bool", "raw": "octet", "letter": "char", "i8v": "i8", "u8v": "u8",
                     "i16v": "i16", "u16v": "u16", "i32v": "i32", "u32v": "u32", "i64v": "i64",
                     "u64v": "u64", "f32": "float32", "f64": "float64", "text": "string", "wide": "wstring"}
    defaults = {f.name: f.default.value for f in scalars.fields if f.default}
    assert defaults["u64v"] == 2**64 - 1 and defaults["i64v"] == -(2**63)
    assert defaults["text"] == "it's \"quoted\"" and defaults["wide"] == "Grüße"
    assert scalars.fields[0].default.text == "true"
    assert [(c.name, c.value.value) for c in scalars.consts] == [("ANSWER", 42), ("GREETING", "hello"),
                                                                  ("PI", 3.14159)]


def test_bounds_arrays_and_nested_types() -> None:
    iface = compile_file(ROS).interface
    c = {f.name: f.type for f in iface.symbols["Containers"].fields}
    assert c["short_name"].bound == 10 and c["code"].name == "wstring" and c["code"].bound == 4
    assert (c["fixed"].array, c["fixed"].size) == ("fixed", 3)
    assert (c["bounded"].array, c["bounded"].size) == ("bounded", 5)
    assert (c["unbounded"].array, c["unbounded"].size) == ("unbounded", None)
    bs = c["bounded_strings"]
    assert (bs.array, bs.size, bs.element.bound) == ("bounded", 2, 8)
    poses = c["poses"]
    assert isinstance(poses.element, m.NamedType) and poses.element.external == "geometry_msgs"
    assert c["stamp"].external == "builtin_interfaces"
    assert c["nested"].element.target is iface.symbols["Scalars"]


def test_sections_with_constants_and_wiring() -> None:
    iface = compile_file(ROS).interface
    cfg = iface.symbols["Configure"]
    assert [k.name for k in cfg.request.consts] == ["MODE_FAST"]
    assert [(e.role, e.name) for e in iface.services] == [("provides", "/configure")]
    assert [(e.role, e.name) for e in iface.actions] == [("provides", "/follow")]
    assert [e.name for e in iface.published] == ["/containers"]
    assert [e.name for e in iface.subscribed] == ["scalars"]
    assert iface.namespace("ros2") == "ros_types"
    assert iface.version == "0.3.1"
