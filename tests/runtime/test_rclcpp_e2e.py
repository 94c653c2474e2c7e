"""End to end: the generated C++ (rclcpp) component built with colcon against rclcpp and run on loopback.

rclcpp has no wheel: ../shared/ros2-runtime/build-cpp.sh builds it from its sources into
VENV/cpp (scripts/install-ros.sh does, in CI). Without it these tests skip, saying so.

The packages come from the test cache (tests/ros_harness/workspaces.py: each built once per content,
in a workspace of its own): ws_cpp, the C++ counter 2.0 (examples/counter_v2.iface with
tests/runtime/data/counter_v2_node.cpp) on iface_runtime_cpp, counter_msgs and iface_msgs; the Python
counter 1.0 for the hand-overs across languages (test_handover.py's); every_member's C++ package with
the user file iface writes (every kind of member: its templates compile), beside its Python package
(the session's), both on the one every_member_msgs; the C++ counter 1.0 on ws_cpp. drive_rclcpp.py runs
the scenario of one C++ node, drive_container.py that of a component container; each test below is one of their steps. Every
wait is bounded, every process is stopped by its own handle, traffic stays on loopback in a random
ROS_DOMAIN_ID.
"""

from __future__ import annotations

import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest

from ..ros_harness.ros import DATA, HARNESS, ROOT, build, environment, generate, run_bounded
from ..ros_harness.standby_probe import findings
from ..ros_harness.workspaces import cpp_environment, workspace_of

DRIVER = HARNESS / "drive_rclcpp.py"
COUNTER_V2 = ROOT / "examples" / "counter_v2.iface"
STEPS = [
    "start: the executable with the installed parameter file",
    "lifecycle: configure and activate through the standard services",
    "parameters: descriptors with description, unit and range",
    "parameters: out-of-range values refused with a reason",
    "parameters: in-range values applied",
    "qos: /count carries the declared QoS, counts published while active",
    "diagnostics: published and control answered while a long callback runs",
    "control: pause after the current transaction, resume",
    "state: saved from one instance, restored into a second, the counter continues",
    "state: a restore from an incompatible interface is refused with a reason",
    "lifecycle: inactive does no work, cleanup withdraws the members",
    "lifecycle: shutdown ends the process",
    "state: the C++ node reads and writes the Python node's state document",
    "handover: iface-lsp handover from the Python counter 1.0 to the C++ counter 2.0",
    "handover: the count continues in C++, none lost, the Python node deactivated",
    "state: saved from the C++ node, restored into the Python node",
]


def overlay(env: dict[str, str], ws: Path, script: str = "local_setup.bash") -> dict[str, str]:
    """``env`` with the workspace ``ws`` sourced on top (its install/local_setup.bash; setup.bash: with its underlays)."""
    script = f'set +u; . "{ws}/install/{script}" >/dev/null && env -0'
    dump = subprocess.run(["bash", "-c", script], capture_output=True, timeout=60, check=True, env=env).stdout
    return dict(item.split("=", 1) for item in dump.decode().split("\0") if "=" in item)


def generated(root: Path, name: str, iface: Path, target: str, user: Path | None = None) -> Path:
    """``generate IFACE --target TARGET`` into root/NAME, with the tests' user file in place when given."""
    gen = root / name
    done = generate(iface, gen, "--target", target)
    assert done.returncode == 0, done.stderr
    if user is not None:
        package = iface.stem.removesuffix("_v2")
        mine = gen / package / ("src/node.cpp" if target == "rclcpp" else f"{package}/node.py")
        shutil.copyfile(user, mine)
        again = generate(iface, gen, "--target", target)
        assert again.returncode == 0, again.stderr
        assert mine.read_text() == user.read_text(), f"{mine.name} was overwritten"
    return gen


def built(venv: Path, gen: Path, ws: Path, what: str, **how: Any) -> Path:
    """``gen`` built (from the test cache) into the workspace ``ws``, which is returned."""
    ws.mkdir()
    ok, tail, seconds = build(venv, gen, ws, **how)
    assert ok, f"{what} did not build:\n{tail}"
    print(f"\nbuild (or cache) of {what}: {seconds:.0f} s")
    return ws


@pytest.fixture(scope="module")
def workspaces(ros_venv: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    env = cpp_environment(ros_venv)
    if env is None:
        pytest.skip(f"rclcpp is not built in {ros_venv}/cpp: run `bash ../shared/ros2-runtime/build-cpp.sh "
                    f"{ros_venv}` (scripts/install-ros.sh does)")
    missing = [tool for tool in ("cmake", "c++", "make") if shutil.which(tool, path=env.get("PATH")) is None]
    if missing:
        pytest.skip(f"no {', '.join(missing)} on PATH to build C++")
    root = tmp_path_factory.mktemp("rclcpp")
    gen = generated(root, "gen_cpp", COUNTER_V2, "rclcpp", DATA / "counter_v2_node.cpp")
    ws_cpp = built(ros_venv, gen, root / "ws_cpp", "counter_msgs, iface_runtime_cpp and counter 2.0 (C++)", cpp=True)
    gen_py = generated(root, "gen_py", ROOT / "examples" / "counter.iface", "rclpy", DATA / "counter_node.py")
    ws_py = built(ros_venv, gen_py, root / "ws_py", "the Python counter 1.0")
    return {"venv": ros_venv, "root": root, "ws_cpp": ws_cpp, "ws_py": ws_py, "env": env}


def signed_package(installed: Path, root: Path) -> dict[str, str]:
    """Sign (a copy of: the cached one is read-only) the installed C++ package as README says (its executable and
    libraries included); a tampered copy."""
    key, store = root / "keys" / "me.key", root / "trusted"
    key.parent.mkdir()
    store.mkdir()
    package = root / "signed" / "counter"
    shutil.copytree(installed, package, symlinks=True)
    for argv in (["--keygen", str(key)], [str(package), "--key", str(key)]):
        done = subprocess.run([sys.executable, "-m", "iface", "sign", *argv], capture_output=True, text=True,
                              timeout=60, check=False)
        assert done.returncode == 0, done.stderr
    shutil.copy(f"{key}.pub", store)
    signed = json.loads((package / "iface-signature.json").read_text())["files"]
    binaries = sorted(p.relative_to(package).as_posix() for p in (package / "lib").rglob("*")
                      if p.is_file() and (os.access(p, os.X_OK) or ".so" in p.name))
    assert "lib/counter/counter" in binaries and set(binaries) <= set(signed), (binaries, sorted(signed))
    tampered = root / "tampered" / "counter"
    shutil.copytree(package, tampered, symlinks=True)
    with open(tampered / "lib" / "counter" / "counter", "ab") as f:
        f.write(b"\0")
    return {"trust_store": str(store), "new_package": str(package), "tampered_package": str(tampered),
            "tampered_file": str(tampered / "lib" / "counter" / "counter")}


@pytest.fixture(scope="module")
def run(workspaces: dict[str, Any]) -> dict[str, Any]:
    venv, root = workspaces["venv"], workspaces["root"]
    env_cpp = environment(venv, workspaces["ws_cpp"], root / "ros-log")
    env_py = environment(venv, workspaces["ws_py"], root / "ros-log")
    env_py["ROS_DOMAIN_ID"] = env_cpp["ROS_DOMAIN_ID"]
    config = {"python": sys.executable, "ros_python": str(venv / "bin" / "python"),
              "cpp_executable": str(workspaces["ws_cpp"] / "install" / "counter" / "lib" / "counter" / "counter"),
              "old_iface": str(ROOT / "examples" / "counter.iface"), "new_iface": str(COUNTER_V2),
              "env_cpp": env_cpp, "env_py": env_py,
              **signed_package(workspaces["ws_cpp"] / "install" / "counter", root)}
    (root / "config.json").write_text(json.dumps(config))
    out, log = root / "result.json", root / "driver.log"
    code = run_bounded([str(venv / "bin" / "python"), str(DRIVER), str(root / "config.json"), "--out", str(out),
                        "--logs", str(root / "logs")], env_cpp, 400, log)
    steps = json.loads(out.read_text()) if out.is_file() else {}
    steps["_run"] = {"code": code, "log": str(log), "logs": str(root / "logs")}
    return steps


@pytest.mark.parametrize("step", STEPS)
def test_cpp_counter(run: dict[str, Any], step: str) -> None:
    passed(run, step)


def passed(run: dict[str, Any], step: str) -> None:
    """The driver's step ``step`` ran and passed."""
    info = run["_run"]
    if step not in run:
        tail = Path(info["log"]).read_text(errors="replace")[-3000:] if Path(info["log"]).is_file() else ""
        pytest.fail(f"step not reached (driver exit {info['code']}; logs in {info['logs']}):\n{tail}")
    assert run[step]["ok"], f"{step}: {run[step]['detail']} (logs in {info['logs']})"


def test_the_cpp_runtimes_own_unit_tests_pass(workspaces: dict[str, Any]) -> None:
    """iface_runtime_cpp's unit tests (its test/: the JSON, the state document and the widening table the
    Python tests hold compat and iface_runtime_py to, the parameter checks, the work gate), built with the
    library in ws_cpp (BUILD_TESTING on for it: workspaces.UNIT_TESTED) and run by ctest, every time."""
    build = workspace_of(workspaces["ws_cpp"], "iface_runtime_cpp") / "build" / "iface_runtime_cpp"
    env = overlay(workspaces["env"], workspaces["ws_cpp"], "setup.bash")
    log = workspaces["root"] / "runtime-tests.log"
    argv = ["ctest", "--output-on-failure", "--timeout", "120"]  # its records (Testing/) are no part of the entry
    done = subprocess.run(argv, cwd=build, env=env, capture_output=True, text=True, timeout=1200, check=False)
    output = f"$ {' '.join(argv)}\n{done.stdout}{done.stderr}"
    log.write_text(output)
    assert done.returncode == 0, f"ctest failed (log: {log}):\n{output[-3000:]}"
    assert "100% tests passed, 0 tests failed out of 4" in output, output[-2000:]


def component_only(gen: Path, keep: str) -> None:
    """Leave only the package ``keep`` in ``gen``: the rest comes from a workspace built before."""
    for package in gen.iterdir():
        if package.is_dir() and package.name != keep:
            shutil.rmtree(package)


@pytest.fixture(scope="module")
def every_member_cpp(workspaces: dict[str, Any]) -> tuple[Path, dict[str, str]]:
    """every_member's C++ package with the user file iface writes, beside its Python package (the session's:
    the same cache entries), which shares every_member_msgs with it: the interface package both targets write."""
    venv, root = workspaces["venv"], workspaces["root"]
    iface = DATA / "every_member.iface"
    ws_py = built(venv, generated(root, "gen_every_member_py", iface, "rclpy", DATA / "every_member_node.py"),
                  root / "ws_every_member_py", "every_member (Python)")
    ws = built(venv, generated(root, "gen_every_member", iface, "rclcpp"), root / "ws_every_member",
               "every_member (C++)", cpp=True, underlays=[ws_py])
    return ws, environment(venv, ws, root / "ros-log")


@pytest.fixture(scope="module")
def counter_v1_cpp(workspaces: dict[str, Any]) -> tuple[Path, dict[str, str]]:
    """The C++ counter 1.0 (examples/counter.iface, tests/runtime/data/counter_node.cpp) on top of ws_cpp:
    its counter_msgs is 2.0's, which holds 1.0's (one interface package per process, as in a container)."""
    venv, root = workspaces["venv"], workspaces["root"]
    gen = generated(root, "gen_counter_v1", ROOT / "examples" / "counter.iface", "rclcpp", DATA / "counter_node.cpp")
    component_only(gen, "counter")
    ws = built(venv, gen, root / "ws_counter_v1", "counter 1.0 (C++, the component alone)", cpp=True,
               underlays=[workspaces["ws_cpp"]])
    return ws, environment(venv, ws, root / "ros-log")


CONTAINER_DRIVER = HARNESS / "drive_container.py"
CONTAINER_STEPS = [
    "container: component_container_mt starts",
    "container: counter 1.0 and 2.0 and every_member load side by side",
    "container: handover from counter 1.0 to 2.0 inside the container",
    "container: the components unload, the container keeps running",
    "handover: the C++ counter 1.0 to the Python counter 1.0",
]


@pytest.fixture(scope="module")
def container_run(workspaces: dict[str, Any], every_member_cpp: tuple[Path, dict[str, str]],
                  counter_v1_cpp: tuple[Path, dict[str, str]]) -> dict[str, Any]:
    venv, root = workspaces["venv"], workspaces["root"]
    env = overlay(every_member_cpp[1], counter_v1_cpp[0])
    env_py = environment(venv, workspaces["ws_py"], root / "ros-log")
    env_v1 = dict(counter_v1_cpp[1])
    env_py["ROS_DOMAIN_ID"] = env_v1["ROS_DOMAIN_ID"] = env["ROS_DOMAIN_ID"]
    config = {"python": sys.executable, "ros_python": str(venv / "bin" / "python"), "env": env, "env_py": env_py,
              "env_v1": env_v1, "cpp_v1": str(counter_v1_cpp[0] / "install" / "counter" / "lib" / "counter" / "counter"),
              "old_iface": str(ROOT / "examples" / "counter.iface"), "new_iface": str(COUNTER_V2)}
    (root / "container.json").write_text(json.dumps(config))
    out, log = root / "container.result.json", root / "container.log"
    code = run_bounded([str(venv / "bin" / "python"), str(CONTAINER_DRIVER), str(root / "container.json"), "--out",
                        str(out), "--logs", str(root / "container-logs")], env, 400, log)
    steps = json.loads(out.read_text()) if out.is_file() else {}
    steps["_run"] = {"code": code, "log": str(log), "logs": str(root / "container-logs")}
    return steps


@pytest.mark.parametrize("step", CONTAINER_STEPS)
def test_components_in_one_container(container_run: dict[str, Any], step: str) -> None:
    """Two generated C++ components, and two versions of one, in one component container; a hand-over between
    two of them there; and one from C++ to Python."""
    passed(container_run, step)


def test_every_member_builds_and_checks_its_parameters(workspaces: dict[str, Any],
                                                       every_member_cpp: tuple[Path, dict[str, str]]) -> None:
    """Every kind of member compiles; /diagnostics comes at the file's rate and the Δ service answers; the C++ node
    refuses parameters with the Python node's reasons, and writes the Python node's state document byte for byte
    (floats, strings, a message, arrays, extreme integers)."""
    venv = workspaces["venv"]
    ws, env = every_member_cpp
    exe = ws / "install" / "every_member" / "lib" / "every_member" / "every_member"
    assert exe.is_file()
    script = r"""
import json, subprocess, sys, time
sys.path.insert(0, sys.argv[2])
from tests.ros_harness.probe import Probe, Protocol
procs = [subprocess.Popen(argv + ["--ros-args", "-r", f"__node:={name}"], stdout=subprocess.DEVNULL,
                          stderr=subprocess.STDOUT)
         for argv, name in (([sys.argv[1]], "em_cpp"), ([sys.executable, "-m", "every_member"], "em_py"))]
probe = Probe()
proto = Protocol(probe, "every_member_msgs")
out = {}
try:
    for name in ("em_cpp", "em_py"):
        probe.wait_ready(name, 30)
    for name, value in (("start_mode", 7), ("label", "much too long"), ("offsets", [1.0]), ("ids", [1, 2, 3, 4, 5]),
                        ("gain", 11.0), ("retries", 4), ("serial", "SN-2")):
        out[name] = [probe.set_param(node, name, value) for node in ("em_cpp", "em_py")]
    import importlib
    Diagnostics = importlib.import_module("every_member_msgs.srv").Diagnostics
    seen = probe.diagnostics_of("/em_cpp")
    time.sleep(2.5)
    out["diagnostics_per_s"] = len(seen) / 2.5
    answer = probe.call(Diagnostics, "/em_cpp/diagnostics", Diagnostics.Request(level=1))
    out["delta"] = type(answer).__name__
    doc = proto.save("em_py")
    doc["values"] = {"counter": 2 ** 64 - 1, "last_label": "\u00fc\"\\x\u2603", "position": [0.1, 1e-07, 1e16],
                     "target": {"x": 1.5, "y": -0.0, "name": "w\u00e9"}, "mode": -2147483648, "busy": True,
                     "history": [-32768, 0, 32767], "flags": 255}
    texts = []
    for node in ("em_py", "em_cpp"):
        answer = proto.restore(node, json.dumps(doc) if not texts else texts[-1])
        assert answer.success, answer.message
        texts.append(proto.save_raw(node).state)
    out["documents"] = texts
finally:
    for proc in procs:
        proc.terminate()
        proc.wait(timeout=15)
    probe.close()
print(json.dumps(out))
"""
    done = subprocess.run([str(venv / "bin" / "python"), "-c", script, str(exe), str(ROOT)],
                          env=env, capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    got = json.loads(done.stdout.strip().splitlines()[-1])
    python, cpp = got.pop("documents")
    assert 3.0 <= got.pop("diagnostics_per_s") <= 5.0  # the file's rate = 4 (Hz), while unconfigured
    assert got.pop("delta") == "Diagnostics_Response"  # ~/diagnostics answered from the diagnostics group
    assert cpp == python, f"C++ {cpp}\nPython {python}"
    assert '"position":[0.1,1e-07,1e+16]' in cpp and '"last_label":"ü\\"\\\\x☃"' in cpp, cpp
    for name, (mine, theirs) in got.items():
        if name == "gain":
            assert mine[0] is False and theirs[0] is False and mine[1], got[name]
        elif name == "serial":
            assert mine[0] is False and theirs[0] is False and "read-only" in mine[1], got[name]
        else:
            assert mine == theirs, f"{name}: C++ {mine}, Python {theirs}"
    assert got["start_mode"][0] == [False, "start_mode=7 is not one of IDLE (0), RUNNING (1), FAULT (2)"]
    assert got["label"][0] == [False, "label is 13 characters long; at most 8 are allowed"]
    assert got["offsets"][0] == [False, "offsets must have exactly 3 elements, not 1"]
    assert got["ids"][0] == [False, "ids may have at most 4 elements, not 5"]
    assert got["retries"][0] == [True, ""]


def test_a_user_file_that_no_longer_matches_stops_the_build_with_the_reason(workspaces: dict[str, Any],
                                                                           tmp_path: Path) -> None:
    """The interface lost a member and gained one: the compiler names both, and the interface file."""
    ws = workspace_of(workspaces["ws_cpp"], "counter")  # the colcon workspace in the cache that built it
    commands = json.loads((ws / "build" / "counter" / "compile_commands.json").read_text())
    entry = next(c for c in commands if c["file"].endswith("/src/node.cpp"))
    text = (DATA / "counter_v2_node.cpp").read_text()
    start = text.index("  void handle_reset(")
    end = text.index("\n  }\n", start) + len("\n  }\n")
    broken = tmp_path / "node.cpp"
    broken.write_text(text[:start] + "  void on_nudge(const Count & msg) override {(void)msg;}\n" + text[end:])
    argv = shlex.split(entry["command"])
    out = argv.index("-o")
    del argv[out:out + 2]
    argv[argv.index("-c"):argv.index("-c") + 2] = ["-fsyntax-only", str(broken)]
    done = subprocess.run(argv, cwd=entry["directory"], env=workspaces["env"], capture_output=True, text=True,
                          timeout=300, check=False)
    assert done.returncode != 0
    assert "does not implement every handler of counter_v2.iface" in done.stderr, done.stderr[-3000:]
    assert "handle_reset" in done.stderr
    assert re.search(r"node\.cpp:\d+:\d+: error: .void counter::Counter::on_nudge\([^\n]*marked .override., but does "
                     "not override", done.stderr), done.stderr[-3000:]


def test_a_standby_makes_its_node_only_when_told_and_ends_with_its_parent(workspaces: dict[str, Any]) -> None:
    """``--standby``, as the Python runtime's (test_rclpy_start.py): no component node until SIGUSR1, then the
    node; a second SIGUSR1 ends nothing; a standby whose parent ends, ends."""
    venv, ws = workspaces["venv"], workspaces["ws_cpp"]
    env = environment(venv, ws, workspaces["root"] / "ros-log")
    exe = str(ws / "install" / "counter" / "lib" / "counter" / "counter")
    findings(venv, env, "counter_standby", [exe], workspaces["root"] / "standby.log")


def test_the_command_line_is_the_python_nodes(workspaces: dict[str, Any]) -> None:
    """--help, an unknown option refused with exit 2 as argparse does, and SIGTERM ends the node cleanly."""
    venv, ws = workspaces["venv"], workspaces["ws_cpp"]
    env = environment(venv, ws, workspaces["root"] / "ros-log")
    exe = str(ws / "install" / "counter" / "lib" / "counter" / "counter")
    shown = subprocess.run([exe, "--help"], env=env, capture_output=True, text=True, timeout=30, check=False)
    assert shown.returncode == 0 and all(o in shown.stdout for o in ("--activate", "--no-default-params", "--standby"))
    bad = subprocess.run([exe, "--bogus"], env=env, capture_output=True, text=True, timeout=30, check=False)
    assert bad.returncode == 2 and "counter: error: unrecognized arguments: --bogus" in bad.stderr, bad.stderr
    log = workspaces["root"] / "sigterm.log"
    with open(log, "w") as out:
        proc = subprocess.Popen([exe, "--activate"], env=env, stdout=out, stderr=subprocess.STDOUT)
        try:
            end = time.monotonic() + 30
            while "parameter file:" not in log.read_text() and time.monotonic() < end:
                time.sleep(0.1)
            proc.terminate()
            code = proc.wait(timeout=15)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait(timeout=10)
    text = log.read_text()
    assert code == 0, text
    assert "ERROR" not in text and "not shut down" not in text, text
