"""The component manager: keeps a system's instances up, keeps their state, replaces them safely (docs/system.md).

``iface-lsp manager SYSTEM`` runs the node ``/iface_manager``. It starts each instance's process
(``processes``), brings the instances up in order (configure, restore the last snapshot of an
instance it started, activate) and, when told to stop, down in reverse order. It watches each
one: its process, whose end it is told of at once (``processes.ExitWatcher``), and a heartbeat
(``~/control`` STATUS) answered within a timeout. A failed instance is restarted per its policy
and the intensity limit (``restart``), its last snapshot restored before it is activated.
Snapshots (``snapshots``) are taken per the instance's period, at every deactivate and on
request. A replacement (``replace``) runs the hand-over's steps (``handover``) with a NEW the
manager starts; from then on the instance runs NEW's implementation (``implementation``). A new
manager adopts the instances still running.

It serves ``/iface_manager/status``, ``/iface_manager/snapshot`` and ``/iface_manager/replace``
(types ``iface_msgs/srv/SystemStatus``, ``Snapshot``, ``Replace``). One lock orders the watch
loop, snapshots and replacements; status answers read without it.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import os
import signal
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..live import deadlock
from ..live.link import Link, LinkError
from ..nodes import protocol
from ..semantics.compile import Workspace
from . import processes
from .container_host import (
    Host,
    component_of,
    container_argv,
    container_ended,
    members,
    parameter_files,
    reload_order,
    second_container,
    second_container_name,
)
from .containers import CONTAINER_EXECUTABLE, CONTAINER_PACKAGE, ContainerError, sharing_problem
from .handover import ACTIVE, FINALIZED, INACTIVE, STATE_LABELS, UNCONFIGURED, HandOver, Refused, decide
from .implementation import Implementation, NotStartable, Replacement, Replacements, of_instance, replacing
from .in_container import ContainerCalls, Loaded
from .processes import ExitWatcher, InstanceProcess, Records, StartError
from .restart import DEFAULT_MAX_RESTARTS, DEFAULT_PERIOD, Intensity, should_restart
from .snapshots import DEFAULT_KEEP, SnapshotStore, iso_time
from .standby import Standby
from .standby import environment as standby_environment

NODE_NAME = "iface_manager"
STATUS_SERVICE = f"/{NODE_NAME}/status"
SNAPSHOT_SERVICE = f"/{NODE_NAME}/snapshot"
REPLACE_SERVICE = f"/{NODE_NAME}/replace"
#: lifecycle_msgs/Transition ids the manager uses beyond configure/activate/deactivate.
CONFIGURE, ACTIVATE, DEACTIVATE = 1, 3, 4
SHUTDOWN_FROM = {UNCONFIGURED: 5, INACTIVE: 6, ACTIVE: 7}
#: Findings kept per instance.
FINDINGS_KEPT = 20
#: Seconds between two requests for a just started instance's first answer: its services are found this soon.
FIRST_ANSWER_RESEND = 0.05
#: Seconds before a bring-up's restore is sent again (a reply the just discovered node dropped).
BRING_UP_RESEND = 0.25
#: The longest the watch loop sleeps (heartbeats and snapshots are due at this grain; a process's end wakes it).
TICK = 0.1


@dataclass
class Options:
    """How the manager runs; every default is in docs/system.md."""

    state_dir: Path
    trust_store: Path | None = None
    max_restarts: int = DEFAULT_MAX_RESTARTS
    restart_period: float = DEFAULT_PERIOD
    heartbeat_period: float = 1.0
    heartbeat_timeout: float = 5.0
    call_timeout: float = 10.0
    start_timeout: float = 30.0
    grace: float = 3.0
    keep: int = DEFAULT_KEEP


@dataclass
class Managed:
    """One instance as the manager sees it: what it runs (``impl``) and its process."""

    spec: Any
    node: str
    impl: Implementation
    store: SnapshotStore
    intensity: Intensity
    generation: int = 1
    state: str = "down"
    process: InstanceProcess | None = None
    restarts: int = 0
    last_snapshot: float | None = None
    next_snapshot: float = 0.0
    heartbeat: Any = None
    heartbeat_sent: float = 0.0
    heartbeat_ok: float = 0.0
    watched: float = 0.0
    findings: list[str] = field(default_factory=list)
    #: The container it is loaded into (its node name; a replacement's may be a second one), None: a process of
    #: its own. ``process`` is then the container's.
    container: str | None = None
    #: Its node in the container (the id ``unload_node`` takes), None while it is not loaded.
    loaded: Loaded | None = None
    #: Its spare process (``standby = "true"``): ROS up and no node, made the instance at its next start.
    standby: Standby = field(default_factory=Standby)

    @property
    def name(self) -> str:
        """The instance name."""
        return str(self.spec.name)

    @property
    def path(self) -> str:
        """The node's fully qualified name."""
        return "/" + self.node.lstrip("/")

    def note(self, message: str) -> None:
        """Keep a finding (the last :data:`FINDINGS_KEPT`)."""
        self.findings.append(message)
        del self.findings[:-FINDINGS_KEPT]


class Manager:
    """The manager of one system; ``serve`` runs it until ``stop`` is set."""

    def __init__(self, system: Any, options: Options, env: dict[str, str]) -> None:
        self.system = system
        self.options = options
        self.env = env
        self.records = Records(options.state_dir)
        self.replacements = Replacements(options.state_dir)
        self.lock = threading.RLock()
        self.stop = threading.Event()
        #: Set when the watch loop should look now (a process ended, or the manager is told to stop).
        self.wake = threading.Event()
        self.watcher = ExitWatcher()
        self.log_dir = options.state_dir / "logs"
        #: ``/iface_manager`` (rclpy), made by ``open``.
        self.node: Any = None
        self._envs: dict[str, dict[str, str]] = {}
        #: The container processes, by node name.
        self.hosts: dict[str, Host] = {}
        self.container_records = Records(options.state_dir)
        self.container_records.folder = options.state_dir / "containers"
        self.instances = [self._managed(spec) for spec in system.instances]

    def _managed(self, spec: Any) -> Managed:
        """An instance as its replacement record (if one holds) or else the system file says."""
        m = Managed(spec, spec.node, of_instance(spec),
                    SnapshotStore(self.options.state_dir / "snapshots" / spec.name, self.options.keep),
                    Intensity(self.options.max_restarts, self.options.restart_period),
                    container=getattr(spec, "container", None))
        replaced = self.replacements.load(spec.name)
        if replaced is not None and replaced.holds_for(spec):
            m.node, m.generation, m.impl = replaced.node, replaced.generation, replaced.implementation
            if m.container is not None and replaced.container:
                m.container = replaced.container  # a second container, NEW could not share the first one
        elif replaced is not None:
            m.note(f"the system file names {spec.component} ({spec.interface_hash[:19]}) for {spec.name}, not what "
                   f"{replaced.implementation.component} replaced: {replaced.implementation.component} no longer runs "
                   "for it")
            self.replacements.remove(spec.name)
        latest = m.store.latest()
        m.last_snapshot = latest.written if latest is not None else None
        return m

    #: Set by a signal handler (an attribute, no lock: the handler may interrupt the thread that holds one).
    stop_requested = False

    def stopping(self) -> bool:
        """Whether the manager is told to stop (``request_stop``, or a signal)."""
        return self.stop_requested or self.stop.is_set()

    def request_stop(self) -> None:
        """Stop serving now (from a thread; a signal handler sets ``stop_requested``, seen within ``TICK``)."""
        self.stop.set()
        self.wake.set()

    # ---- ROS --------------------------------------------------------------------------------------
    def open(self) -> None:
        """Create ``/iface_manager`` and its services, and spin it in a thread."""
        import rclpy
        from iface_msgs.srv import Replace, Snapshot, SystemStatus
        from rclpy.callback_groups import ReentrantCallbackGroup
        from rclpy.executors import MultiThreadedExecutor

        self._rclpy = rclpy
        self.node = rclpy.create_node(NODE_NAME)
        group = ReentrantCallbackGroup()
        self.link = Link(self.node, group)
        self.node.create_service(SystemStatus, STATUS_SERVICE, self._on_status, callback_group=group)
        self.node.create_service(Snapshot, SNAPSHOT_SERVICE, self._on_snapshot, callback_group=group)
        self.node.create_service(Replace, REPLACE_SERVICE, self._on_replace, callback_group=group)
        self.executor = MultiThreadedExecutor(num_threads=4)
        self.executor.add_node(self.node)
        self._spinner = threading.Thread(target=self._spin, name="iface-manager-spin", daemon=True)
        self._spinner.start()

    def _spin(self) -> None:
        with contextlib.suppress(Exception):  # the context was shut down under the executor
            while self._rclpy.ok() and not self._closing:
                self.executor.spin_once()  # woken by work, by ``close`` and by the context's shutdown

    _closing = False

    def close(self) -> None:
        """Stop spinning and destroy the node; stop watching the processes."""
        self._closing = True
        self.executor.wake()
        self._spinner.join(timeout=5)
        self.executor.shutdown(timeout_sec=2.0)
        self.node.destroy_node()
        self.watcher.close()

    def log(self, message: str) -> None:
        """One line on the manager's log."""
        self.node.get_logger().info(message)

    # ---- up, watch, down ---------------------------------------------------------------------------
    def up(self) -> None:
        """Adopt or start each instance, in order, and bring it to active."""
        for m in self.instances:
            for finding in m.findings:
                self.log(f"{m.name}: {finding}")
            if self.stopping():
                return
            with self.lock:
                if m.container is not None or not self._adopt(m):
                    self._start_or_fail(m, "start")

    def serve(self) -> None:
        """Watch the instances until ``stop`` is set; a process's end is looked at the moment it is told."""
        while not self.stopping():
            self.wake.clear()
            with self.lock:
                self._watch_containers()
                for m in self.instances:
                    self._watch(m, time.monotonic())
            self.wake.wait(TICK)

    def down(self) -> None:
        """Deactivate (with a snapshot) and shut down each instance, in reverse order.

        An instance shut down (finalized) does nothing more: the next one is deactivated while its process
        ends, and the processes' ends are then awaited in the same order. One whose shutdown was not
        confirmed is awaited (and stopped) before the next one is deactivated.
        """
        ending = []
        for m in reversed(self.instances):
            with self.lock:
                if self._down(m):
                    ending.append(m)
        for m in ending:
            with self.lock:
                self._ended(m)
        with self.lock:
            for host in list(self.hosts.values()):
                self._stop_host(host)

    def _down(self, m: Managed) -> bool:
        """Deactivate and shut down ``m``; whether its process is left to end (it confirmed its shutdown)."""
        m.standby.stop()
        if m.container is not None:
            self._down_loaded(m)
            return False
        if m.process is None or not m.process.alive():
            self.records.remove(m.name)
            m.state = "down" if m.state not in ("failed",) else m.state
            return False
        t = self.options.call_timeout
        try:
            state = self.link.lifecycle_state(m.path, t)
            if state == ACTIVE:
                self.link.transition(m.path, DEACTIVATE, t)
                state = INACTIVE
                self._snapshot(m, "deactivate")
            if state in SHUTDOWN_FROM:
                self.link.transition(m.path, SHUTDOWN_FROM[state], t)
                return True
            if state == FINALIZED:
                return True
            m.note(f"down: {STATE_LABELS.get(state, state)}, not shut down")
        except LinkError as e:
            m.note(f"down: {e}")
        self._ended(m)
        return False

    def _ended(self, m: Managed) -> None:
        """Wait for the process of ``m`` to end (stopped after 10 s), and say it is down."""
        if m.process is not None and not m.process.wait(10.0):
            m.process.stop(5.0)
        self.records.remove(m.name)
        m.state = "down"
        self.log(f"{m.name}: down")

    def _watched(self, process: InstanceProcess) -> InstanceProcess:
        """``process``, its end told to the watch loop the moment it comes."""
        self.watcher.watch(process, lambda _p: self.wake.set())
        return process

    def _adopt(self, m: Managed) -> bool:
        """Manage again an instance a previous manager started, if it still runs; whether it did.

        A recorded process that runs another node than the instance's (its OLD, which a replacement
        recorded before it was shut down) is stopped, not adopted.
        """
        record = self.records.load(m.name)
        if record is not None and not processes.running(record):
            self.log(f"{m.name}: recorded pid {record.pid} no longer runs")
            record = None
        if record is not None and record.node.lstrip("/") != m.node.lstrip("/"):
            self.log(f"{m.name}: recorded pid {record.pid} runs {record.node}, not the instance's node {m.node} "
                     "(a replacement's OLD, or one the system file no longer names): stopping it")
            InstanceProcess(record).stop(5.0)
            record = None
        if record is None:
            # not recorded (a manager killed right after a start): the graph and /proc still know it
            found = processes.find_by_node(m.node, processes.ros_domain(self.env))
            if len(found) != 1:
                return False
            i = m.impl
            record = dataclasses.replace(found[0], instance=m.name, package_dir=i.package_dir,
                                         iface_file=i.iface_file, interface_hash=i.interface_hash,
                                         generation=m.generation, component=i.component, package=i.package,
                                         executable=i.executable)
            self.records.save(record)
        m.process = self._watched(InstanceProcess(record))
        m.impl = record.implementation() or dataclasses.replace(
            m.impl, iface_file=record.iface_file or m.impl.iface_file,
            interface_hash=record.interface_hash or m.impl.interface_hash, package_dir=record.package_dir)
        m.node, m.generation = record.node, record.generation
        t = self.options.call_timeout
        try:
            state = int(self.link.control(m.path, protocol.STATUS, t).lifecycle_state)
            if state == UNCONFIGURED:
                self.link.transition(m.path, CONFIGURE, t)
                state = INACTIVE
            if state == INACTIVE:
                self.link.transition(m.path, ACTIVATE, t)
        except LinkError as e:
            m.note(f"adopted pid {record.pid} does not answer: {e}; restarting it")
            self.log(f"{m.name}: {m.findings[-1]}")
            m.process.stop(5.0)
            return False
        self._active(m, f"{m.name}: adopted pid {record.pid} ({m.path}, {m.impl.component}, active)")
        return True

    # ---- starting an instance ------------------------------------------------------------------------
    def _environment(self, package_dir: str) -> dict[str, str]:
        """The environment an implementation starts in: the manager's, with its install folder's workspace on top
        (made once per folder)."""
        if not package_dir:
            return self.env
        made = self._envs.get(package_dir)
        if made is None:
            made = self._envs[package_dir] = processes.package_environment(Path(package_dir), self.env)
        return made

    def _launch(self, m: Managed, impl: Implementation, node: str, generation: int, log: str,
                standby: bool = False) -> InstanceProcess:
        """Start a process of ``impl`` as ``node`` for ``m`` (with the instance's parameters), watched; a
        ``standby`` waits for SIGUSR1 before it makes its node."""
        env = self._environment(impl.package_dir)
        exe = processes.find_executable(impl.package, impl.executable, env, impl.package_dir)
        argv = [exe, *(["--standby"] if standby else []), "--ros-args", "-r", f"__node:={node}"]
        if m.spec.parameters:
            argv += ["--params-file", str(m.spec.parameters)]
        proc = processes.start(m.name, node, argv, standby_environment(env) if standby else env, self.log_dir / log,
                               implementation=impl, generation=generation)
        self.log(f"{m.name}: started {'standby ' if standby else ''}pid {proc.pid} ({impl.component}, {exe})")
        return self._watched(proc)

    def _start(self, m: Managed) -> None:
        """Start a process for ``m`` (its standby told, if it has one), configure it, restore its last snapshot,
        activate it."""
        m.state = "starting"
        spare = m.standby.take(lambda p: (p.record.node, p.record.generation, p.record.implementation())
                               == (m.node, m.generation, m.impl))  # not one made for what ran before a replacement
        if spare is not None:
            m.process = spare
            self.log(f"{m.name}: standby pid {spare.pid} told to start")
        else:
            m.process = self._launch(m, m.impl, m.node, m.generation, f"{m.name}.log")
        self.records.save(m.process.record)
        self._bring_up(m, m.process)

    def _keep_standby(self, m: Managed) -> None:
        """Start a standby for an active ``m`` that wants one (``standby = "true"``) and has none running."""
        if not m.spec.standby or m.container is not None or m.state != "active" or self.stopping():
            return
        said = m.standby.keep(lambda: self._launch(m, m.impl, m.node, m.generation, f"{m.name}.log", standby=True))
        if said is not None:
            m.note(said)
            self.log(f"{m.name}: {said}")
        seen = m.standby.seen(self._node_names)
        if seen is not None:
            self.log(f"{m.name}: {seen}")

    def _bring_up(self, m: Managed, proc: InstanceProcess) -> None:
        """Configure, restore the last snapshot, activate; each step logged as it ends."""
        t = self.options.call_timeout
        self._until_answers(m.path, proc)
        self.log(f"{m.name}: answers (pid {proc.pid})")
        self.link.transition(m.path, CONFIGURE, t, alive=proc.alive)
        m.state = "inactive"
        self.log(f"{m.name}: configured")
        latest = m.store.latest()
        if latest is not None:
            done = self.link.call(f"{m.path}/restore_state", {"state": latest.document, "timeout_sec": t}, t + 2,
                                  alive=proc.alive, resend=BRING_UP_RESEND)
            if not done.success:
                raise LinkError(f"{m.path} refused the state: {done.message}")
            self.log(f"{m.name}: restored snapshot {latest.sequence} ({done.message})")
        self.link.transition(m.path, ACTIVATE, t, alive=proc.alive)
        if not proc.alive():
            raise LinkError(f"{m.path} ended while it was activated")
        self._active(m, f"{m.name}: active (pid {proc.pid})")

    def _active(self, m: Managed, line: str) -> None:
        """``m`` is active: ``line`` logged, its heartbeat and snapshot clocks started, and its state set last, as
        status is read without the lock and must never run ahead of the log."""
        self.log(line)
        m.heartbeat, m.heartbeat_ok = None, time.monotonic()
        m.next_snapshot = time.monotonic() + (m.spec.snapshot_period or 0)
        m.state = "active"

    def _until_answers(self, node: str, proc: InstanceProcess) -> None:
        """Wait until ``node`` answers ``~/control``: asked every ``FIRST_ANSWER_RESEND`` s, so the first answer
        comes as soon as its services are discovered both ways."""
        try:
            self.link.call(f"{node}/control", {"command": protocol.STATUS, "timeout_sec": 1.0},
                           self.options.start_timeout, alive=proc.alive, resend=FIRST_ANSWER_RESEND)
        except LinkError:
            if not proc.alive():
                raise LinkError(f"{node}: its process ended (exit {proc.exit_code()}) before it answered") from None
            raise LinkError(f"{node} did not answer within {self.options.start_timeout:g} s") from None

    def _start_or_fail(self, m: Managed, why: str) -> None:
        """Start ``m`` (load it into its container); on failure restart it per policy and intensity until it is up or
        stays down."""
        while True:
            try:
                if m.container is not None:
                    self._load(m)
                else:
                    self._start(m)
                return
            except (StartError, LinkError, ContainerError, NotStartable, OSError) as e:
                reason = f"{why} failed: {e}"
            if not self._may_restart(m, reason, clean=False):
                return
            why = "restart"

    def _may_restart(self, m: Managed, reason: str, clean: bool) -> bool:
        """Record a failure of ``m``; whether it is to be started again (counted as a restart)."""
        m.note(reason)
        self.log(f"{m.name}: {reason}")
        if m.container is not None:
            self._unload(m)
        elif m.process is not None and m.process.alive():
            m.process.stop(2.0)
        self.records.remove(m.name)
        m.heartbeat = None
        if not should_restart(m.spec.restart, failed=not clean):
            m.standby.stop()
            m.state = "stopped"
            m.note(f"not restarted (restart = {m.spec.restart})")
            return False
        if not m.intensity.allow(time.monotonic()):
            m.standby.stop()
            m.state = "failed"
            m.note(f"stays down: more than {m.intensity.max_restarts} restarts within {m.intensity.period:g} s")
            self.log(f"{m.name}: stays down (restart intensity reached)")
            return False
        m.restarts += 1
        m.state = "starting"  # until it is up again: never reported active with no process
        return True

    def _watch(self, m: Managed, now: float) -> None:
        if m.state != "active" or m.process is None:
            return
        if now - m.watched > 2 * self.options.heartbeat_period:
            # not watched for a while (a replacement or another restart held the lock): no heartbeat was
            # asked for, so none is missing; the timeout runs from now
            m.heartbeat, m.heartbeat_ok = None, now
        m.watched = now
        if m.container is not None and not m.process.alive():
            return  # the container's end: _watch_containers restarts every instance in it
        if not m.process.alive():
            code = m.process.exit_code()
            if self._may_restart(m, f"process {m.process.pid} ended" + (f" (exit {code})" if code is not None else ""),
                                 clean=code == 0):
                self._start_or_fail(m, "restart")
            return
        if m.heartbeat is not None and m.heartbeat.done():
            answer = m.heartbeat.result()
            m.heartbeat = None
            if answer is not None:
                m.heartbeat_ok = now
        if m.heartbeat is not None and now - m.heartbeat_sent > 2 * self.options.heartbeat_period:
            m.heartbeat = None  # sent again below: a reply may have been dropped
        if m.heartbeat is None and now - m.heartbeat_sent >= self.options.heartbeat_period:
            m.heartbeat = self.link.send(f"{m.path}/control", {"command": protocol.STATUS, "timeout_sec": 1.0})
            m.heartbeat_sent = now
        if now - m.heartbeat_ok > self.options.heartbeat_timeout:
            if self._may_restart(m, f"no heartbeat for {self.options.heartbeat_timeout:g} s", clean=False):
                self._start_or_fail(m, "restart")
            return
        period = m.spec.snapshot_period
        if period and now >= m.next_snapshot:
            m.next_snapshot = now + period
            self._snapshot(m, "period")
        self._keep_standby(m)

    # ---- containers ---------------------------------------------------------------------------------
    def _host(self, name: str, env: dict[str, str]) -> Host:
        """The running container ``name`` (started, in ``env``, when it does not run)."""
        host = self.hosts.get(name)
        if host is None:
            host = self.hosts[name] = Host(name, env)
        if not host.alive():
            self._start_host(host)
        return host

    def _start_host(self, host: Host) -> None:
        """Start the container process of ``host`` (a previous manager's still running is stopped first: its
        instances are loaded again, with their snapshots) and wait until it answers."""
        record = self.container_records.load(host.name)
        if record is not None and processes.running(record):
            self.log(f"container {host.name}: a previous manager's pid {record.pid} still runs: stopping it")
            InstanceProcess(record).stop(5.0)
        restart = host.process is not None
        spare = host.standby.take()
        if spare is not None:
            proc = spare
            self.log(f"container {host.name}: standby pid {proc.pid} told to start")
        else:
            proc = self._launch_host(host)
        host.process = proc
        host.restarts += int(restart)
        self.container_records.save(proc.record)
        host.calls = ContainerCalls(self.link, host.name)  # its clients kept from a previous start (see ready)
        try:
            host.calls.ready(self.options.start_timeout, alive=proc.alive, resend=FIRST_ANSWER_RESEND)
        except LinkError:
            if not proc.alive():
                raise LinkError(f"container {host.name}: its process ended (exit {proc.exit_code()}) before it "
                                "answered") from None
            raise LinkError(f"container {host.name} did not answer within {self.options.start_timeout:g} s") from None
        self.log(f"container {host.name}: answers (pid {proc.pid})")

    def _launch_host(self, host: Host, standby: bool = False) -> InstanceProcess:
        """Start a container process for ``host`` (a ``standby`` waits for SIGUSR1 to make its node), watched."""
        exe = processes.find_executable(CONTAINER_PACKAGE, CONTAINER_EXECUTABLE, host.env)
        impl = Implementation(CONTAINER_EXECUTABLE, "", "", CONTAINER_PACKAGE, CONTAINER_EXECUTABLE)
        proc = processes.start(host.name, host.name, container_argv(exe, host.name, standby),
                               standby_environment(host.env) if standby else host.env,
                               self.log_dir / f"container.{host.name}.log", implementation=impl, generation=1)
        self.log(f"container {host.name}: started {'standby ' if standby else ''}pid {proc.pid} ({exe})")
        return self._watched(proc)

    def _keep_host_standby(self, host: Host) -> None:
        """Start a standby container for a running ``host`` one of whose active instances says ``standby = "true"``."""
        if self.stopping() or not host.alive() or not any(
                m.spec.standby and m.state == "active" for m in members(self.instances, host.name)):
            return
        said = host.standby.keep(lambda: self._launch_host(host, standby=True))
        if said is not None:
            self.log(f"container {host.name}: {said}")
        seen = host.standby.seen(self._node_names)
        if seen is not None:
            self.log(f"container {host.name}: {seen}")

    def _node_names(self) -> set[str]:
        """The names of the nodes in the manager's graph, hidden ones too (none before ``open``)."""
        return set() if self.node is None else {name for name, _ns in self.node.get_node_names_and_namespaces()}

    def _stop_host(self, host: Host) -> None:
        """Stop the container process of ``host`` (its instances unloaded before) and its standby, and forget it."""
        host.standby.stop()
        if host.process is not None and host.process.alive():
            host.process.stop(5.0)
            self.log(f"container {host.name}: stopped (pid {host.process.pid})")
        self.container_records.remove(host.name)
        self.link.forget("/" + host.name)
        self.hosts.pop(host.name, None)

    def _load(self, m: Managed) -> None:
        """Load ``m`` into its container (started if it does not run): its trust checked first, then configured, its
        last snapshot restored and activated by the container."""
        assert m.container is not None
        env = self._environment(m.impl.package_dir)
        host = self._host(m.container, env)
        assert host.calls is not None and host.process is not None
        m.state, m.process, m.loaded = "starting", host.process, None
        self.link.forget(m.path)
        component = component_of(m.impl, m.spec.plugin, m.impl.component == m.spec.component, env)
        latest = m.store.latest()
        try:
            m.loaded = host.calls.load(component, m.node.lstrip("/"),
                                       params_files=parameter_files(m.spec.parameters),
                                       intra_process=bool(m.spec.intra_process), activate=True,
                                       state=latest.document if latest is not None else "",
                                       trust_store=self.options.trust_store, timeout=self.options.call_timeout)
        except LinkError as e:
            if host.alive() and host.process is not None:
                # a container that does not answer a load is not trusted with the others either: its end
                # restarts every instance in it (_watch_containers), this one first (_start_or_fail)
                self.log(f"container {host.name}: no answer to the load of {m.name} ({e}): stopping pid "
                         f"{host.process.pid}")
                host.process.stop(2.0)
            raise
        restored = f", snapshot {latest.sequence} restored" if latest is not None else ""
        self._active(m, f"{m.name}: active in container {host.name} (pid {host.pid}, {component.plugin} from "
                        f"{component.prefix}{restored})")

    def _unload(self, m: Managed) -> None:
        """Unload ``m`` from its container when it is loaded there and the container runs."""
        host = self.hosts.get(m.container or "")
        if (m.loaded is not None and host is not None and host.alive() and host.calls is not None
                and m.process is host.process):  # an id of a process that ended may be another node's now
            try:
                host.calls.unload(m.loaded.unique_id, self.options.call_timeout)
            except (ContainerError, LinkError) as e:
                m.note(f"unload from container {host.name}: {e}")
        m.loaded = None
        self.link.forget(m.path)

    def _down_loaded(self, m: Managed) -> None:
        """Down for an instance in a container: deactivate (a snapshot), then unload."""
        host = self.hosts.get(m.container or "")
        if m.loaded is None or host is None or not host.alive():
            m.loaded = None
            m.state = "down" if m.state != "failed" else m.state
            return
        t = self.options.call_timeout
        try:
            if self.link.lifecycle_state(m.path, t) == ACTIVE:
                self.link.transition(m.path, DEACTIVATE, t)
                self._snapshot(m, "deactivate")
        except LinkError as e:
            m.note(f"down: {e}")
        self._unload(m)
        m.state = "down"
        self.log(f"{m.name}: down (unloaded from container {host.name})")

    def _watch_containers(self) -> None:
        """A container whose process ended: every instance in it failed, and restarted (in order, with its snapshot)
        per its own policy and intensity."""
        for host in list(self.hosts.values()):
            # those loaded into a process of the container that ended (the current one, or one before it)
            hit = [m for m in reload_order(self.instances, host.name) if m.process is None or not m.process.alive()]
            if not hit:
                if host.process is not None and not host.alive() and not members(self.instances, host.name):
                    self._stop_host(host)
                else:
                    self._keep_host_standby(host)
                continue
            ended = next((m.process for m in hit if m.process is not None), host.process)
            reason = container_ended(host.name, ended.pid if ended is not None else 0,
                                     ended.exit_code() if ended is not None else None)
            self.log(reason)
            for m in hit:
                m.loaded = None  # gone with the process
            again = [m for m in hit if self._may_restart(m, reason, clean=False)]
            for m in again:
                self._start_or_fail(m, "restart")

    def _replace_loaded(self, m: Managed, h: HandOver, report: Any, new: Any, package: Path, generation: int,
                        new_node: str, timeout: float) -> dict[str, Any]:
        """Replace an instance in a container: NEW loaded beside OLD and switched by the container when it can share
        the process; else NEW in a second container, handed over between the two processes."""
        host = self.hosts.get(m.container or "")
        if host is None or not host.alive() or host.calls is None:
            h.note("refused", f"container {m.container} does not run", ok=False)
            return _record(h, report, m, "refused")
        try:
            impl = replacing(m.impl, new, report.new_hash, package)
            env = self._environment(str(package))
            component = component_of(impl, m.spec.plugin, impl.component == m.spec.component, env)
        except (NotStartable, StartError, ContainerError, OSError) as e:
            h.note("load NEW", str(e), ok=False)
            return _record(h, report, m, "refused")
        try:
            problem = sharing_problem(component.library, host.pid, host.env, env)
        except ContainerError as e:
            problem = f"cannot tell whether it can ({e})"
        target = host
        if problem is None:
            h.note("share", f"NEW's {component.library.name} can share container {host.name}'s process: loaded "
                   "beside OLD, switched by the container")
        else:
            name = second_container_name(m.spec.container or host.name, generation)
            h.note("second container", second_container(host.name, name, problem))
            try:
                target = self._host(name, env)
            except (StartError, LinkError, OSError) as e:
                h.note("load NEW", str(e), ok=False)
                if name in self.hosts:
                    self._stop_host(self.hosts[name])
                return _record(h, report, m, "refused")
        assert target.calls is not None and target.process is not None
        try:
            loaded = target.calls.load(component, new_node, params_files=parameter_files(m.spec.parameters),
                                       intra_process=bool(m.spec.intra_process), configure=True,
                                       trust_store=self.options.trust_store, timeout=self.options.start_timeout)
        except (ContainerError, LinkError) as e:
            h.note("load NEW", str(e), ok=False)
            if target is not host:
                self._stop_host(target)
            return _record(h, report, m, "refused")
        h.note("load NEW", f"{new_node} loaded into container {target.name} (pid {target.pid}): {component.plugin} "
               f"from {component.prefix}, configured")
        try:
            h.check_nodes()
            h.prepare()
            if target is host:
                h.switch_in(host.calls, host.name)
            else:
                h.switch()
            failure = self._grace(new_node, target.process)
            if failure is None:
                return self._commit_loaded(m, h, report, target, loaded, impl, new_node, generation)
            h.note("grace", failure, ok=False)
        except Refused as e:
            h.note("refused", str(e), ok=False)
        try:
            target.calls.unload(loaded.unique_id, self.options.call_timeout)
        except (ContainerError, LinkError) as e:
            h.note("unload NEW", str(e), ok=False)
        if target is not host:
            self._stop_host(target)
        self.link.forget("/" + new_node)
        return _undone(h, report, m)

    def _commit_loaded(self, m: Managed, h: HandOver, report: Any, target: Host, loaded: Loaded,
                       impl: Implementation, new_node: str, generation: int) -> dict[str, Any]:
        """NEW (in ``target``) is the instance from now on: recorded, then OLD unloaded (and its container stopped
        when NEW left it empty), then NEW's state saved."""
        old_host, old_loaded, old_path = self.hosts[m.container or ""], m.loaded, m.path
        m.node, m.impl, m.generation, m.loaded = new_node, impl, generation, loaded
        m.container, m.process = target.name, target.process
        m.heartbeat, m.heartbeat_ok = None, time.monotonic()
        self.replacements.save(Replacement(m.name, new_node, generation, impl, m.spec.component,
                                           m.spec.interface_hash, target.name))
        if old_loaded is not None and old_host.calls is not None:
            try:
                old_host.calls.unload(old_loaded.unique_id, self.options.call_timeout)
            except (ContainerError, LinkError) as e:
                h.note("unload OLD", str(e), ok=False)
        self.link.forget(old_path)
        if old_host is not target and not members(self.instances, old_host.name):
            self._stop_host(old_host)
        self._snapshot(m, "replace")
        h.note("commit", f"{m.name} is {m.path} in container {target.name} (pid {target.pid}, {impl.component}); "
               f"OLD {old_path} unloaded")
        self.log(f"{m.name}: replaced by {m.path} in container {target.name} ({impl.component} from "
                 f"{impl.package_dir})")
        return _record(h, report, m, "replaced")

    # ---- snapshots ---------------------------------------------------------------------------------
    def _snapshot(self, m: Managed, why: str) -> str | None:
        """Save ``m``'s state to disk; the file, or None (the reason kept as a finding)."""
        alive = m.process.alive if m.process is not None else None
        try:
            document = str(self.link.save(m.path, self.options.call_timeout, alive=alive).state)
            snap = m.store.write(document)
        except (LinkError, OSError) as e:
            m.note(f"snapshot ({why}) failed: {e}")
            return None
        m.last_snapshot = snap.written
        return str(snap.path)

    def snapshot_all(self, only: str = "") -> tuple[bool, list[str], str]:
        """Snapshots of every running instance (or of ``only``): (all saved, files, message)."""
        with self.lock:
            chosen = [m for m in self.instances if not only or m.name == only]
            if not chosen:
                return False, [], f"no instance {only}"
            files, missed = [], []
            for m in chosen:
                saved = self._snapshot(m, "request") if m.state == "active" else None
                if saved is None:
                    missed.append(m.name)
                else:
                    files.append(saved)
            message = f"{len(files)} snapshot(s) saved" + (f"; not saved: {', '.join(missed)}" if missed else "")
            return not missed, files, message

    # ---- status ------------------------------------------------------------------------------------
    def status(self) -> dict[str, Any]:
        """The status as JSON data (the ``system status --format json`` form)."""
        instances: list[dict[str, Any]] = []
        findings: list[dict[str, str]] = []
        for m in self.instances:
            instances.append({
                "name": m.name, "node": m.path, "component": m.impl.component, "state": m.state,
                "pid": m.process.pid if m.process is not None and m.process.alive() else 0,
                "restarts": m.restarts, "interface_hash": m.impl.interface_hash,
                "last_snapshot": iso_time(m.last_snapshot) if m.last_snapshot is not None else None,
                "container": m.container})
            findings.extend({"instance": m.name, "message": f} for f in m.findings)
        return {"system": self.system.name, "instances": instances, "findings": findings}

    def _on_status(self, request: Any, response: Any) -> Any:
        from iface_msgs.msg import InstanceStatus

        data = self.status()
        response.system = self.system.name
        response.instances = [
            InstanceStatus(name=i["name"], node=i["node"], component=i["component"], state=i["state"], pid=i["pid"],
                           restarts=i["restarts"], interface_hash=i["interface_hash"],
                           last_snapshot=i["last_snapshot"] or "", container=i["container"] or "",
                           findings=[f["message"] for f in data["findings"] if f["instance"] == i["name"]])
            for i in data["instances"]]
        return response

    def _on_snapshot(self, request: Any, response: Any) -> Any:
        response.success, response.files, response.message = self.snapshot_all(request.instance)
        return response

    def _on_replace(self, request: Any, response: Any) -> Any:
        timeout = request.timeout_sec if request.timeout_sec > 0 else self.options.call_timeout
        record = self.replace(request.instance, request.new_iface, request.package, timeout)
        response.success = record["result"] == "replaced"
        response.result = record["result"]
        response.record = json.dumps(record)
        return response

    # ---- replace -----------------------------------------------------------------------------------
    def replace(self, instance: str, new_iface: str, package: str, timeout: float) -> dict[str, Any]:
        """Replace ``instance`` by NEW (``new_iface`` built in ``package``); the hand-over's record."""
        with self.lock:
            m = next((x for x in self.instances if x.name == instance), None)
            if m is None or m.state != "active":
                why = f"no instance {instance}" if m is None else f"{instance} is {m.state}, not active"
                return {"result": "refused", "instance": instance, "steps": [{"step": "refused", "ok": False,
                                                                             "detail": why}]}
            return self._replace(m, new_iface, Path(package), timeout)

    def _replace(self, m: Managed, new_iface: str, package: Path, timeout: float) -> dict[str, Any]:
        """The hand-over's steps with a NEW this manager starts, a grace period, then commit or roll back."""
        generation = m.generation + 1
        new_node = f"{m.spec.node}_{generation}"
        ws = Workspace()
        old, new = ws.compile_path(m.impl.iface_file), ws.compile_path(new_iface)
        others = [ws.compile_path(x.impl.iface_file) for x in self.instances if x is not m]
        report = decide(old, new, others)
        h = HandOver(m.path, new_node, report.new_hash, timeout, self.options.trust_store, package, link=self.link)
        if new.has_errors:
            h.note("compat", f"{new_iface} has errors (`iface-lsp check {new_iface}` lists them)", ok=False)
            return _record(h, report, m, "refused")
        if not h.check_compat(report, new_iface, m.impl.iface_file):
            return _record(h, report, m, "refused")
        try:
            h.check_trust()  # before NEW is started: only trusted code runs
        except Refused as e:
            h.note("refused", str(e), ok=False)
            return _record(h, report, m, "refused")
        if m.container is not None:
            return self._replace_loaded(m, h, report, new, package, generation, new_node, timeout)
        try:
            impl = replacing(m.impl, new, report.new_hash, package)
            proc = self._launch(m, impl, new_node, generation, f"{m.name}.{generation}.log")
        except (NotStartable, StartError, OSError) as e:
            h.note("start NEW", str(e), ok=False)
            return _record(h, report, m, "refused")
        try:
            self._until_answers("/" + new_node, proc)
            h.note("start NEW", f"{new_node} started (pid {proc.pid}): {impl.component} from package {impl.package}, "
                   f"executable {impl.executable}")
        except LinkError as e:
            h.note("start NEW", str(e), ok=False)
            proc.stop(2.0)
            self.link.forget("/" + new_node)
            return _record(h, report, m, "refused")
        try:
            h.check_nodes()
            h.prepare()
            h.switch()
            failure = self._grace(new_node, proc)
            if failure is None:
                return self._commit(m, h, report, proc, impl, new_node, generation)
            h.note("grace", failure, ok=False)
        except Refused as e:
            h.note("refused", str(e), ok=False)
        proc.stop(2.0)
        self.link.forget("/" + new_node)
        return _undone(h, report, m)

    def _grace(self, node: str, proc: InstanceProcess) -> str | None:
        """NEW's first heartbeats within the grace period; None when it stayed up and active."""
        end = time.monotonic() + self.options.grace
        answered = False
        while time.monotonic() < end or not answered:
            if not proc.alive():
                return f"/{node} ended within the grace period"
            try:
                status = self.link.control("/" + node, protocol.STATUS, max(0.5, end - time.monotonic()))
            except LinkError:
                return f"/{node} missed its first heartbeat"
            if status.lifecycle_state != ACTIVE:
                return f"/{node} is no longer active"
            answered = True
            proc.ended.wait(min(0.2, max(0.0, end - time.monotonic())))
        return None

    def _commit(self, m: Managed, h: HandOver, report: Any, proc: InstanceProcess, impl: Implementation,
                new_node: str, generation: int) -> dict[str, Any]:
        """NEW is the instance from now on: recorded (before OLD goes, so that a new manager never adopts OLD),
        then OLD shut down, then NEW's state saved."""
        old_proc, old_path = m.process, m.path
        m.standby.stop()  # OLD's: the next one starts NEW
        m.process, m.node, m.impl, m.generation = proc, new_node, impl, generation
        m.heartbeat, m.heartbeat_ok = None, time.monotonic()
        self.replacements.save(Replacement(m.name, new_node, generation, impl, m.spec.component,
                                           m.spec.interface_hash))
        self.records.save(proc.record)
        try:
            self.link.transition(old_path, SHUTDOWN_FROM[INACTIVE], self.options.call_timeout)
        except LinkError:
            pass
        if old_proc is not None and not old_proc.wait(5.0):
            old_proc.stop(2.0)
        self.link.forget(old_path)
        self._snapshot(m, "replace")
        h.note("commit", f"{m.name} is {m.path} (pid {proc.pid}, {impl.component}); OLD {old_path} shut down")
        self.log(f"{m.name}: replaced by {m.path} (pid {proc.pid}, {impl.component} from {impl.package_dir})")
        return _record(h, report, m, "replaced")


def _undone(h: HandOver, report: Any, m: Managed) -> dict[str, Any]:
    """The record of a replacement that did not go through: refused while OLD was untouched, else OLD rolled back."""
    if not h.touched_old:
        return _record(h, report, m, "refused")
    if h.roll_back():
        h.note("rollback", f"{m.path} active again with its state")
    else:
        h.note("rollback", f"{m.path} could not be made active again with its state", ok=False)
        m.note(f"rollback failed: {[s.detail for s in h.steps if not s.ok][-1:]}")
    return _record(h, report, m, "rolled_back")


def _record(h: HandOver, report: Any, m: Managed, result: str) -> dict[str, Any]:
    out = h.record(report)
    out["result"] = result
    out["instance"] = m.name
    return out


def _end_deadlocked(found: deadlock.Stuck) -> None:
    """A manager whose Fast DDS participant is deadlocked hears and answers nothing again, and destroying the
    participant waits forever: it ends at once (exit 3), and a manager started again (launch respawns it) adopts the
    instances, which run on."""
    sys.stderr.write(f"iface-lsp manager: {found.describe()}; ending so that a manager started again adopts the "
                     "instances\n")
    sys.stderr.flush()
    os._exit(3)


def watch_own_dds(interval: float = 2.5) -> None:
    """Watch this process's Fast DDS participant for the deadlock (``live.deadlock``); found, end the process."""
    deadlock.watch(os.getpid(), _end_deadlocked, interval)


def run(system: Any, options: Options) -> int:
    """Run the manager until SIGINT or SIGTERM; 0 after a clean shutdown (exit 3 where its Fast DDS deadlocks)."""
    import rclpy
    from rclpy.signals import SignalHandlerOptions

    env = dict(os.environ)
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    watch_own_dds()
    manager = Manager(system, options, env)
    previous = {s: signal.signal(s, lambda *_: setattr(manager, "stop_requested", True))
                for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        manager.open()
        manager.log(f"managing {system.name} ({len(manager.instances)} instances), state in {options.state_dir}")
        manager.up()
        manager.serve()
        manager.down()
        manager.close()
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        rclpy.try_shutdown()
    return 0
