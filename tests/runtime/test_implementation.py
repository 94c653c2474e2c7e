"""What an instance runs after a replacement (no ROS): NEW's package and executable from NEW's file and install
folder, the instance's annotations only for NEW of the same component; the replacement kept in the state folder."""

from __future__ import annotations

import shutil
from pathlib import Path
from types import SimpleNamespace

import pytest

from iface.operate.implementation import Implementation, NotStartable, Replacement, Replacements, of_instance, replacing
from iface.semantics.compile import Workspace

ROOT = Path(__file__).resolve().parents[2]
OLD = Implementation("thermostat", "/s/thermostat.iface", "sha256:old", "thermostat", "thermostat")


def _install(folder: Path, package: str, *executables: str) -> Path:
    for name in executables:
        exe = folder / "lib" / package / name
        exe.parent.mkdir(parents=True, exist_ok=True)
        exe.write_text("#!/bin/sh\n")
        exe.chmod(0o755)
    return folder


def _compiled(tmp_path: Path, name: str) -> object:
    shutil.copy(ROOT / "examples" / "room_sensor.iface", tmp_path)
    source = ROOT / "tests" / "runtime" / "data" / f"{name}.iface"
    if not source.is_file():
        source = ROOT / "examples" / f"{name}.iface"
    shutil.copy(source, tmp_path)
    return Workspace().compile_path(str(tmp_path / f"{name}.iface"))


def test_another_component_runs_its_own_package_and_executable_from_its_folder(tmp_path: Path) -> None:
    new = _compiled(tmp_path, "thermostat_pro")
    folder = _install(tmp_path / "ws-pro" / "install" / "thermostat_pro", "thermostat_pro", "thermostat_pro")
    impl = replacing(OLD, new, "sha256:new", folder)  # type: ignore[arg-type]
    assert impl == Implementation("thermostat_pro", str(tmp_path / "thermostat_pro.iface"), "sha256:new",
                                  "thermostat_pro", "thermostat_pro", str(folder))


def test_the_only_executable_of_the_package_is_found_and_none_is_refused(tmp_path: Path) -> None:
    new = _compiled(tmp_path, "thermostat_pro")
    folder = _install(tmp_path / "install", "thermostat_pro", "pro_node")
    assert replacing(OLD, new, "h", folder).executable == "pro_node"  # type: ignore[arg-type]
    with pytest.raises(NotStartable, match="no lib/thermostat_pro/"):
        replacing(OLD, new, "h", _install(tmp_path / "empty", "thermostat"))  # type: ignore[arg-type]


def test_the_same_component_keeps_the_instance_s_package_and_executable(tmp_path: Path) -> None:
    new = _compiled(tmp_path, "thermostat")
    annotated = Implementation("thermostat", "/s/thermostat.iface", "sha256:old", "house_heating", "thermo")
    folder = _install(tmp_path / "install" / "house_heating", "house_heating", "thermo", "other")
    impl = replacing(annotated, new, "sha256:new", folder)  # type: ignore[arg-type]
    assert (impl.package, impl.executable, impl.package_dir) == ("house_heating", "thermo", str(folder))


def test_a_replacement_is_kept_while_the_system_file_names_what_it_replaced(tmp_path: Path) -> None:
    store = Replacements(tmp_path)
    new = Implementation("thermostat_pro", "/p.iface", "sha256:new", "thermostat_pro", "thermostat_pro", "/ws")
    store.save(Replacement("thermostat", "thermostat_3", 3, new, "thermostat", "sha256:old"))
    record = store.load("thermostat")
    assert record is not None and record.implementation == new and record.node == "thermostat_3"
    spec = SimpleNamespace(component="thermostat", iface_file="/s/t.iface", interface_hash="sha256:old",
                           package="thermostat", executable="thermostat")
    assert record.holds_for(spec)
    assert not record.holds_for(SimpleNamespace(component="thermostat", interface_hash="sha256:edited"))
    assert of_instance(spec) == Implementation("thermostat", "/s/t.iface", "sha256:old", "thermostat", "thermostat")
    store.remove("thermostat")
    assert store.load("thermostat") is None
