"""Fixtures of the runtime tests: the ROS 2 runtime of each release and the workspace of the test components per
release.

Its packages come from the test cache (tests/ros_harness/workspaces.py): built once per content and release on
this machine, whichever worker or run asks first; the workspace itself is a view of them.

A module that sets ``PER_RELEASE = True`` runs once per release ``IFACE_ROS_DISTRO`` selects (default:
every release, ``ros_harness.ros.RELEASES``), its test ids naming the release (``[jazzy-…]``); the
other ROS modules (C++, the README's build) run on Kilted only. A release without its venv skips, saying
why.
"""

from __future__ import annotations

import os
import shutil
import sys
from collections.abc import Generator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from iface.live import deadlock as dds_deadlock
from iface.nodes.shared import RUNTIMES

from ..ros_harness.ros import DATA, DISTRO_VARIABLE, RELEASES, ROOT, build, generate, runtime_venv, selected_releases
from ..ros_harness.systems import COMPONENTS as SYSTEM_COMPONENTS

#: The Python runtime is a package of its own (iface/nodes/runtimes/iface_runtime_py): its tests import it as it is.
sys.path.insert(0, str(RUNTIMES / "iface_runtime_py"))

#: The components the end-to-end tests build and run: (interface, user module of the tests).
COMPONENTS = {
    "robot_arm": (ROOT / "examples" / "robot_arm.iface", DATA / "robot_arm_node.py"),
    "every_member": (DATA / "every_member.iface", DATA / "every_member_node.py"),
}
#: Built beside them for the live tests (test_live.py), not part of the interface-package build test.
LIVE_COMPONENTS = {
    "live_probe": (DATA / "live" / "live_probe.iface", DATA / "live" / "live_probe_node.py"),
}


@dataclass
class Workspace:
    """A colcon workspace with the generated packages of COMPONENTS built and installed."""

    venv: Path
    generated: Path
    path: Path
    seconds: float


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Generator[None, Any, None]:
    """A failed test's report names each process on this machine whose Fast DDS participant is deadlocked
    (``iface.live.deadlock``): what a ROS test that got no answer then waited on."""
    outcome = yield
    report = outcome.get_result()
    if report.failed and call.when == "call":
        found = dds_deadlock.in_domain(None)
        if found:
            report.sections.append(("Fast DDS deadlocks", "\n".join(s.describe() for s in found)))


def pytest_generate_tests(metafunc: pytest.Metafunc) -> None:
    """Every test that runs ROS 2 gets its release: each selected one in a PER_RELEASE module, else Kilted."""
    if "ros_release" not in metafunc.fixturenames:
        return
    releases = selected_releases() if getattr(metafunc.module, "PER_RELEASE", False) else [RELEASES[0]]
    metafunc.parametrize("ros_release", releases, indirect=True, scope="session", ids=releases)


@pytest.fixture(scope="session")
def ros_release(request: pytest.FixtureRequest) -> str:
    """The ROS 2 release of the test (``pytest_generate_tests``)."""
    release = str(request.param)
    if release not in selected_releases():
        pytest.skip(f"runs on {release.capitalize()} only, and {DISTRO_VARIABLE}={os.environ.get(DISTRO_VARIABLE)}")
    return release


@pytest.fixture(scope="session")
def ros_venv(ros_release: str) -> Path:
    venv, why = runtime_venv(ros_release)
    if venv is None:
        pytest.skip(why)
    return venv


@pytest.fixture(scope="session")
def ros_workspace(ros_venv: Path, ros_release: str, tmp_path_factory: pytest.TempPathFactory) -> Workspace:
    """Generate each component (then put the tests' user module in place and generate again) and build them.

    The manager's test system (SYSTEM_COMPONENTS) is here too. Each package is a workspace of its own in the
    test cache, per release; ``path`` is the view of them all (``install/setup.bash`` sources each).
    """
    root = tmp_path_factory.mktemp(f"ros2-{ros_release}")
    gen = root / "gen"
    for package, (iface, user) in {**COMPONENTS, **LIVE_COMPONENTS, **SYSTEM_COMPONENTS}.items():
        first = generate(iface, gen)
        assert first.returncode == 0, first.stderr
        shutil.copyfile(user, gen / package / package / "node.py")
        again = generate(iface, gen)
        assert again.returncode == 0, again.stderr
        assert (gen / package / package / "node.py").read_text() == user.read_text(), "node.py was overwritten"
    ws = root / "ws"
    ws.mkdir()
    ok, tail, seconds = build(ros_venv, gen, ws)
    assert ok, f"the generated packages did not build:\n{tail}"
    print(f"\nros2-runtime ({ros_release}) build (or cache) of "
          f"{', '.join([*COMPONENTS, *LIVE_COMPONENTS, *SYSTEM_COMPONENTS])}: "
          f"{seconds:.0f} s")
    return Workspace(ros_venv, gen, ws, seconds)
