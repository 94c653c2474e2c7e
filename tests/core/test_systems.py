"""System files: text → model (both parse paths), start order, periods, ``system_spec``, and the CLI's
``check`` and ``graph`` on a system (its graph's conflicts located on the instances)."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest

from iface.forms.jsonform import items_from_json, schema_text, to_json
from iface.model import nodes as m
from iface.nodes.system import SystemFileError, system_spec
from iface.semantics.compile import Workspace
from iface.semantics.systems import period, start_order
from iface.syntax.parse import parse_text
from iface.text.printer import print_items
from tests.conftest import run_main

from .helpers import DATA, EXAMPLES, write_home
from .test_every_command import assert_every_command_answers
TEXT = '''/** Two parts. */
system pair version "2.1"
include "a.iface"

/** The second, started first. */
instance second : beta (after = "first", restart = "never")
instance first : alpha
'''


def _model(text: str) -> list[m.Item]:
    result = parse_text(text)
    assert not result.problems, result.problems
    return result.items


@pytest.mark.parametrize("broken", [False, True], ids=["fast path", "recovering parser"])
def test_system_and_instances_are_modelled_with_their_spans(broken: bool) -> None:
    text = TEXT + ("message Broken {\n" if broken else "")
    result = parse_text(text)
    assert bool(result.problems) == broken  # the broken chunk sends the file through lark's recovering parser
    system, include, second, first = result.items[:4]
    assert isinstance(system, m.SystemDecl) and isinstance(include, m.Include)
    assert (system.name, system.version, system.doc) == ("pair", "2.1", "Two parts.")
    assert text[system.span.start:system.span.end] == 'system pair version "2.1"'
    assert text[system.name_span.start:system.name_span.end] == "pair"
    assert isinstance(second, m.Instance) and isinstance(first, m.Instance)
    assert (second.name, second.component, second.doc) == ("second", "beta", "The second, started first.")
    assert text[second.span.start:second.span.end] == 'instance second : beta (after = "first", restart = "never")'
    assert text[second.name_span.start:second.name_span.end] == "second"
    assert text[second.component_span.start:second.component_span.end] == "beta"
    assert [(a.key, a.text) for a in second.annotations] == [("after", "first"), ("restart", "never")]
    assert (first.node, second.value("restart"), first.value("restart")) == ("first", "never", None)


def test_keywords_stay_names_where_a_name_is_wanted() -> None:
    items = _model("struct system {\n    1: i32 instance\n}\ntypedef i32 instance\n")
    assert [type(i).__name__ for i in items] == ["Struct", "Typedef"]
    assert items[0].name == "system" and items[0].fields[0].name == "instance"


def test_start_order_follows_after_then_declaration_order() -> None:
    def names(text: str) -> list[str]:
        return [i.name for i in start_order([x for x in _model(text) if isinstance(x, m.Instance)])]

    assert names(TEXT) == ["first", "second"]
    assert names("instance a : x\ninstance b : x\ninstance c : x\n") == ["a", "b", "c"]
    chained = 'instance a : x (after = "c")\ninstance b : x\ninstance c : x (after = "b")\n'
    assert names(chained) == ["b", "c", "a"]
    cycle = 'instance a : x (after = "b")\ninstance b : x (after = "a")\ninstance c : x\n'
    assert names(cycle) == ["c", "a", "b"]  # a cycle (an error) falls back to declaration order


def test_periods() -> None:
    assert (period("1s"), period("500ms"), period("2min"), period(" 0.25 s ")) == (1.0, 0.5, 120.0, 0.25)
    assert [period(t) for t in ("1", "0s", "-1s", "1h", "often", "")] == [None] * 6


@pytest.fixture(scope="module")
def home(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_home(tmp_path_factory.mktemp("home"))


def test_system_spec_gives_each_instance_what_starting_it_needs(home: Path) -> None:
    spec = system_spec(home)
    assert (spec.name, spec.version, spec.file) == ("home", "0.2.0", home.resolve())
    assert [i.name for i in spec.instances] == ["hall", "kitchen", "heating"]
    hall, kitchen, heating = spec.instances
    assert (hall.node, hall.component, hall.package, hall.executable) == (
        "hall_sensor", "room_sensor", "room_sensor", "room_sensor")
    assert (hall.restart, hall.snapshot_period, hall.after, hall.parameters, hall.line) == (
        "always", None, (), None, 6)
    assert (kitchen.node, kitchen.snapshot_period, kitchen.restart) == ("kitchen", 0.5, "on-failure")
    assert kitchen.parameters == (home.parent / "kitchen.yaml").resolve() and kitchen.parameters.is_file()
    assert (heating.after, heating.restart, heating.package) == (("kitchen", "hall"), "never", "thermostat")
    assert heating.iface_file == (home.parent / "thermostat.iface").resolve()
    # the hash is the component's own, as `iface-lsp hash` and the generated node report it
    hashed = run_main("hash", str(EXAMPLES / "room_sensor.iface"))
    assert hashed.returncode == 0 and hall.interface_hash in hashed.stdout and hall.interface_hash.startswith("sha256:")


def test_system_spec_refuses_a_file_with_errors_or_without_a_system(tmp_path: Path) -> None:
    bad = DATA / "invalid" / "unknown-component_typo.iface"
    with pytest.raises(SystemFileError, match=r"unknown-component_typo\.iface:3:17: error\[unknown-component\]"):
        system_spec(bad)
    with pytest.raises(SystemFileError, match=r"counter\.iface:1:1: error\[no-system\]"):
        system_spec(EXAMPLES / "counter.iface")
    with pytest.raises(SystemFileError, match="cannot read"):
        system_spec(tmp_path / "missing.iface")


def _system(tmp_path: Path, sensor_qos: str, heater_type: str) -> Path:
    (tmp_path / "sensor.iface").write_text(f'''component sensor
namespace ros2 sensor_msgs_x
message Temp {{ float64 c }}
publishes Temp on "/t" ({sensor_qos})
''')
    (tmp_path / "heater.iface").write_text(f'''component heater
namespace ros2 heater_msgs
include "sensor.iface"
message Temp {{ float64 c }}
subscribes {heater_type} on "/t" (qos.reliability = "reliable", qos.durability = "transient_local")
subscribes sensor.Temp on "/nobody"
''')
    system = tmp_path / "house.iface"
    system.write_text('system house\ninclude "sensor.iface"\ninclude "heater.iface"\n'
                      'instance s : sensor\ninstance h : heater\n')
    return system


def test_check_reports_the_system_graph_on_the_instances(tmp_path: Path) -> None:
    system = _system(tmp_path, 'qos.reliability = "best_effort"', "sensor.Temp")
    r = run_main("check", str(system))
    assert r.returncode == 1, r.stdout + r.stderr
    lines = [ln[ln.index("house.iface:"):] for ln in r.stdout.splitlines() if "house.iface:" in ln]
    assert "house.iface:5:10: error[graph-qos-mismatch]: QoS of '/t' cannot match between s and h: reliability: " \
           "offered best_effort, requested reliable; durability: offered volatile, requested transient_local" in lines
    assert "house.iface:5:10: warning[graph-unpublished-topic]: h subscribes '/nobody', which no component of " \
           "the system publishes" in lines
    (tmp_path / "conflict").mkdir()
    conflict = _system(tmp_path / "conflict", 'qos.reliability = "reliable", qos.durability = "transient_local"',
                       "Temp")
    r = run_main("check", "--format", "json", str(conflict))
    found = {(d["line"], d["column"], d["code"]) for d in json.loads(r.stdout)["diagnostics"]
             if d["file"].endswith("house.iface")}
    assert found == {(4, 10, "graph-topic-type-conflict"), (5, 10, "graph-topic-type-conflict"),
                     (5, 10, "graph-unpublished-topic")}
    assert r.returncode == 1


def test_graph_of_a_system_file_has_a_node_per_instance(home: Path) -> None:
    r = run_main("graph", "--format", "json", str(home))
    assert r.returncode == 0, r.stderr
    g = json.loads(r.stdout)
    assert [(c["name"], c["component"]) for c in g["components"]] == [
        ("hall", "room_sensor"), ("kitchen", "room_sensor"), ("heating", "thermostat")]
    links = {(lk["from"], lk["to"], lk["name"]) for lk in g["links"]}
    assert links == {("hall", "heating", "/room/temperature"), ("kitchen", "heating", "/room/temperature")}
    mixed = run_main("graph", str(home), str(EXAMPLES / "counter.iface"))
    assert mixed.returncode == 2 and "is a system file: give it alone" in mixed.stderr


def test_every_command_answers_on_a_system_file(home: Path, tmp_path: Path) -> None:
    assert_every_command_answers(home, tmp_path)


def test_the_living_room_example_is_clean() -> None:
    r = run_main("check", str(EXAMPLES / "living_room.iface"))  # the real entry point, in its own process
    assert r.returncode == 0 and "error" not in r.stdout and "warning" not in r.stdout, r.stdout
    assert run_main("fmt", "--check", str(EXAMPLES / "living_room.iface"), str(EXAMPLES / "room_sensor.iface"),
                   str(EXAMPLES / "thermostat.iface")).returncode == 0


def test_the_json_form_holds_a_system_and_reads_back(home: Path) -> None:
    form = to_json(Workspace().compile_path(str(home)).interface)
    jsonschema.validate(form, json.loads(schema_text()))
    kinds = [x["kind"] for x in form["items"]]
    assert kinds == ["system", "include", "include", "instance", "instance", "instance"]
    assert form["items"][5]["component"] == "thermostat"
    assert print_items(items_from_json(form)) == home.read_text(encoding="utf-8")


def test_default_package_and_executable_are_those_the_rclpy_target_writes(tmp_path: Path) -> None:
    spec = system_spec(EXAMPLES / "living_room.iface")
    for inst in spec.instances:
        r = run_main("generate", str(inst.iface_file), "--target", "rclpy", "--out", str(tmp_path), "-q")
        assert r.returncode == 0, r.stderr
        setup = (tmp_path / inst.package / "setup.py").read_text(encoding="utf-8")
        assert f"'{inst.executable} = {inst.package}.__main__:main'" in setup
        assert f'<name>{inst.package}</name>' in (tmp_path / inst.package / "package.xml").read_text(encoding="utf-8")


CONTAINED = '''system plant
include "counter.iface"
include "room_sensor.iface"

instance sensor : room_sensor
instance one : counter (container = "box")
instance two : counter (container = "box", node = "counter_two", intra_process = "false", after = "one")
instance lone : counter (runtime = "rclcpp")
instance third : counter (container = "other", plugin = "counter::Counter", package = "counter")
'''


def _contained(tmp_path: Path, text: str = CONTAINED) -> Path:
    for name in ("counter.iface", "room_sensor.iface"):
        (tmp_path / name).write_text((EXAMPLES / name).read_text(encoding="utf-8"), encoding="utf-8")
    path = tmp_path / "plant.iface"
    path.write_text(text, encoding="utf-8")
    return path


def test_system_spec_gives_an_instance_in_a_container_its_container_and_class(tmp_path: Path) -> None:
    spec = system_spec(_contained(tmp_path))
    got = {i.name: (i.container, i.runtime, i.plugin, i.intra_process) for i in spec.instances}
    assert got == {"sensor": (None, "rclpy", None, False),
                   "one": ("box", "rclcpp", "counter::Counter", True),
                   "two": ("box", "rclcpp", "counter::Counter", False),
                   "lone": (None, "rclcpp", "counter::Counter", False),
                   "third": ("other", "rclcpp", "counter::Counter", True)}
    assert spec.containers == ("box", "other")
    assert [i.name for i in spec.in_container("box")] == ["one", "two"]
    assert spec.in_container("nothing") == ()


def test_standby_is_for_an_instance_that_may_restart(tmp_path: Path) -> None:
    text = CONTAINED + ('instance spare : counter (standby = "true", node = "spare")\n'
                        'instance spare_rclcpp : counter (runtime = "rclcpp", standby = "true", node = "spare_cpp")\n'
                        'instance boxed : counter (container = "box", standby = "true", node = "boxed")\n'
                        'instance idle : counter (standby = "true", restart = "never", node = "idle")\n'
                        'instance unsure : counter (standby = "yes", node = "unsure")\n')
    path = _contained(tmp_path, text)
    comp = Workspace().compile_path(str(path))
    found = sorted((d.location()[0], d.severity.name, d.message.split(":")[0]) for d in comp.diagnostics
                   if d.code == "invalid-instance-annotation")
    assert found == [(13, "WARNING", ('standby = "true" keeps a spare process for a restart, and restart = "never" '
                                      "never restarts the instance")),
                     (14, "ERROR", "standby must be \"true\" or \"false\", not 'yes'")]
    (tmp_path / "plant.iface").write_text(text.replace('instance unsure : counter (standby = "yes", node = "unsure")\n',
                                                       ""), encoding="utf-8")
    got = {i.name: i.standby for i in system_spec(path).instances}
    assert got == {"sensor": False, "one": False, "two": False, "lone": False, "third": False, "spare": True,
                   "spare_rclcpp": True, "boxed": True, "idle": True}


def test_check_says_what_an_instance_in_a_container_does_not_use(tmp_path: Path) -> None:
    text = CONTAINED + ('instance stray : counter (plugin = "counter::Counter", intra_process = "true")\n'
                        'instance runner : counter (container = "box", executable = "counter")\n')
    comp = Workspace().compile_path(str(_contained(tmp_path, text)))
    found = sorted((d.location()[0], d.code, d.severity.name) for d in comp.diagnostics
                   if d.code == "invalid-instance-annotation")
    assert found == [(10, "invalid-instance-annotation", "WARNING"), (10, "invalid-instance-annotation", "WARNING"),
                     (11, "invalid-instance-annotation", "WARNING")]
    messages = " ".join(d.message for d in comp.diagnostics)
    assert "'plugin' is for an instance in a container" in messages
    assert "'executable' is not used for an instance in a container" in messages
    assert not [d for d in comp.diagnostics if d.severity.name == "ERROR"]


def test_a_container_named_as_a_node_is_refused_with_the_node_as_related(tmp_path: Path) -> None:
    text = CONTAINED.replace('container = "other"', 'container = "counter_two"')
    comp = Workspace().compile_path(str(_contained(tmp_path, text)))
    (clash,) = [d for d in comp.diagnostics if d.code == "container-name-clash"]
    assert clash.location()[0] == 9 and "instance 'two'" in clash.message
    (related,) = clash.related
    assert related.source.text[related.span.start:related.span.end] == '"counter_two"'
    r = run_main("check", str(tmp_path / "plant.iface"))
    assert r.returncode == 1 and "error[container-name-clash]" in r.stdout
