"""Starting a generated node as a user does: the README's commands, and user code the interface no longer matches.

The README's "From the interface to a running node" blocks are run as written (in a temporary folder that
holds the examples; the runtime's ros2-env.sh where the block names the default one; the folder the colcon
build made is kept in the test cache and used again while the lines and what they build stay the same): the
first builds and starts the node with `ros2 run`, the second looks at it with `ros2 node info`, `ros2 lifecycle get` and
`ros2 param describe`, each given `--no-daemon` and asked again within a bound while it does not see the node
yet (`node info` with a spin time of 2 s, the others 0.5 s first and longer when asked again:
ros_harness/ros2cli.py). Loopback only, a random ROS_DOMAIN_ID, every wait bounded,
every process stopped by its own handle.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

from ..ros_harness import cache
from ..ros_harness.ros import DEFAULT_VENV, ROOT, environment, run_bounded, sourced
from ..ros_harness.ros2cli import Launched, cmdline, iface_lsp_on_path, ros2
from ..ros_harness.standby_probe import findings
from ..ros_harness.workspaces import toolchain
from .conftest import Workspace

SECTION = "## From the interface to a running node"
TUTORIAL = ROOT / "docs" / "tutorial.md"
DEFAULT_ENV = "~/.cache/ros2-runtime/ros2-env.sh"

#: Drives /robot_arm (started without --activate) through configure and activate, printing what exists when.
LIFECYCLE = textwrap.dedent("""
    import time
    import rclpy
    from rclpy.node import Node
    from lifecycle_msgs.msg import Transition
    from lifecycle_msgs.srv import ChangeState, GetState
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from robot_arm_msgs.msg import JointState

    def call(node, srv, name, request):
        client = node.create_client(srv, name)
        assert client.wait_for_service(timeout_sec=20), name
        future = client.call_async(request)
        rclpy.spin_until_future_complete(node, future, timeout_sec=20)
        assert future.result() is not None, name
        return future.result()

    def spin(node, seconds, until=lambda: False):
        end = time.monotonic() + seconds
        while time.monotonic() < end and not until():
            rclpy.spin_once(node, timeout_sec=0.1)
        return until()

    def members(node):
        if "robot_arm" not in node.get_node_names():  # not discovered yet
            return False, False, False
        services = {s for s, _ in node.get_service_names_and_types_by_node("robot_arm", "/")}
        publishers = [i for i in node.get_publishers_info_by_topic("/arm/joint_state") if i.node_name == "robot_arm"]
        return "/robot_arm/save_state" in services, "/arm/move_to_pose" in services, bool(publishers)

    def move(node, transition):
        request = ChangeState.Request()
        request.transition.id = transition
        assert call(node, ChangeState, "/robot_arm/change_state", request).success
        return call(node, GetState, "/robot_arm/get_state", GetState.Request()).current_state.label

    rclpy.init()
    node = Node("lifecycle_look")
    got = []
    node.create_subscription(JointState, "/arm/joint_state", got.append,  # best_effort, as the file says
                             QoSProfile(depth=10, reliability=ReliabilityPolicy.BEST_EFFORT))
    print("state", call(node, GetState, "/robot_arm/get_state", GetState.Request()).current_state.label)
    spin(node, 20, lambda: members(node)[0])
    spin(node, 2)  # what the node made in its constructor is discovered with its protocol services
    print("unconfigured", *members(node))
    print("configure", move(node, Transition.TRANSITION_CONFIGURE))
    spin(node, 20, lambda: members(node) == (True, True, True))
    spin(node, 1.5)
    print("inactive", *members(node), len(got))
    print("activate", move(node, Transition.TRANSITION_ACTIVATE))
    print("active", spin(node, 10, lambda: len(got) > 0))
""")


def readme_blocks() -> list[list[str]]:
    """The shell lines of each ```sh block of the README's section, comments dropped."""
    text = TUTORIAL.read_text(encoding="utf-8")
    assert SECTION in text, f"{TUTORIAL.name} has no '{SECTION}'"
    section = text[text.index(SECTION):]
    section = section[:section.find("\n#", len(SECTION))]
    blocks = re.findall(r"```sh\n(.*?)```", section, re.DOTALL)
    return [[line.split("  #", 1)[0].strip() for line in block.splitlines() if line.strip()] for block in blocks]


def _run_lines(lines: list[str], clone: Path, env: dict[str, str]) -> str | None:
    """Run the shell ``lines`` in a new clone (the examples in it) at ``clone``: None, or what went wrong."""
    clone.mkdir(parents=True)
    shutil.copytree(ROOT / "examples", clone / "examples")
    script = "set -e\n" + "\n".join(lines) + "\n"
    done = subprocess.run(["bash", "-c", script], cwd=clone, env=env, capture_output=True, text=True, timeout=1200,
                          check=False)
    return None if done.returncode == 0 else f"{script}\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"


def readme_clone(venv: Path, setup: list[str], env: dict[str, str], scratch: Path) -> Path:
    """The clone where the README's setup lines ran, built with colcon as a user does: from the test cache when
    the same lines built the same sources with the same runtime before (what they build is what the lines
    before ``colcon`` write: they run first in ``scratch``)."""
    before = setup[:next(i for i, line in enumerate(setup) if line.startswith("colcon "))]
    why = _run_lines(before, scratch, env)
    assert why is None, why
    key = cache.key_of("README", *setup, cache.digest_tree(scratch / "src"), toolchain(venv, False))
    try:
        entry = cache.entry(key, "the README's commands (From the interface to a running node)",
                            lambda folder: _run_lines(setup, folder / "clone", env))
    except cache.BuildFailed as failed:
        raise AssertionError(str(failed)) from None
    return entry.path / "clone"


def test_the_readme_commands_start_a_node_the_ros2_command_shows(ros_venv: Path, tmp_path: Path) -> None:
    blocks = readme_blocks()
    assert len(blocks) == 2, blocks
    lines, looks = blocks
    assert lines[0].startswith("source "), lines
    if ros_venv != DEFAULT_VENV:
        lines = [line.replace(DEFAULT_ENV, str(ros_venv / "ros2-env.sh")) for line in lines]
    *setup, start = lines
    assert start == "ros2 run robot_arm robot_arm --activate", start
    assert [shlex.split(line)[:3] for line in looks] == [["ros2", "node", "info"], ["ros2", "lifecycle", "get"],
                                                         ["ros2", "param", "describe"]], looks
    env = environment(ros_venv, log_dir=tmp_path / "ros-log")
    # iface-lsp of this checkout, whatever is installed
    env["PATH"] = iface_lsp_on_path(tmp_path / "bin", ROOT, sys.executable) + os.pathsep + env["PATH"]
    work = readme_clone(ros_venv, setup, env, tmp_path / "scratch")
    assert (work / "src" / "robot_arm" / "robot_arm" / "node.py").is_file()
    sources = [line for line in setup if line.startswith("source ")]
    node = Launched(["bash", "-c", "\n".join([*sources, f"exec {start}"])], env, tmp_path / "node.log", cwd=work)
    try:
        shell = sourced(env, [work / "ws"])  # "in another shell, with the same two source lines"
        expected = {"info": ("/arm/joint_state: robot_arm_msgs/msg/JointState",
                             "/robot_arm/save_state: iface_msgs/srv/SaveState",
                             "/robot_arm/describe: iface_msgs/srv/Describe",
                             "/arm/follow_trajectory: robot_arm_msgs/action/FollowTrajectory"),
                    "get": ("active [3]",),
                    "describe": ("Parameter name: max_speed", "Type: double", "Min value: 0.1", "Max value: 3.0")}
        for line in looks:
            argv = shlex.split(line)
            wanted = expected[argv[2]]
            answer = ros2(shell, *argv[1:], until=wanted[0], within=60)
            assert answer.code == 0 and all(w in answer.out for w in wanted), f"{answer}\nnode:\n{node.log()[-2000:]}"
        node.watch()
        assert any("robot_arm" in " ".join(cmdline(pid)) for pid in node.seen), node.seen
        code = node.interrupt(timeout=30)  # Ctrl-C: ros2 run passes it on to the node
        left = node.left_running(within=10)
        assert code == 0 and not left, (code, left, node.log()[-2000:])
    finally:
        node.stop()


def test_user_code_the_regenerated_interface_no_longer_matches_refuses_to_start(ros_workspace: Workspace,
                                                                                 tmp_path: Path) -> None:
    """A handler renamed away from its member: the node says which, at start, and exits 2 without a traceback."""
    installed = next((ros_workspace.path / "install" / "robot_arm" / "lib").glob("python3*/site-packages/robot_arm"))
    shutil.copytree(installed, tmp_path / "robot_arm")
    node_py = tmp_path / "robot_arm" / "node.py"
    text = node_py.read_text()
    assert "def on_joint_command(self" in text
    node_py.write_text(text.replace("def on_joint_command(self", "def on_joint_cmd(self"))
    env = environment(ros_workspace.venv, ros_workspace.path, tmp_path / "ros-log")
    env["PYTHONPATH"] = f"{tmp_path}{os.pathsep}{env.get('PYTHONPATH', '')}"
    code = run_bounded([str(ros_workspace.venv / "bin" / "python"), "-m", "robot_arm", "--activate"], env, 60,
                       tmp_path / "start.log")
    said = (tmp_path / "start.log").read_text(errors="replace")
    assert code == 2, said
    assert "Traceback" not in said
    lines = said.strip().splitlines()
    assert re.match(r"robot_arm: the code does not match the interface \(robot_arm\.iface, sha256:[0-9a-f]{64}\):$",
                    lines[0]), said
    assert ("  RobotArm has no on_joint_command(self, msg), which handles 'subscribes JointCommand on "
            "/arm/joint_command' of robot_arm.iface") in lines
    assert any(line.startswith("  RobotArm.on_joint_cmd handles nothing in robot_arm.iface") for line in lines), said


def test_members_exist_from_configure_and_work_only_when_active(ros_workspace: Workspace, tmp_path: Path) -> None:
    """Started without --activate: only the protocol services; configure creates the members (a publisher that
    sends nothing while inactive); activate lets them work."""
    env = environment(ros_workspace.venv, ros_workspace.path, tmp_path / "ros-log")
    python = str(ros_workspace.venv / "bin" / "python")
    with open(tmp_path / "node.log", "w") as log:
        node = subprocess.Popen([python, "-m", "robot_arm"], env=env, stdout=log, stderr=subprocess.STDOUT,
                                start_new_session=True)
    try:
        look = tmp_path / "lifecycle.py"
        look.write_text(LIFECYCLE)
        code = run_bounded([python, str(look)], env, 120, tmp_path / "look.log")
        seen = (tmp_path / "look.log").read_text(errors="replace")
    finally:
        os.killpg(node.pid, signal.SIGINT)
        try:
            node.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(node.pid, signal.SIGKILL)
            node.wait(timeout=20)
    assert code == 0, seen[-3000:]
    lines = seen.strip().splitlines()
    for expected in ("state unconfigured", "unconfigured True False False", "configure inactive",
                     "inactive True True True 0", "activate active", "active True"):
        assert expected in lines, f"{expected!r} not in:\n{seen}"


#: An action client of the runtime, its lock there when the node first sees it (LockedActionClient).
LOCKED = textwrap.dedent("""\
    import sys
    import rclpy
    from every_member_msgs.action import Travel
    from iface_runtime_py.runtime import LockedActionClient
    sys.path.insert(0, sys.argv[1])
    from tests.ros_harness.probe import LockedActionClient as ProbeClient
    rclpy.init()
    node = rclpy.create_node("locked_probe")
    for cls, who in ((LockedActionClient, "the runtime's"), (ProbeClient, "the tests' probe's")):
        seen = []
        add = node.add_waitable
        node.add_waitable = lambda waitable: (seen.append(hasattr(waitable, "_lock")), add(waitable))
        client = cls(node, Travel, "/travel")
        client.get_num_entities()  # what an executor thread asks while it builds its wait set
        print(f"{who} lock when added:", seen)
        node.add_waitable = add
        client.destroy()
    node.destroy_node()
    rclpy.shutdown()
""")


def test_an_action_client_has_its_lock_when_the_node_first_sees_it(ros_workspace: Workspace, tmp_path: Path) -> None:
    """Kilted's rclpy adds an ActionClient to its node before it makes the lock ``get_num_entities`` takes; an
    executor thread that built its wait set then ended the component's process (AttributeError, seen in CI while a
    configure made the client). The runtime's client has its lock first, and so has the tests' probe's (its spin
    thread ended the same way in a CI run, and every later call of its driver timed out)."""
    env = environment(ros_workspace.venv, ros_workspace.path, tmp_path / "ros-log")
    script = tmp_path / "locked.py"
    script.write_text(LOCKED)
    code = run_bounded([str(ros_workspace.venv / "bin" / "python"), str(script), str(ROOT)], env, 60,
                       tmp_path / "locked.log")
    said = (tmp_path / "locked.log").read_text(errors="replace").splitlines()
    assert code == 0 and "the runtime's lock when added: [True]" in said, said[-30:]
    assert "the tests' probe's lock when added: [True]" in said, said[-30:]



def test_a_standby_makes_its_node_only_when_told_and_ends_with_its_parent(ros_workspace: Workspace,
                                                                          tmp_path: Path) -> None:
    """``--standby`` (the manager's spare for a fast restart): ROS up with a hidden node and no component node until
    SIGUSR1, then the component's node (``__node:=`` its own, not the hidden one's); a second SIGUSR1 ends
    nothing; a standby whose parent ends, ends."""
    env = environment(ros_workspace.venv, ros_workspace.path, tmp_path / "ros-log")
    exe = ros_workspace.path / "install" / "robot_arm" / "lib" / "robot_arm" / "robot_arm"
    findings(ros_workspace.venv, env, "arm_standby", [str(exe)], tmp_path / "standby.log")
