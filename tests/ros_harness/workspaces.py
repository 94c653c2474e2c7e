"""Building generated ROS 2 packages into the test cache (``cache.py``), one workspace per package, as underlays.

Every package is built alone, in a workspace of its own, on the workspaces of the generated packages it
depends on (colcon's underlays). Each such workspace is a cache entry under the key of what it is built from: the
packages' files, the keys of the workspaces it is built on, the ROS runtime (the venv's path, release
and installed distributions; rclcpp's build for C++), the compiler and cmake, and the build command. The
same package is so built once per content on this machine, whichever test, bench or worker asks first.

What ``build`` leaves in the caller's workspace folder is a view of those entries: ``install/setup.bash``
(and ``local_setup.bash``) sources each of them in order, ``install/PKG`` links to each package's
install folder (read-only: copy a package before changing it; ``own_copy`` makes such a view),
``iface-layers.json`` lists them (what a later ``build`` on this workspace as an underlay reads).
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import re
import shutil
import subprocess
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

from . import cache
from .ros import environment, shared_dir, sourced

LAYERS = "iface-layers.json"
_NAME = re.compile(r"<name>\s*([^<\s]+)\s*</name>")
_DEPEND = re.compile(r"<(?:depend|build_depend|exec_depend|build_export_depend)>\s*([^<\s]+)\s*</")
_BUILD_TYPE = re.compile(r"<build_type>\s*([^<\s]+)\s*</build_type>")


@dataclass(frozen=True)
class Package:
    """A generated package: its name, folder, the packages it depends on, whether rosidl builds it."""

    name: str
    folder: Path
    depends: frozenset[str]
    interfaces: bool
    build_type: str


@dataclass(frozen=True)
class Layer:
    """A built workspace in the cache: its key, its colcon workspace, its packages, the keys of those it is built on."""

    key: str
    path: Path
    packages: tuple[str, ...]
    on: tuple[str, ...]
    chain: tuple[str, ...] = ()  # installs outside the cache it was built on (rclcpp's), sourced before it

    def to_json(self) -> dict[str, object]:
        return {"key": self.key, "path": str(self.path), "packages": list(self.packages), "on": list(self.on),
                "chain": list(self.chain)}


@dataclass(frozen=True)
class _Planned:
    """A group of packages to build together: its key and the keys of the layers it is built on, in order."""

    group: tuple[Package, ...]
    key: str
    on: tuple[str, ...]
    cpp: bool


def packages(generated: Path) -> dict[str, Package]:
    """Each package directly under ``generated``."""
    found: dict[str, Package] = {}
    for xml in sorted(generated.glob("*/package.xml")):
        text = xml.read_text(encoding="utf-8")
        name = _NAME.search(text)
        if name is None:
            continue
        cmake = xml.parent / "CMakeLists.txt"
        interfaces = cmake.is_file() and "rosidl_generate_interfaces" in cmake.read_text("utf-8")
        kind = _BUILD_TYPE.search(text)
        found[name.group(1)] = Package(name.group(1), xml.parent, frozenset(_DEPEND.findall(text)), interfaces,
                                       kind.group(1) if kind else "ament_cmake")
    return found


def _version(tool: str, path: str) -> str:
    where = shutil.which(tool, path=path)
    if where is None:
        return f"{tool}: none"
    done = subprocess.run([where, "--version"], capture_output=True, text=True, timeout=60, check=False)
    said = (done.stdout or done.stderr).strip().splitlines()
    return f"{tool}: {where}: {said[0] if said else ''}"


def _file(path: Path) -> str:
    return cache.digest_file(path) if path.is_file() else f"no {path.name}"


@functools.cache
def toolchain(venv: Path, cpp: bool) -> str:
    """What a build with the runtime in ``venv`` (and rclcpp, with ``cpp``) depends on besides its sources."""
    venv = venv.resolve()
    installed = sorted(p.name for p in venv.glob("lib/python3*/site-packages/*.dist-info"))
    installed += sorted(p.name for p in venv.glob("colcon/lib/python3*/site-packages/*.dist-info"))
    path = environment(venv)["PATH"]
    parts = [f"venv {venv}", f"ros2-env.sh {_file(venv / 'ros2-env.sh')}", f"pyvenv.cfg {_file(venv / 'pyvenv.cfg')}",
             "installed " + hashlib.sha256("\n".join(installed).encode()).hexdigest(),
             *(_version(tool, path) for tool in ("cc", "c++", "cmake", "make"))]
    shared = shared_dir()
    if cpp:
        parts += [f"cpp {_file(venv / 'cpp' / 'stamp')} {_file(venv / 'cpp' / 'cpp-env.sh')}",
                  f"command {_CPP_COMMAND}"]
    elif shared is not None:
        runtime = shared / "ros2-runtime"
        parts += [f"build.sh {_file(runtime / 'build.sh')} check_types.py {_file(runtime / 'check_types.py')}"]
    else:
        parts += [f"command {_COLCON}"]
    return "\n".join(parts)


def cpp_environment(venv: Path) -> dict[str, str] | None:
    """The environment of ros2-env.sh and cpp-env.sh (rclcpp built by build-cpp.sh); None without rclcpp."""
    cpp_env = venv / "cpp" / "cpp-env.sh"
    if not cpp_env.is_file():
        return None
    script = f'set +u; . "{venv}/ros2-env.sh" >/dev/null && . "{cpp_env}" >/dev/null && env -0'
    base = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    dump = subprocess.run(["bash", "-c", script], capture_output=True, timeout=60, check=True, env=base).stdout
    return dict(item.split("=", 1) for item in dump.decode().split("\0") if "=" in item)


_COLCON = ["colcon", "--log-base", "log", "build", "--base-paths", "src", "--build-base", "build", "--install-base",
           "install", "--event-handlers", "console_direct-", "--cmake-args", "-DBUILD_TESTING=OFF"]
#: The C++ build, as docs/targets.md says (and the compile commands kept for the tests that compile one file).
_CPP_COMMAND = [*_COLCON, "-DCMAKE_EXPORT_COMPILE_COMMANDS=ON"]
#: Packages with unit tests of their own: built with BUILD_TESTING on, their build folder kept whole, so that
#: ctest runs them there (test_rclcpp_e2e.py) without a second build.
UNIT_TESTED = ("iface_runtime_cpp",)


def _order(found: dict[str, Package]) -> list[str]:
    """The packages of ``found`` in build order: each after the generated packages it depends on."""
    order: list[str] = []
    pending = sorted(found)
    while pending:
        name = next((n for n in pending if all(d not in found or d in order for d in found[n].depends)), pending[0])
        pending.remove(name)
        order.append(name)
    return order


def layers_of(workspace: Path) -> list[Layer]:
    """The layers of a workspace ``build`` made (none for another folder)."""
    listing = workspace / LAYERS
    if not listing.is_file():
        return []
    return [Layer(item["key"], Path(item["path"]), tuple(item["packages"]), tuple(item["on"]), tuple(item["chain"]))
            for item in json.loads(listing.read_text(encoding="utf-8"))]


def workspace_of(workspace: Path, package: str) -> Path:
    """The colcon workspace (in the cache) that built ``package`` of the workspace ``build`` made."""
    return next(layer.path for layer in reversed(layers_of(workspace)) if package in layer.packages)


def _make(venv: Path, group: tuple[Package, ...], cpp: bool, underlays: list[Layer]) -> Callable[[Path], str | None]:
    """The function that builds ``group`` into a cache entry's folder, on ``underlays``."""

    def make(folder: Path) -> str | None:
        gen, ws = folder / "gen", folder / "ws"
        for package in group:
            shutil.copytree(package.folder, gen / package.folder.name, symlinks=True)
        ws.mkdir()
        base = cpp_environment(venv) if cpp else environment(venv)
        assert base is not None, "no rclcpp in the runtime"
        env = sourced(base, [layer.path for layer in underlays], "local_setup.bash")
        shared = shared_dir()
        if cpp or shared is None:
            shutil.copytree(gen, ws / "src", symlinks=True)
            cmd = [*(_CPP_COMMAND if cpp else _COLCON), f"-DPython3_EXECUTABLE={venv}/bin/python"]
            if _unit_tested(group):
                cmd = [part.replace("-DBUILD_TESTING=OFF", "-DBUILD_TESTING=ON") for part in cmd]
            if cpp:
                cmd += [f"-DCMAKE_EXE_LINKER_FLAGS={env.get('ROS2_RUNTIME_CXX_LDFLAGS', '')}",
                        f"-DCMAKE_SHARED_LINKER_FLAGS={env.get('ROS2_RUNTIME_CXX_SHARED_LDFLAGS', '')}"]
        else:
            cmd = ["bash", str(shared / "ros2-runtime" / "build.sh"), str(gen), str(ws)]
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=1500, env=env, cwd=ws, check=False)
        if cpp or shared is None:
            (ws / "colcon.log").write_text(done.stdout + done.stderr)
        if done.returncode != 0:
            tail = "\n".join((done.stdout + done.stderr).strip().splitlines()[-30:])
            return f"{', '.join(p.name for p in group)} did not build (log: {ws}/colcon.log):\n{tail}"
        _prune(ws, keep={p.name for p in group if p.name in UNIT_TESTED})
        return None

    return make


def _unit_tested(group: tuple[Package, ...]) -> bool:
    return any(p.name in UNIT_TESTED and p.build_type != "ament_python" for p in group)


def _prune(ws: Path, keep: set[str]) -> None:
    """Leave what the tests use: install/, src/, the build's logs, each package's compile commands and the whole
    build folder of the packages ``keep`` names."""
    shutil.rmtree(ws / "log", ignore_errors=True)
    build = ws / "build"
    for package in build.iterdir() if build.is_dir() else ():
        if not package.is_dir() or package.name in keep:
            continue
        for child in package.iterdir():
            if child.is_dir() and not child.is_symlink():
                shutil.rmtree(child)
            elif child.name != "compile_commands.json":
                child.unlink()


def _plan(venv: Path, found: dict[str, Package], below: list[Layer], cpp: bool) -> list[_Planned]:
    """The groups of ``found`` to build, in order, each with its key and the layers it is built on."""
    provider = {name: layer.key for layer in below for name in layer.packages}
    on_of = {layer.key: layer.on for layer in below}
    plan: list[_Planned] = []
    for name in _order(found):
        names = [name]
        group = (found[name],)
        direct = sorted({provider[d] for p in group for d in p.depends if d not in names and d in provider})
        on: list[str] = []
        for key in direct:
            on += [k for k in (*on_of[key], key) if k not in on]
        with_cpp = cpp and any(not p.interfaces and p.build_type != "ament_python" for p in group)
        key = cache.key_of(toolchain(venv, with_cpp), *(f"{p.name} {cache.digest_tree(p.folder)}" for p in group),
                           *(f"on {k}" for k in direct),
                           *(["BUILD_TESTING=ON"] if with_cpp and _unit_tested(group) else []))
        on_of[key] = tuple(on)
        provider.update(dict.fromkeys(names, key))
        plan.append(_Planned(group, key, tuple(on), with_cpp))
    return plan


def build_layers(venv: Path, generated: Path, *, underlays: Sequence[Path] = (),
                 cpp: bool = False) -> tuple[list[Layer], str, bool]:
    """The cache entries that hold every package under ``generated``, built now when missing: (the layers in
    order, those of ``underlays`` first; why not, on failure; whether any was built now).

    ``underlays`` are workspaces ``build`` made, whose packages the generated ones may depend on. With
    ``cpp``, the packages that are not interface packages are built against rclcpp (build-cpp.sh).
    While another process builds an entry this one needs, this one builds another it needs, if any.
    """
    below: list[Layer] = []
    for workspace in underlays:
        below += [layer for layer in layers_of(workspace) if layer not in below]
    plan = _plan(venv, packages(generated), below, cpp)
    done = {layer.key: layer for layer in below}
    built = False
    pending = list(plan)
    while pending:
        ready = [item for item in pending if all(k in done for k in item.on)]
        assert ready, "a package depends on one built after it"
        for position, item in enumerate(ready):
            names = tuple(p.name for p in item.group)
            what = f"{' '.join(names)} ({'rclcpp' if item.cpp else 'runtime'} of {venv})"
            try:
                entry = cache.entry(item.key, what, _make(venv, item.group, item.cpp, [done[k] for k in item.on]),
                                    wait=position == len(ready) - 1)
            except cache.Busy:
                continue
            except cache.BuildFailed as failed:
                return [], str(failed), True
            built |= entry.built
            chain = (str(venv / "cpp" / "install"),) if item.cpp else ()
            done[item.key] = Layer(item.key, entry.path / "ws", names, item.on, chain)
            pending.remove(item)
            break
    layers = list(below)
    layers += [done[item.key] for item in plan if done[item.key] not in layers]
    return layers, "", built


def write_view(workspace: Path, layers: list[Layer]) -> None:
    """Make ``workspace`` the view of ``layers``: its install/setup.bash sources each, install/PKG links to each
    package."""
    install = workspace / "install"
    if install.is_dir():
        shutil.rmtree(install)
    install.mkdir(parents=True)
    lines = ["# The layers of this workspace: each a workspace of the iface test cache",
             "# (tests/ros_harness/workspaces.py),",
             "# sourced in order (each one's own packages: its underlays are the layers before it)."]
    sh = list(lines)
    for prefix in dict.fromkeys(p for layer in layers for p in layer.chain):
        lines.append(f'. "{prefix}/local_setup.bash"')
        sh.append(f'COLCON_CURRENT_PREFIX="{prefix}" . "{prefix}/local_setup.sh"')
    for layer in layers:
        lines.append(f'. "{layer.path}/install/local_setup.bash"')
        sh.append(f'COLCON_CURRENT_PREFIX="{layer.path}/install" . "{layer.path}/install/local_setup.sh"')
        for name in layer.packages:
            link = install / name
            if link.is_symlink():
                link.unlink()
            link.symlink_to(layer.path / "install" / name)
    for name in ("setup.bash", "local_setup.bash"):
        (install / name).write_text("\n".join(lines) + "\n")
    for name in ("setup.sh", "local_setup.sh"):
        (install / name).write_text("\n".join(sh) + "\nunset COLCON_CURRENT_PREFIX\n")
    (workspace / LAYERS).write_text(json.dumps([layer.to_json() for layer in layers], indent=1) + "\n")


def join(workspace: Path, workspaces: Sequence[Path]) -> None:
    """Make ``workspace`` the view of the layers of ``workspaces`` (made by ``build``), in order."""
    layers: list[Layer] = []
    for each in workspaces:
        layers += [layer for layer in layers_of(each) if layer not in layers]
    write_view(workspace, layers)


def build(venv: Path, generated: Path, workspace: Path, *, underlays: Sequence[Path] = (),
          cpp: bool = False) -> tuple[bool, str, float]:
    """Every package under ``generated``, built (or taken from the cache) and viewed in ``workspace``:
    (ok, why not, seconds)."""
    start = time.monotonic()
    layers, why, _ = build_layers(venv, generated, underlays=underlays, cpp=cpp)
    if why:
        return False, why, time.monotonic() - start
    write_view(workspace, layers)
    return True, "", time.monotonic() - start


def own_copy(workspace: Path, names: Sequence[str], dest: Path) -> Path:
    """``dest`` made the view of ``workspace`` (made by ``build``) in which the packages ``names`` are copies of
    their own (``dest/own/<package>``, the layer that ``workspace`` links for each): a user's install folders,
    which a test may change (sign, tamper with) where the test cache's entries are read-only. Build on
    ``workspace``, not on ``dest``: a cache entry must never be built on a test's copy."""
    layers = layers_of(workspace)
    for name in names:
        at = max(i for i, layer in enumerate(layers) if name in layer.packages)
        copy = dest / "own" / name
        if copy.exists():
            shutil.rmtree(copy)
        shutil.copytree(layers[at].path / "install", copy / "install", symlinks=True)
        layers[at] = replace(layers[at], path=copy)
    write_view(dest, layers)
    return dest


def debian_build(generated: Path) -> subprocess.CompletedProcess[str]:
    """``../shared/ros2-build/build.sh GENERATED WORKDIR`` (Debian's rosidl, C and C++ programs per type), its
    outcome taken from the cache when the same packages were built by the same script and Debian packages.

    A failed build is not kept: it runs again next time. Without ../shared: exit status 2 and why.
    """
    shared = shared_dir()
    script = shared / "ros2-build" / "build.sh" if shared is not None else None
    if script is None or not script.is_file():
        return subprocess.CompletedProcess([], 2, "", "no ../shared/ros2-build (set IFACE_ROS2_SHARED)")
    here = script.parent
    names = [line.strip() for line in (here / "apt-packages.txt").read_text().splitlines() if line.strip()]
    versions = subprocess.run(["dpkg-query", "-W", "-f", "${Package} ${Version}\\n", *names], capture_output=True,
                              text=True, timeout=60, check=False).stdout if shutil.which("dpkg-query") else ""
    path = "/usr/bin:" + os.environ.get("PATH", "")
    key = cache.key_of("ros2-build", cache.digest_tree(here), versions,
                       *(_version(tool, path) for tool in ("cc", "c++", "cmake", "make")),
                       f"generated {cache.digest_tree(generated)}")
    outcome: list[subprocess.CompletedProcess[str]] = []

    def make(folder: Path) -> str | None:
        gen, ws = folder / "gen", folder / "ws"
        shutil.copytree(generated, gen, symlinks=True)
        done = subprocess.run(["bash", str(script), str(gen), str(ws)], capture_output=True, text=True, timeout=1500,
                              check=False)
        outcome.append(done)
        if done.returncode != 0:
            return f"ros2-build exited {done.returncode}"
        (folder / "outcome.json").write_text(json.dumps({"stdout": done.stdout, "stderr": done.stderr}))
        shutil.rmtree(ws / "build", ignore_errors=True)
        shutil.rmtree(ws / "smoke", ignore_errors=True)
        return None

    try:
        entry = cache.entry(key, f"ros2-build of {' '.join(sorted(packages(generated)))}", make)
    except cache.BuildFailed:
        return outcome[-1]
    recorded = json.loads((entry.path / "outcome.json").read_text())
    return subprocess.CompletedProcess(["bash", str(script)], 0, recorded["stdout"], recorded["stderr"])
