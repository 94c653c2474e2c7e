"""Restart policy and intensity (R restarts within T seconds), without ROS."""

from __future__ import annotations

import pytest

from iface.operate.restart import DEFAULT_MAX_RESTARTS, DEFAULT_PERIOD, Intensity, should_restart


@pytest.mark.parametrize(("policy", "failed", "expected"), [
    ("never", True, False), ("never", False, False), ("on-failure", True, True), ("on-failure", False, False),
    ("always", True, True), ("always", False, True)])
def test_policy(policy: str, failed: bool, expected: bool) -> None:
    assert should_restart(policy, failed) is expected


def test_intensity_stops_at_r_within_t_and_forgets_older_restarts() -> None:
    limit = Intensity(3, 10.0)
    assert [limit.allow(t) for t in (0.0, 1.0, 2.0, 3.0)] == [True, True, True, False]
    assert limit.allow(9.9) is False
    assert limit.allow(10.0) is True  # the restart at 0.0 is out of the window
    assert limit.allow(10.5) is False


def test_defaults_are_documented() -> None:
    from ..ros_harness.ros import ROOT

    text = (ROOT / "docs" / "system.md").read_text(encoding="utf-8")
    assert f"{DEFAULT_MAX_RESTARTS} restarts within {DEFAULT_PERIOD:g} s" in text
