"""What every ROS driver shares (imported inside the ROS 2 environment: it needs rclpy).

``Report`` writes each step's outcome as it goes; ``Component`` is a process started by its argv and
stopped by its own handle (its exit status or signal, or its threads' stacks, in a failed step's
detail); ``Probe`` is the driver's own node, spun in a background executor, whose every call and
wait is bounded; ``Protocol`` calls ~/save_state, ~/restore_state and ~/control of a component.
"""

from __future__ import annotations

import inspect
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any, NoReturn

import rclpy
from diagnostic_msgs.msg import DiagnosticArray
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState, GetState
from rcl_interfaces.srv import DescribeParameters, GetParameters, SetParameters
from rclpy.action import ActionClient
from rclpy.executors import MultiThreadedExecutor
from rclpy.parameter import Parameter, parameter_value_to_python
from rclpy.qos import QoSProfile

from iface.live import deadlock as dds_deadlock

TRANSITIONS = {"configure": Transition.TRANSITION_CONFIGURE, "activate": Transition.TRANSITION_ACTIVATE,
               "deactivate": Transition.TRANSITION_DEACTIVATE, "cleanup": Transition.TRANSITION_CLEANUP,
               "shutdown": Transition.TRANSITION_UNCONFIGURED_SHUTDOWN}
GOAL = {"configure": "inactive", "activate": "active", "deactivate": "inactive", "cleanup": "unconfigured"}
SHUTDOWN_FROM = {"inactive": Transition.TRANSITION_INACTIVE_SHUTDOWN,
                 "active": Transition.TRANSITION_ACTIVE_SHUTDOWN,
                 "unconfigured": Transition.TRANSITION_UNCONFIGURED_SHUTDOWN}


#: The participants of probes that deadlocked (``Probe.revived``), kept so that nothing destroys them.
ABANDONED: list[Any] = []


def run(main: Callable[[], int]) -> NoReturn:
    """End a driver with ``main()``'s code (1 where it raised). Where a probe left a deadlocked participant the
    process ends at once (``os._exit``): destroying that participant, as Python's own exit does, waits forever."""
    try:
        code = main()
    except SystemExit as e:  # a signal handler's sys.exit
        code = e.code if isinstance(e.code, int) else 1
    except BaseException:  # noqa: BLE001 - printed, and the driver's exit code says it
        traceback.print_exc()
        code = 1
    if ABANDONED:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    sys.exit(code)


class StepFailed(Exception):
    """A check of a step did not hold."""


def check(condition: Any, message: str) -> None:
    if not condition:
        raise StepFailed(message)


class Report:
    """The steps and their outcome, written to the result file after each one."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.steps: dict[str, dict[str, Any]] = {}

    def step(self, name: str, fn: Callable[[], Any]) -> bool:
        start = time.monotonic()
        try:
            detail = fn()
            ok = True
        except Exception as e:  # noqa: BLE001 - a failed step, reported
            ok = False
            detail = f"{type(e).__name__}: {e}" if isinstance(e, (StepFailed, TimeoutError)) else \
                traceback.format_exc().strip().splitlines()[-1]
            detail += Component.status_of_all() + dds_deadlock.note()
        self.steps[name] = {"ok": ok, "detail": str(detail or ""), "seconds": round(time.monotonic() - start, 2)}
        self.path.write_text(json.dumps(self.steps, indent=1))
        print(f"{'PASS' if ok else 'FAIL'} {name}: {detail}", flush=True)
        return ok


def stacks_note(pid: int, path: Path) -> str:
    """Write the stacks of every thread of a running process to ``path`` (gdb, bounded); a line saying where."""
    gdb = shutil.which("gdb")
    if gdb is None:
        return ""
    try:
        done = subprocess.run([gdb, "-p", str(pid), "-batch", "-nx", "-ex", "thread apply all bt"],
                              capture_output=True, text=True, timeout=60, check=False)
    except subprocess.TimeoutExpired:
        return f"\n(gdb on {pid} did not end within 60 s)"
    path.write_text(done.stdout + done.stderr)
    return f"\n(stacks of {pid}: {path})"


def entry_point(package: str, *own: str) -> list[str]:
    """The command that starts a generated Python component from its entry point (``own``: its own flags)."""
    return [sys.executable, "-m", package, *own]


class Component:
    """A component process started by ``argv`` (with ``env``, else this one), its log, stopped by its own
    handle."""

    started: list[Component] = []

    def __init__(self, name: str, logs: Path, argv: list[str], ros_args: tuple[str, ...] = (),
                 env: dict[str, str] | None = None) -> None:
        Component.started.append(self)
        self.name = name
        self.log_path = logs / f"{name}.log"
        self._log = open(self.log_path, "w")  # noqa: SIM115 - closed in stop()
        self.proc = subprocess.Popen([*argv, "--ros-args", "-r", f"__node:={name}", *ros_args], env=env,
                                     stdout=self._log, stderr=subprocess.STDOUT)

    @classmethod
    def status_of_all(cls) -> str:
        """Each started process: running (with its threads' stacks, when gdb is there) or its exit status,
        and the end of its log (for a failed step)."""
        parts = []
        for comp in cls.started:
            code = comp.proc.poll()
            tail = (comp.log() if not comp._log.closed else comp.log_path.read_text(errors="replace"))[-600:]
            state = "running" if code is None else f"exited {code}" + (
                f" (signal {signal.Signals(-code).name})" if code < 0 and -code in signal.valid_signals() else "")
            parts.append(f"\n--- {comp.name}: {state}\n{tail}")
            if code is None and not comp._log.closed:
                parts.append(stacks_note(comp.proc.pid, comp.log_path.with_suffix(".stacks.txt")))
        return "".join(parts)

    def log(self) -> str:
        self._log.flush()
        return self.log_path.read_text(errors="replace")

    def wait_exit(self, timeout: float) -> int | None:
        try:
            return self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            return None

    def stop(self) -> None:
        if self.proc.poll() is None:
            self.proc.terminate()
            if self.wait_exit(10) is None:
                self.proc.kill()
                self.proc.wait(timeout=10)
        self._log.close()



class LockedActionClient(ActionClient):
    """rclpy's ActionClient, its lock made first: Kilted's adds the client to its node before it makes the lock
    ``get_num_entities`` takes, and this probe's executor thread, building its wait set meanwhile, ended with an
    AttributeError (a CI run's every later call then timed out). The runtime's class of the same name, for the
    same race; this file does not import the runtime."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self._lock = threading.Lock()
        super().__init__(*args, **kwargs)


def until(predicate: Callable[[], Any], timeout: float, what: str) -> Any:
    """The first true value of ``predicate``, asked every 50 ms, within ``timeout`` seconds."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(0.05)
    raise TimeoutError(f"{what}: not seen within {timeout:g} s")


class Probe:
    """The test's own node, spun by a background executor; every wait bounded.

    Its participant may deadlock inside Fast DDS (``iface.live.deadlock``): a call or wait that ends without
    an answer then looks, and where it finds this process's event thread stuck, the probe opens a new
    participant in its place (its subscriptions made again) and asks once more. The stuck one is never
    destroyed (that waits forever): a driver ends through ``run``."""

    def __init__(self) -> None:
        self._subscriptions: list[tuple[Any, str, Callable[..., None], QoSProfile | int]] = []
        self._fast_specs: list[tuple[Any, str, Callable[..., None], QoSProfile]] = []
        self._stuck: set[int] = set()
        self.revivals = 0
        self._open()

    def _open(self) -> None:
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.node = rclpy.create_node("iface_probe", context=self.context)
        self.executor = MultiThreadedExecutor(num_threads=4, context=self.context)
        self.executor.add_node(self.node)
        self._thread = threading.Thread(target=self.executor.spin, daemon=True)
        self._thread.start()
        self._clients: dict[tuple[Any, str], Any] = {}
        self._action_clients: list[Any] = []
        self._fast: list[tuple[Any, threading.Event, threading.Thread]] = []
        for spec in self._subscriptions:
            self.node.create_subscription(*spec)
        for fast in self._fast_specs:
            self._start_fast(*fast)

    def revived(self) -> bool:
        """True when this process's Fast DDS participant was deadlocked and a new one now takes its place."""
        found = dds_deadlock.stuck(os.getpid(), ignore=frozenset(self._stuck))
        if not found:
            return False
        self._stuck.update(s.tid for s in found)
        print(f"probe: {found[0].describe()}; a new participant takes its place", flush=True)
        for _, stop, _ in self._fast:
            stop.set()
        ABANDONED.append((self.context, self.node, self.executor, self._thread, self._fast, self._clients,
                          self._action_clients))
        self.revivals += 1
        self._open()
        return True

    def fast_subscription(self, msg_type: Any, topic: str, callback: Callable[..., None], qos: QoSProfile) -> None:
        """A subscription on a node of its own that no executor spins: a thread of its own takes every message
        waiting at once (``take_message``, as rclpy's executors take one), then sleeps a millisecond. rclpy's
        executors build a wait set in Python for each message: at 1 kHz on a loaded machine the single-threaded
        one took 333 counts a second (test_manager_containers, the probe's one busy thread), the multi-threaded
        one a third of them; draining takes 2,000 a second at 13 % of a core, where the single-threaded
        executor took 60 %. ``callback`` takes the message, or the message and its info."""
        self._fast_specs.append((msg_type, topic, callback, qos))
        self._start_fast(msg_type, topic, callback, qos)

    def _start_fast(self, msg_type: Any, topic: str, callback: Callable[..., None], qos: QoSProfile) -> None:
        node = rclpy.create_node(f"iface_probe_fast_{len(self._fast)}", context=self.context)
        sub = node.create_subscription(msg_type, topic, callback, qos)
        with_info = len(inspect.signature(callback).parameters) == 2
        stop = threading.Event()

        def drain() -> None:
            while not stop.is_set():
                with sub.handle:
                    taken = sub.handle.take_message(msg_type, False)
                if taken is None:
                    stop.wait(0.001)
                elif with_info:
                    callback(*taken)
                else:
                    callback(taken[0])

        thread = threading.Thread(target=drain, daemon=True)
        thread.start()
        self._fast.append((node, stop, thread))

    def subscribe(self, msg_type: Any, topic: str, callback: Callable[..., None], qos: QoSProfile | int) -> None:
        """A subscription of the probe's node, made again on a new participant (``revived``)."""
        self._subscriptions.append((msg_type, topic, callback, qos))
        self.node.create_subscription(msg_type, topic, callback, qos)

    def close(self) -> None:
        for node, stop, thread in self._fast:
            stop.set()
            thread.join(timeout=5)
            node.destroy_node()
        self.executor.shutdown(timeout_sec=2)
        self._thread.join(timeout=5)
        for client in self._action_clients:
            client.destroy()
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.context)

    def action_client(self, action_type: Any, name: str) -> Any:
        client = LockedActionClient(self.node, action_type, name)
        self._action_clients.append(client)
        return client

    @staticmethod
    def wait(future: Any, timeout: float, what: str) -> Any:
        done = threading.Event()
        future.add_done_callback(lambda _: done.set())
        if not done.wait(timeout):
            raise TimeoutError(f"no answer from {what} within {timeout:g} s")
        return future.result()

    def wait_until(self, predicate: Callable[[], Any], timeout: float, what: str) -> Any:
        """The first true value of ``predicate`` within ``timeout``; once more on a new participant where
        this one is deadlocked (``revived``)."""
        try:
            return until(predicate, timeout, what)
        except TimeoutError:
            if not self.revived():
                raise
            return until(predicate, timeout, what)

    def call(self, srv_type: Any, name: str, request: Any, timeout: float = 10.0, idempotent: bool = False) -> Any:
        """Call a service. An idempotent request is sent again every few seconds until ``timeout``: a
        server seen in the graph may not have matched this client's reply reader yet, and DDS then
        drops the reply (a late reply to an earlier send is ignored by its sequence number). Without an
        answer, once more on a new participant where this one is deadlocked (``revived``)."""
        try:
            return self._call(srv_type, name, request, timeout, idempotent)
        except (TimeoutError, StepFailed):
            if not self.revived():
                raise
            return self._call(srv_type, name, request, timeout, idempotent)

    def _call(self, srv_type: Any, name: str, request: Any, timeout: float, idempotent: bool) -> Any:
        key = (srv_type, name)
        if key not in self._clients:
            self._clients[key] = self.node.create_client(srv_type, name)
        client = self._clients[key]
        check(client.wait_for_service(timeout_sec=timeout), f"service {name} not available after {timeout:g} s")
        if not idempotent:
            return self.wait(client.call_async(request), timeout, name)
        end = time.monotonic() + timeout
        sends = 0
        while True:
            sends += 1
            left = end - time.monotonic()
            try:
                return self.wait(client.call_async(request), max(0.1, min(3.0, left)), name)
            except TimeoutError:
                if left <= 3.0:
                    raise TimeoutError(f"no answer from {name} within {timeout:g} s ({sends} sends)") from None

    def wait_ready(self, node: str, timeout: float = 30.0) -> str:
        """Wait until a newly started ``node`` answers get_state (being in the graph is not enough)."""
        self.wait_until(lambda: f"/{node}/get_state" in self.services_of(node), timeout, f"{node}'s lifecycle services")
        return self.lifecycle_state(node)

    def call_async(self, srv_type: Any, name: str, request: Any, timeout: float = 10.0) -> Any:
        key = (srv_type, name)
        if key not in self._clients:
            self._clients[key] = self.node.create_client(srv_type, name)
        client = self._clients[key]
        check(client.wait_for_service(timeout_sec=timeout), f"service {name} not available after {timeout:g} s")
        return client.call_async(request)

    # ---- lifecycle
    def lifecycle_state(self, node: str) -> str:
        return str(self.call(GetState, f"/{node}/get_state", GetState.Request(), idempotent=True)
                   .current_state.label)

    def transition(self, node: str, label: str) -> str:
        before = self.lifecycle_state(node)
        request = ChangeState.Request()
        request.transition.id = SHUTDOWN_FROM[before] if label == "shutdown" else TRANSITIONS[label]
        try:
            response = self.call(ChangeState, f"/{node}/change_state", request, timeout=20)
        except TimeoutError:  # sent once; without an answer, the state says whether it happened
            if label == "shutdown" or self.lifecycle_state(node) != GOAL[label]:
                raise
            return f"{before} -> {GOAL[label]}"
        check(response.success, f"{label} of {node} refused (was {before})")
        if label == "shutdown":
            return f"{before} -> finalized"
        after = self.lifecycle_state(node)
        return f"{before} -> {after}"

    # ---- parameters
    def params(self, node: str, names: list[str]) -> dict[str, Any]:
        response = self.call(GetParameters, f"/{node}/get_parameters", GetParameters.Request(names=names),
                             idempotent=True)
        return {n: parameter_value_to_python(v) for n, v in zip(names, response.values, strict=True)}

    def describe(self, node: str, names: list[str]) -> dict[str, Any]:
        response = self.call(DescribeParameters, f"/{node}/describe_parameters",
                             DescribeParameters.Request(names=names), idempotent=True)
        return dict(zip(names, response.descriptors, strict=True))

    def set_param(self, node: str, name: str, value: Any) -> tuple[bool, str]:
        request = SetParameters.Request(parameters=[Parameter(name, value=value).to_parameter_msg()])
        result = self.call(SetParameters, f"/{node}/set_parameters", request, idempotent=True).results[0]
        return bool(result.successful), str(result.reason)

    # ---- topics
    def collect(self, msg_type: Any, topic: str, qos: QoSProfile | int = 10) -> list[Any]:
        got: list[Any] = []
        self.subscribe(msg_type, topic, got.append, qos)
        return got

    def diagnostics_of(self, node_fqn: str) -> list[tuple[float, Any]]:
        """(arrival time, status) of every /diagnostics status of ``node_fqn`` from now on."""
        got: list[tuple[float, Any]] = []

        def on(msg: DiagnosticArray) -> None:
            for s in msg.status:
                if s.name == node_fqn:
                    got.append((time.monotonic(), s))

        self.subscribe(DiagnosticArray, "/diagnostics", on, 50)
        return got

    def endpoint_qos(self, topic: str, node: str, publisher: bool) -> Any:
        infos = (self.node.get_publishers_info_by_topic if publisher else
                 self.node.get_subscriptions_info_by_topic)(topic)
        mine = [i for i in infos if i.node_name == node]
        check(mine, f"no {'publisher' if publisher else 'subscription'} of {node} on {topic}: "
                    f"{[i.node_name for i in infos]}")
        return mine[0].qos_profile

    def wait_services(self, node: str, names: tuple[str, ...], timeout: float = 10.0) -> set[str]:
        """``node``'s services once every one of ``names`` is among them: the graph shows what a
        transition created a moment later, longer on a busy machine."""
        end = time.monotonic() + timeout
        while True:
            services = self.services_of(node)
            missing = set(names) - services
            if not missing:
                return services
            if time.monotonic() > end:
                raise StepFailed(f"{sorted(missing)} not served by {node} within {timeout:g} s: {sorted(services)}")
            time.sleep(0.05)

    def services_of(self, node: str) -> set[str]:
        """The services ``node`` (in /) serves; empty while it is not (yet) discovered."""
        if node not in self.node.get_node_names():
            return set()
        try:
            return {name for name, _ in self.node.get_service_names_and_types_by_node(node, "/")}
        except Exception:  # noqa: BLE001 - gone between the two calls
            return set()


class ManagerStatus:
    """``/iface_manager/status`` of a running component manager, as the scenario drivers poll it."""

    def __init__(self, probe: Probe, poll: float = 0.05) -> None:
        self.probe = probe
        self.poll = poll
        self.srv = import_interface("iface_msgs/srv/SystemStatus")

    def __call__(self) -> dict[str, Any]:
        """Each instance's status by its name."""
        answer = self.probe.call(self.srv, "/iface_manager/status", self.srv.Request(), timeout=30, idempotent=True)
        return {i.name: i for i in answer.instances}

    def settle(self, predicate: Callable[[dict[str, Any]], bool], timeout: float, what: str) -> dict[str, Any]:
        """The first status for which ``predicate`` holds, asked every ``poll`` s (a manager starting or gone: asked
        again); StepFailed with the last status seen after ``timeout`` s."""
        end = time.monotonic() + timeout
        last: dict[str, Any] = {}
        while time.monotonic() < end:
            try:
                last = self()
            except Exception:  # noqa: BLE001 - a manager starting or gone: ask again
                time.sleep(self.poll)
                continue
            if predicate(last):
                return last
            time.sleep(self.poll)
        raise StepFailed(f"{what}: not seen within {timeout:g} s; last status: "
                         + "; ".join(f"{n} {i.state} pid {i.pid} restarts {i.restarts} {list(i.findings)[-2:]}"
                                     for n, i in last.items()))


def import_interface(name: str) -> Any:
    """``pkg/kind/Name`` → the class."""
    import importlib

    package, kind, type_name = name.split("/")
    return getattr(importlib.import_module(f"{package}.{kind}"), type_name)


# ---- the component protocol ------------------------------------------------------------------------


class Protocol:
    """~/save_state, ~/restore_state and ~/control of components, whichever package their types are in.

    A generated rclpy component speaks the protocol through ``iface_msgs``; a node that still has the
    services in its own interface package (``package``) is reached through those: each node's type is
    read from the graph once.
    """

    def __init__(self, probe: Probe, package: str = "iface_msgs") -> None:
        self.probe = probe
        self.package = package
        self.save_t = import_interface("iface_msgs/srv/SaveState")
        self.restore_t = import_interface("iface_msgs/srv/RestoreState")
        self.control_t = import_interface("iface_msgs/srv/ComponentControl")
        self._types: dict[str, Any] = {}

    def type_of(self, node: str, service: str) -> Any:
        """The type of ``/node/service`` as the graph shows it (bounded wait), imported."""
        name = f"/{node.lstrip('/')}/{service}"
        if name not in self._types:
            found = self.probe.wait_until(lambda: next((types[0] for n, types in
                                                         self.probe.node.get_service_names_and_types()
                                                         if n == name and types), None), 30, f"{name} in the graph")
            self._types[name] = import_interface(found)
        return self._types[name]

    def save_raw(self, node: str) -> Any:
        save_t = self.type_of(node, "save_state")
        return self.probe.call(save_t, f"/{node}/save_state", save_t.Request(timeout_sec=5.0), idempotent=True)

    def save(self, node: str) -> dict[str, Any]:
        response = self.save_raw(node)
        check(response.success, f"save_state of {node} failed: {response.message}")
        return json.loads(response.state)

    def restore(self, node: str, doc: dict[str, Any] | str) -> Any:
        text = doc if isinstance(doc, str) else json.dumps(doc)
        restore_t = self.type_of(node, "restore_state")
        return self.probe.call(restore_t, f"/{node}/restore_state", restore_t.Request(state=text, timeout_sec=5.0))

    def control(self, node: str, command: int, timeout: float = 10.0) -> Any:
        control_t = self.type_of(node, "control")
        return self.probe.call(control_t, f"/{node}/control",
                               control_t.Request(command=command, timeout_sec=timeout), timeout=timeout + 10)

    def control_async(self, node: str, command: int, timeout: float = 10.0) -> Any:
        control_t = self.type_of(node, "control")
        return self.probe.call_async(control_t, f"/{node}/control",
                                     control_t.Request(command=command, timeout_sec=timeout))


def incompatible(doc: dict[str, Any], variable: str) -> dict[str, Any]:
    """A document as a component whose ``variable`` is a string would save it."""
    other = json.loads(json.dumps(doc))
    other["component"] = doc["component"] + "_v9"
    other["interface_hash"] = "sha256:" + "0" * 64
    other["schema"][variable] = "string"
    other["values"][variable] = "not a number"
    return other
