"""The manager's container logic without ROS 2: which instances a container's end brings down and in which order,
each one's restart counted against its own intensity limit, the finding that names the container, the record's
reason for a second container, and the status's ``container`` field."""

from __future__ import annotations

import os
import threading
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

from iface.live.link import LinkError
from iface.operate import manager as manager_module
from iface.operate.container_host import (
    Host,
    container_argv,
    container_ended,
    members,
    ordered_down,
    reload_order,
    second_container,
    second_container_name,
)
from iface.operate.manager import Manager, Options
from iface.operate.processes import ProcessRecord


def _spec(name: str, container: str | None, restart: str = "on-failure") -> SimpleNamespace:
    return SimpleNamespace(name=name, node=name, component="ticker", iface_file=Path("/x/ticker.iface"),
                           interface_hash="sha256:" + "0" * 64, package="ticker", executable="ticker",
                           restart=restart, snapshot_period=None, after=(), parameters=None, line=1,
                           container=container, runtime="rclcpp" if container else "rclpy",
                           plugin="ticker::Ticker" if container else None, intra_process=bool(container),
                           standby=False)


class _Dead:
    """A container process that ended (killed: no exit status of a child)."""

    pid = 4242
    ended = threading.Event()

    def alive(self) -> bool:
        return False

    def exit_code(self) -> int | None:
        return -9

    def stop(self, grace: float) -> None:
        raise AssertionError("a dead container is not stopped")


def _manager(tmp_path: Path, specs: list[SimpleNamespace], max_restarts: int = 3) -> Manager:
    system = SimpleNamespace(name="plant", instances=tuple(specs))
    m = Manager(system, Options(state_dir=tmp_path, max_restarts=max_restarts), {})
    m.log = lambda message: None  # type: ignore[method-assign]
    m.link = SimpleNamespace(forget=lambda node: None)  # type: ignore[assignment]
    return m


def test_a_containers_instances_in_start_order_and_down_in_reverse() -> None:
    inst = [SimpleNamespace(name=n, container=c, state=s) for n, c, s in (
        ("a", "box", "active"), ("py", None, "active"), ("b", "box", "failed"), ("c", "box", "inactive"),
        ("d", "other", "active"))]
    assert [m.name for m in members(inst, "box")] == ["a", "b", "c"]
    assert [m.name for m in reload_order(inst, "box")] == ["a", "c"]  # b is down already: it stays down
    assert [m.name for m in ordered_down(inst)] == ["d", "c", "b", "py", "a"]
    assert container_argv("/p/iface_container", "box") == ["/p/iface_container", "--ros-args", "-r", "__node:=box"]


def test_a_dead_container_restarts_each_instance_in_it_counted_in_its_own_restarts(tmp_path: Path) -> None:
    mgr = _manager(tmp_path, [_spec("ticker", "box"), _spec("sensor", None), _spec("tally", "box")], max_restarts=1)
    ticker, sensor, tally = mgr.instances
    dead = _Dead()
    mgr.hosts["box"] = Host("box", {}, process=dead)  # type: ignore[arg-type]
    for m in mgr.instances:
        m.state = "active"
    ticker.process = tally.process = dead  # type: ignore[assignment]
    started: list[tuple[str, str]] = []

    def start_or_fail(m: Any, why: str) -> None:
        started.append((m.name, why))
        m.state = "active"

    mgr._start_or_fail = start_or_fail  # type: ignore[method-assign]
    mgr._watch_containers()
    assert started == [("ticker", "restart"), ("tally", "restart")]  # in order; the process instance untouched
    assert (ticker.restarts, tally.restarts, sensor.restarts) == (1, 1, 0)
    said = container_ended("box", 4242, -9)
    assert ticker.findings == [said] and tally.findings == [said] and not sensor.findings
    assert "container box (pid 4242) ended (exit -9)" in said

    # the limit is each instance's: the ticker failed once more on its own, so the next container end leaves it down
    ticker.intensity.times.append(ticker.intensity.times[-1])
    tally.intensity.times.clear()
    ticker.process = tally.process = dead  # type: ignore[assignment]
    started.clear()
    mgr._watch_containers()
    assert started == [("tally", "restart")]
    assert (ticker.state, ticker.restarts, tally.restarts) == ("failed", 1, 2)
    assert "stays down: more than 1 restarts within 60 s" in ticker.findings[-1]


def test_no_instance_of_a_dead_container_is_reported_active_before_it_is_loaded_again(tmp_path: Path) -> None:
    """While the first instance of a container that ended is loaded again, the others are not reported active with
    no process (a client that waited for every instance active took the tally's stale state for a restart)."""
    mgr = _manager(tmp_path, [_spec("ticker", "box"), _spec("tally", "box")])
    dead = _Dead()
    mgr.hosts["box"] = Host("box", {}, process=dead)  # type: ignore[arg-type]
    for m in mgr.instances:
        m.state, m.process = "active", dead  # type: ignore[assignment]
    seen: list[dict[str, tuple[str, int]]] = []

    def start_or_fail(m: Any, why: str) -> None:
        seen.append({i["name"]: (i["state"], i["restarts"]) for i in mgr.status()["instances"]})
        m.state = "active"

    mgr._start_or_fail = start_or_fail  # type: ignore[method-assign]
    mgr._watch_containers()
    assert seen == [{"ticker": ("starting", 1), "tally": ("starting", 1)},
                    {"ticker": ("active", 1), "tally": ("starting", 1)}]


def test_an_instance_with_restart_never_stays_down_when_its_container_ends(tmp_path: Path) -> None:
    mgr = _manager(tmp_path, [_spec("ticker", "box", restart="never"), _spec("tally", "box")])
    mgr.hosts["box"] = Host("box", {}, process=_Dead())  # type: ignore[arg-type]
    for m in mgr.instances:
        m.state = "active"
    started: list[str] = []
    mgr._start_or_fail = lambda m, why: started.append(m.name)  # type: ignore[method-assign]
    mgr._watch_containers()
    assert started == ["tally"]
    assert mgr.instances[0].state == "stopped" and mgr.instances[0].restarts == 0


class _Alive:
    """A container process that runs (one started again after the one before it ended)."""

    pid = 4343

    def alive(self) -> bool:
        return True


def test_instances_left_in_a_containers_previous_process_are_restarted(tmp_path: Path) -> None:
    """The container was started again for one instance (its process stopped when a load got no answer): the
    others, loaded into the process that ended, are restarted too, and those already in the new one are not."""
    mgr = _manager(tmp_path, [_spec("ticker", "box"), _spec("tally", "box")])
    ticker, tally = mgr.instances
    mgr.hosts["box"] = Host("box", {}, process=_Alive())  # type: ignore[arg-type]
    ticker.state, ticker.process = "active", mgr.hosts["box"].process
    tally.state, tally.process = "active", _Dead()  # type: ignore[assignment]
    started: list[str] = []
    mgr._start_or_fail = lambda m, why: started.append(m.name)  # type: ignore[method-assign]
    mgr._watch_containers()
    assert started == ["tally"] and (ticker.restarts, tally.restarts) == (0, 1)
    assert "container box (pid 4242) ended" in tally.findings[-1]


def test_status_names_each_instances_container(tmp_path: Path) -> None:
    mgr = _manager(tmp_path, [_spec("ticker", "box"), _spec("sensor", None)])
    data = mgr.status()
    assert [(i["name"], i["container"]) for i in data["instances"]] == [("ticker", "box"), ("sensor", None)]


def test_the_record_says_why_new_goes_into_a_second_container() -> None:
    name = second_container_name("box", 2)
    assert name == "box_2"
    said = second_container("box", name, "another iface_runtime_cpp: NEW's is /n (1.5.0), the container runs /o "
                            "(1.4.0); one iface_runtime_cpp per process")
    assert said.startswith("NEW cannot share the process of container box: another iface_runtime_cpp")
    assert said.endswith("loaded into a second container box_2 and handed over between the two processes")



class _Hung:
    """A container process that runs but does not answer; ``stop`` ends it."""

    pid = 4444

    def __init__(self) -> None:
        self.stopped = False

    def alive(self) -> bool:
        return not self.stopped

    def stop(self, grace: float) -> None:
        self.stopped = True


class _NoAnswer:
    """Container calls whose load gets no answer."""

    def load(self, *args: Any, **kwargs: Any) -> Any:
        raise LinkError("/box/_container/load_node does not answer within 10 s")


def test_a_container_that_does_not_answer_a_load_is_stopped(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Its end then restarts every instance in it (the one being loaded first, by _start_or_fail)."""
    mgr = _manager(tmp_path, [_spec("ticker", "box")])
    ticker = mgr.instances[0]
    hung = _Hung()
    mgr.hosts["box"] = Host("box", {}, process=hung, calls=_NoAnswer())  # type: ignore[arg-type]
    monkeypatch.setattr(manager_module, "component_of", lambda *a: SimpleNamespace(plugin="ticker::Ticker",
                                                                                    prefix=Path("/p")))
    with pytest.raises(LinkError, match="does not answer"):
        mgr._load(ticker)
    assert hung.stopped and ticker.loaded is None and ticker.state == "starting"


class _Answers:
    """A link whose every call and transition succeeds, and container calls whose load does."""

    def forget(self, node: str) -> None:
        pass

    def call(self, *args: Any, **kwargs: Any) -> Any:
        return SimpleNamespace(success=True, message="ok")

    def transition(self, *args: Any, **kwargs: Any) -> None:
        pass

    def load(self, *args: Any, **kwargs: Any) -> Any:
        return SimpleNamespace(unique_id=1, full_node_name="/ticker")

    def control(self, *args: Any, **kwargs: Any) -> Any:
        return SimpleNamespace(lifecycle_state=manager_module.ACTIVE)


class _Running:
    pid = 4343

    def alive(self) -> bool:
        return True


def _logged_with_state(mgr: Manager) -> list[tuple[str, str]]:
    """Each line the manager logs, with its instance's state when the line was written."""
    lines: list[tuple[str, str]] = []
    mgr.log = lambda message: lines.append((message, mgr.instances[0].state))  # type: ignore[method-assign]
    return lines


@pytest.mark.parametrize("container", [None, "box", "adopted"])
def test_an_instance_is_reported_active_only_after_the_log_says_so(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, container: str | None) -> None:
    """Status is read without the manager's lock: a client that saw every instance active and then read the log
    found no "spare: active" line in it (the state was set, the line not yet written)."""
    mgr = _manager(tmp_path, [_spec("ticker", None if container == "adopted" else container)])
    mgr.link = _Answers()  # type: ignore[assignment]
    lines = _logged_with_state(mgr)
    ticker = mgr.instances[0]
    if container is None:
        mgr._bring_up(ticker, _Running())  # type: ignore[arg-type]
    elif container == "adopted":
        record = ProcessRecord("ticker", "/ticker", os.getpid(), 1, (), "/p", "ticker.iface", "sha256:x", 1)
        monkeypatch.setattr(mgr.records, "load", lambda name: record)
        monkeypatch.setattr(manager_module.processes, "running", lambda r: True)
        monkeypatch.setattr(mgr, "_watched", lambda process: process)
        assert mgr._adopt(ticker)
    else:
        mgr.hosts["box"] = Host("box", {}, process=_Running(), calls=_Answers())  # type: ignore[arg-type]
        monkeypatch.setattr(manager_module, "component_of", lambda *a: SimpleNamespace(plugin="ticker::Ticker",
                                                                                        prefix=Path("/p")))
        monkeypatch.setattr(mgr, "_environment", lambda package_dir: {})
        mgr._load(ticker)
    active = [(line, state) for line, state in lines if line.startswith(("ticker: active", "ticker: adopted"))]
    assert len(active) == 1 and active[0][1] != "active", lines
    assert ticker.state == "active"
