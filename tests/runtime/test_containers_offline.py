"""What the manager decides before it asks a container to load a component, without ROS: where a package's component
library is, whether the trust store trusts it, and whether NEW's libraries are those a running process has loaded
(checked against real libraries and this test's own process)."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from iface.operate.containers import (
    INDEX,
    ContainerError,
    component_in,
    find_component,
    installed_parameters,
    mapped_files,
    needed,
    sharing_problem,
    why_not,
)
from iface.operate.in_container import ContainerCalls
from iface.operate.trust import keygen, sign
from tests.conftest import run_cli

PNG = Path("/usr/lib/x86_64-linux-gnu/libpng16.so.16")


def _package(prefix: Path, package: str = "ticker", line: str = "ticker::Ticker;lib/libticker_component.so") -> Path:
    (prefix / INDEX).mkdir(parents=True)
    (prefix / INDEX / package).write_text(line + "\n", encoding="utf-8")
    (prefix / "lib").mkdir()
    (prefix / "lib" / f"lib{package}_component.so").write_bytes(b"\x7fELF not really")
    config = prefix / "share" / package / "config"
    config.mkdir(parents=True)
    (config / f"{package}.params.yaml").write_text("/**:\n  ros__parameters: {}\n", encoding="utf-8")
    return prefix


def test_a_component_is_found_by_package_and_class_in_the_first_prefix_that_has_it(tmp_path: Path) -> None:
    first, second = _package(tmp_path / "one"), _package(tmp_path / "two")
    env = {"AMENT_PREFIX_PATH": os.pathsep.join([str(tmp_path / "empty"), str(first), str(second)])}
    found = find_component("ticker", "ticker::Ticker", env)
    assert (found.prefix, found.library) == (first, first / "lib" / "libticker_component.so")
    assert found.resource == first / "share/ament_index/resource_index/rclcpp_components/ticker"
    assert installed_parameters(found) == first / "share/ticker/config/ticker.params.yaml"
    with pytest.raises(ContainerError, match=r"registers no component ticker::Other \(it registers: ticker::Ticker\)"):
        find_component("ticker", "ticker::Other", env)
    with pytest.raises(ContainerError, match="no rclcpp component of package counter in the sourced workspace"):
        find_component("counter", "counter::Counter", env)
    with pytest.raises(ContainerError, match="--target rclcpp"):
        component_in(tmp_path / "empty", "ticker", "ticker::Ticker")


def test_only_a_signed_package_whose_signature_covers_the_library_is_trusted(tmp_path: Path) -> None:
    store = tmp_path / "store"
    store.mkdir()
    pub, _ = keygen(tmp_path / "key")
    shutil.copy(pub, store)
    prefix = _package(tmp_path / "pkg")
    component = component_in(prefix, "ticker", "ticker::Ticker")
    assert "is not signed" in " ".join(component.untrusted(store))
    sign(prefix, tmp_path / "key")
    assert component.untrusted(store) == []
    component.library.write_bytes(b"\x7fELF changed")
    assert any("libticker_component.so: changed since it was signed" in p for p in component.untrusted(store))
    outside = _package(tmp_path / "outside", line=f"ticker::Ticker;{tmp_path / 'elsewhere.so'}")
    (tmp_path / "elsewhere.so").write_bytes(b"x")
    sign(outside, tmp_path / "key")
    away = component_in(outside, "ticker", "ticker::Ticker")
    assert away.untrusted(store) == [f"{tmp_path / 'elsewhere.so'} is outside the signed package folder {outside}"]


@pytest.mark.skipif(not PNG.is_file() or shutil.which("ldd") is None, reason="needs libpng16 and ldd")
def test_new_shares_a_process_only_with_the_very_libraries_it_has_loaded(tmp_path: Path) -> None:
    """libpng needs libz: in this process's environment it resolves to the libz this process has mapped (shared);
    a NEW whose environment finds another libz first cannot share it; one that finds none is told so."""
    env = dict(os.environ)
    deps = needed(PNG, env)
    assert "libz.so.1" in deps and deps["libz.so.1"] is not None and "libc.so.6" in deps
    assert os.path.realpath("/lib/x86_64-linux-gnu/libc.so.6") in mapped_files(os.getpid())
    assert sharing_problem(PNG, os.getpid(), env, env) is None
    other = tmp_path / "other"
    other.mkdir()
    with open(deps["libz.so.1"], "rb") as f:
        (other / "libz.so.1").write_bytes(f.read() + b"\0")
    theirs = dict(env, LD_LIBRARY_PATH=str(other))
    problem = sharing_problem(PNG, os.getpid(), env, theirs)
    assert problem == why_not("libz.so.1", str(other / "libz.so.1"), deps["libz.so.1"])
    assert problem.startswith(f"NEW needs libz.so.1 as {other / 'libz.so.1'}, the container has")
    copy = tmp_path / "copy"
    copy.mkdir()
    shutil.copy(deps["libz.so.1"], copy / "libz.so.1")  # the same bytes: as good as the file itself
    assert sharing_problem(PNG, os.getpid(), env, dict(env, LD_LIBRARY_PATH=str(copy))) is None


def test_the_reason_names_the_runtime_or_the_interface_package(tmp_path: Path) -> None:
    for prefix, version in (("a", "1.2.0"), ("b", "1.3.0")):
        share = tmp_path / prefix / "share" / "iface_runtime_cpp"
        share.mkdir(parents=True)
        (share / "package.xml").write_text(f"<package><version>{version}</version></package>", encoding="utf-8")
    new = str(tmp_path / "b" / "lib" / "libiface_runtime_cpp.so")
    old = str(tmp_path / "a" / "lib" / "libiface_runtime_cpp.so")
    assert why_not("libiface_runtime_cpp.so", new, old) == (
        f"another iface_runtime_cpp: NEW's is {new} (1.3.0), the container runs {old} (1.2.0); one iface_runtime_cpp "
        "per process")
    said = why_not("libticker_msgs__rosidl_typesupport_cpp.so", "/n/lib/x.so", "/o/lib/x.so")
    assert said.startswith("another ticker_msgs (an interface package): ") and "one interface package per process" in said


class _NoCalls:
    """A protocol client that fails the test when anything is sent."""

    def call(self, service: str, fill: dict[str, object], timeout: float, idempotent: bool = True) -> object:
        raise AssertionError(f"{service} was called")


def test_an_untrusted_component_is_refused_before_the_container_is_asked(tmp_path: Path) -> None:
    store = tmp_path / "store"
    store.mkdir()
    pub, _ = keygen(tmp_path / "key")
    shutil.copy(pub, store)
    component = component_in(_package(tmp_path / "pkg"), "ticker", "ticker::Ticker")
    box = ContainerCalls(_NoCalls(), "box")
    with pytest.raises(ContainerError, match=r"ticker \(.*pkg\) is not trusted, not loaded: .*is not signed"):
        box.load(component, "ticker", activate=True, trust_store=store)
    sign(component.prefix, tmp_path / "key")
    component.library.write_bytes(b"\x7fELF changed")
    with pytest.raises(ContainerError, match="libticker_component.so: changed since it was signed"):
        box.load(component, "ticker", trust_store=store)


def test_the_manager_takes_a_system_with_containers(tmp_path: Path) -> None:
    """The manager runs containers now: a system with one is not refused for it (without ROS 2 here it stops only
    because ROS 2 cannot be imported)."""
    examples = Path(__file__).resolve().parents[2] / "examples"
    shutil.copy(examples / "counter.iface", tmp_path)
    (tmp_path / "plant.iface").write_text('system plant version "1.0.0"\ninclude "counter.iface"\n'
                                          'instance one : counter (container = "box")\n', encoding="utf-8")
    done = run_cli("manager", str(tmp_path / "plant.iface"), "--state-dir", str(tmp_path / "state"))
    assert "component containers" not in done.stderr and "Traceback" not in done.stderr, done.stderr
    try:
        import iface_msgs  # noqa: F401
    except ImportError:
        assert done.returncode == 2 and "cannot be imported" in done.stderr, done.stdout + done.stderr
    else:  # pragma: no cover - ROS sourced in the test environment itself
        pytest.skip("iface_msgs is importable here: the manager would run")
