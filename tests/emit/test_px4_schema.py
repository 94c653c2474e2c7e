"""Every module.yaml the px4 target writes for an example or a fixture passes PX4's own schema.

PX4 checks module.yaml files with cerberus against ``validation/module_schema.yaml``
(``Tools/validate_yaml.py``); the schema is shipped unchanged in ``data/px4`` (see its README).
"""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from iface.emit import generate
from iface.model.diagnostics import Severity
from iface.semantics.compile import Workspace

cerberus = pytest.importorskip("cerberus", reason="PX4's schema is a cerberus schema: pip install cerberus")

# PX4's schema uses cerberus's older rule names (keyschema, valueschema), which cerberus 1.3 still reads
pytestmark = pytest.mark.filterwarnings("ignore:The rule '.*' was renamed:DeprecationWarning")

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = Path(__file__).parent / "data" / "px4" / "module_schema.yaml"
SOURCES = sorted(ROOT.glob("examples/*.iface")) + sorted(ROOT.glob("tests/**/*.iface"))


def validator() -> object:
    return cerberus.Validator(yaml.safe_load(SCHEMA.read_text(encoding="utf-8")))


def px4_validate(text: str) -> dict[str, object]:
    """The errors PX4's validate_yaml.py would print for one module.yaml (empty when it passes)."""
    doc = yaml.safe_load(text)
    for key in [k for k in doc if k.startswith("__")]:
        del doc[key]
    v = validator()
    return {} if v.validate(doc) else v.errors  # type: ignore[attr-defined]


def module_yamls() -> dict[str, str]:
    """module.yaml of every example and fixture the px4 target generates without error."""
    out: dict[str, str] = {}
    for path in SOURCES:
        comp = Workspace().compile_path(str(path))
        if any(d.severity == Severity.ERROR for d in comp.all_diagnostics()):
            continue
        result = generate(comp, "px4")
        if result.has_errors:
            continue
        for f in result.files:
            if f.path.endswith("/module.yaml"):
                out[f"{path.relative_to(ROOT)}: {f.path}"] = f.text
    return out


def test_every_module_yaml_passes_px4s_schema() -> None:
    found = module_yamls()
    # the examples (robot_arm, counter …) and the px4 fixtures make modules: an empty sweep would prove nothing
    assert len(found) >= 10 and any(k.startswith("examples/") for k in found), sorted(found)
    failing = {k: e for k, text in found.items() if (e := px4_validate(text))}
    assert not failing, failing


def test_the_schema_refuses_what_px4_refuses() -> None:
    base = ("module_name: m\nparameters:\n  - group: g\n    definitions:\n      M_X:\n"
            "        description: {short: s, long: l}\n        type: float\n        default: 1.0\n")
    assert px4_validate(base) == {}
    assert px4_validate(base + "        unit: meters\n")
    assert px4_validate(base + "        increment: fast\n")
    assert px4_validate(base.replace("type: float", "type: double"))
    assert px4_validate(base.replace("        default: 1.0\n", ""))


def test_units_min_max_decimal_increment(tmp_path: Path) -> None:
    src = tmp_path / "tuner.iface"
    src.write_text('component tuner (px4.prefix = "TUN")\nconfiguration c {\n'
                   '    /** Gain. */\n    float gain = 0.5 (unit = "m/s", range = "0..2", px4.decimal = 2, '
                   'px4.increment = 0.05),\n    i32 count = 3 (min = 1, max = 9, unit = "Hz")\n}\n')
    result = generate(Workspace().compile_path(str(src)), "px4")
    assert not result.has_errors, [d.format() for d in result.diagnostics]
    text = next(f.text for f in result.files if f.path.endswith("module.yaml"))
    assert px4_validate(text) == {}
    defs = yaml.safe_load(text)["parameters"][0]["definitions"]
    assert {k: defs["TUN_GAIN"][k] for k in ("unit", "min", "max", "decimal", "increment")} == {
        "unit": "m/s", "min": 0.0, "max": 2.0, "decimal": 2, "increment": 0.05}
    assert {k: defs["TUN_COUNT"][k] for k in ("unit", "min", "max")} == {"unit": "Hz", "min": 1, "max": 9}


def test_a_bad_increment_is_an_error_at_the_annotation(tmp_path: Path) -> None:
    src = tmp_path / "tuner.iface"
    src.write_text('component tuner\nconfiguration c {\n    float gain = 0.5 (px4.increment = "fast")\n}\n')
    result = generate(Workspace().compile_path(str(src)), "px4")
    codes = [(d.code, d.location()[0]) for d in result.diagnostics if d.severity == Severity.ERROR]
    assert codes == [("px4-annotation", 3)]
