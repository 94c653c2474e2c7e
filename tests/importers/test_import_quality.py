"""Imported files read as if written by hand: formatted, clean under ``check``, no claims they do not make.

Issue 16: an imported ROS 2 package passes ``fmt --check`` and ``check`` with no warning or hint,
defines its services and actions without claiming to provide them, keeps its comments without
the ``#`` frames of comment boxes, and turns units written in comments into ``unit`` annotations.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from iface.semantics.compile import Workspace

from ..conftest import ROOT, run_main
from .helpers import PX4, ROBOT_GEOMETRY, ROBOT_MSGS, ROS2

RANGE_MSGS = ROS2 / "range_msgs"


def _corpus() -> Path | None:
    """../shared/corpus beside the clone, or the folder IFACE_CORPUS names (absent on a fresh clone)."""
    for p in (os.environ.get("IFACE_CORPUS"), ROOT.parent / "shared" / "corpus", ROOT.parents[1] / "shared" / "corpus"):
        if p and (Path(p) / "ros2").is_dir():
            return Path(p)
    return None


def _import(tmp_path: Path, source: str, *inputs: Path) -> list[Path]:
    done = run_main("import", "-q", "--from", source, *(str(p) for p in inputs), "--out", str(tmp_path))
    assert done.returncode == 0, done.stderr
    return sorted(tmp_path.glob("*.iface"))


def _assert_hand_written(files: list[Path]) -> None:
    fmt = run_main("fmt", "--check", *(str(p) for p in files))
    assert fmt.returncode == 0, fmt.stdout + fmt.stderr
    check = run_main("check", *(str(p) for p in files))
    assert check.returncode == 0, check.stdout
    lines = check.stdout.splitlines()
    assert len(lines) == 1 and lines[0].startswith("ok: "), check.stdout  # not one warning, hint or note


def test_ros2_packages_import_formatted_and_without_any_finding(tmp_path: Path) -> None:
    _assert_hand_written(_import(tmp_path, "ros2", ROBOT_MSGS, ROBOT_GEOMETRY, RANGE_MSGS))


def test_px4_messages_import_formatted_and_without_any_finding(tmp_path: Path) -> None:
    _assert_hand_written(_import(tmp_path, "px4", PX4))


def test_an_imported_package_provides_nothing_it_only_defines(tmp_path: Path) -> None:
    files = _import(tmp_path, "ros2", ROBOT_MSGS, ROBOT_GEOMETRY)
    for path in files:
        iface = Workspace().compile_path(str(path)).interface
        assert iface.component is not None
        assert (iface.services, iface.actions, iface.published, iface.subscribed) == ([], [], [], []), path.name
    text = (tmp_path / "robot_msgs_srv.iface").read_text()
    assert text.count("component robot_msgs") == 1  # the companion file says it is the same package


def test_comment_boxes_lose_their_frame_and_units_become_annotations(tmp_path: Path) -> None:
    (path,) = _import(tmp_path, "ros2", RANGE_MSGS)
    text = path.read_text()
    assert "#\n" not in text and " #" not in text
    assert "     * Sensor geometry\n" in text
    fields = {f.name: f for d in Workspace().compile_path(str(path)).interface.definitions
              for f in getattr(d, "fields", [])}
    units = {name: f.unit for name, f in fields.items()}
    assert units == {"field_of_view": "rad", "min_range": "m", "max_range": "m", "speed_limit": "m/s",
                     "range": None, "temperature": "degC", "strength": None, "mixed": None, "kind": None,
                     "readings": None, "period": "s"}
    assert fields["min_range"].doc == "closest distance it measures [m]"  # the comment is kept
    srv = next(d for d in Workspace().compile_path(str(path)).interface.definitions if d.name == "Calibrate")
    assert srv.request.fields[0].unit == "m" and srv.response.fields[1].unit == "m"


@pytest.mark.parametrize(("comment", "unit"), [
    ("start angle of the scan [rad]", "rad"),
    ("time between measurements [seconds] - if your scanner", "s"),
    ("Voltage in Volts (Mandatory)", "V"),
    ("Negative when discharging (A)  (If unmeasured NaN)", "A"),
    ("Absolute pressure reading in Pascals.", "Pa"),
    ("rad", "rad"),
    ("m/s", "m/s"),
    ("distance in meters", "m"),
    ("intensity data [device-specific units].", None),
    ("one of [jpeg, png]", None),
    ("position in m, velocity [m/s]", None),   # two units: ambiguous
    ("the value in a list", None),             # 'a' is English, not amperes
    ("Position covariance [m^2] defined relative to", None),
])
def test_units_are_read_only_where_unambiguous(comment: str, unit: str | None) -> None:
    from iface.importers.units import unit_of_comment

    assert unit_of_comment([f" {comment}"]) == unit


def test_only_the_first_comment_line_names_the_unit() -> None:
    """The field's own line, else the first line above it: further lines explain, and may name other units."""
    from iface.importers.units import unit_of_comment

    lines = [" The torque or the force to be applied at each joint.", " effort is a torque in newton-meters,",
             " or a force in newtons."]
    assert unit_of_comment(lines) is None


def test_every_corpus_package_imports_as_if_written_by_hand(tmp_path: Path) -> None:
    corpus = _corpus()
    if corpus is None:
        pytest.skip("the shared corpus (../shared/corpus or IFACE_CORPUS) is not here")
    packages = [p for p in sorted((corpus / "ros2").glob("*/")) + sorted((corpus / "ros2").glob("*/*/"))
                if (p / "msg").is_dir() or (p / "srv").is_dir() or (p / "action").is_dir()]
    done = run_main("import", "-q", "--from", "ros2", *(str(p) for p in packages), "--out", str(tmp_path))
    assert done.returncode == 0, done.stderr  # the .idl with a wchar too
    _assert_hand_written(sorted(tmp_path.glob("*.iface")))
