"""The node targets are one pipeline (``iface.nodes.pipeline``) with a language each: what each language says."""

from __future__ import annotations

import pytest

from iface.emit import get_target
from iface.nodes import pipeline
from iface.nodes.rclcpp import LANGUAGE as CPP
from iface.nodes.rclpy import LANGUAGE as PY
from iface.semantics.compile import Workspace

from ..ros_harness.ros import ROOT

LANGUAGES = {"rclpy": PY, "rclcpp": CPP}


@pytest.mark.parametrize("name", sorted(LANGUAGES))
def test_each_target_is_the_pipeline_with_its_language(name: str) -> None:
    language = LANGUAGES[name]
    target = get_target(name)
    assert target is not None and target.templates == str(language.templates)
    comp = Workspace().compile_path(str(ROOT / "examples" / "counter_v2.iface"))
    by_target = target.generate(comp, {})
    by_pipeline = pipeline.generate(language, comp, {})
    assert [(f.path, f.text, f.once) for f in by_target.files] == [(f.path, f.text, f.once) for f in by_pipeline.files]


@pytest.mark.parametrize("name", sorted(LANGUAGES))
def test_a_language_names_one_user_file_and_templates_that_exist(name: str) -> None:
    language = LANGUAGES[name]
    assert [f for f in language.files if f.comment is None] == [language.user_file]
    for f in language.files:
        assert (language.templates / f.template).is_file(), f.template


def test_the_targets_describe_themselves_as_before() -> None:
    """``iface-lsp targets`` prints these."""
    assert PY.target_descriptor().description == (
        "ROS 2 component package (rclpy lifecycle node: parameters, QoS, state save/restore, diagnostics, launch "
        "file) beside its interface package")
    assert CPP.target_descriptor().description == (
        "ROS 2 component package in C++ (rclcpp lifecycle node: parameters, QoS, state save/restore, diagnostics, "
        "launch file) beside its interface package")


def test_the_user_file_is_found_where_the_language_writes_it() -> None:
    from iface.nodes.component import node_spec

    spec = node_spec(Workspace().compile_path(str(ROOT / "examples" / "robot_arm.iface")))
    assert spec is not None
    assert pipeline.user_file_path(PY, "out", spec) == "out/robot_arm/robot_arm/node.py"
    assert pipeline.user_file_path(CPP, "out", spec) == "out/robot_arm/src/node.cpp"
