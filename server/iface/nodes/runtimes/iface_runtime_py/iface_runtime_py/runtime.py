"""The node machinery of components iface generates (rclpy): lifecycle, work transactions, Δ, Σ.

The same for every component, shared by them all (this package); the generated base class
(``base.py`` of the component package) says what a component has, the user's class (``node.py``)
what it does. The protocol services use the types of ``iface_msgs``. How it fits together:
docs/runtime.md.

Callback groups, and why:
- ``main_group`` (mutually exclusive): subscriptions, services, work timers. Each call is a work
  transaction; the user's main code runs one callback at a time.
- ``action_group`` (reentrant): action servers, so a long goal neither blocks the topics nor its
  own cancel requests. Each goal is one work transaction.
- ``client_group`` (reentrant): service and action clients, so a handler can wait for an answer.
- ``diagnostics_group``: the /diagnostics timer and the Δ services.
- ``control_group``: ~/control, ~/save_state, ~/restore_state, ~/describe.
The multi-threaded executor has a thread for each, so diagnostics and control are answered
while the main callbacks are busy.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import signal
import sys
import threading
import time
import traceback
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any, ClassVar

import rclpy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from iface_msgs.srv import ComponentControl, Describe, RestoreState, SaveState
from rcl_interfaces.msg import (
    FloatingPointRange,
    IntegerRange,
    ParameterDescriptor,
    ParameterType,
    ParameterValue,
    SetParametersResult,
)
from rclpy.action import ActionClient, ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import MutuallyExclusiveCallbackGroup, ReentrantCallbackGroup
from rclpy.duration import Duration
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.lifecycle import LifecycleNode, LifecycleState, TransitionCallbackReturn
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    LivelinessPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_services_default,
)

from . import __version__
from .describe import interface_json
from .gate import Gate
from .handlers import HandlerSpec, InterfaceMismatch, handler_problems
from .params import ParamSpec
from .protocol import (
    ALIGN_SEC,
    DEFAULT_TIMEOUT_SEC,
    DIAGNOSTICS_TOPIC,
    HANDLER_PREFIXES,
    PAUSE,
    PROTOCOL_VERSION,
    RESUME,
    SAVE,
    STATUS,
)
from .state import StateCodec, StateError

#: What ``Describe`` says this runtime is (its version: package.xml's).
RUNTIME = "rclpy"
RUNTIME_VERSION = __version__
#: How long cleanup, shutdown and error wait for the work in progress before destroying the members.
CLOSE_TIMEOUT_SEC = 5.0
_LEVELS = {"ok": DiagnosticStatus.OK, "warn": DiagnosticStatus.WARN, "error": DiagnosticStatus.ERROR,
           "stale": DiagnosticStatus.STALE}


# ---- QoS ----------------------------------------------------------------------------------------

_RELIABILITY = {"reliable": ReliabilityPolicy.RELIABLE, "best_effort": ReliabilityPolicy.BEST_EFFORT,
                "system_default": ReliabilityPolicy.SYSTEM_DEFAULT}
_DURABILITY = {"volatile": DurabilityPolicy.VOLATILE, "transient_local": DurabilityPolicy.TRANSIENT_LOCAL,
               "system_default": DurabilityPolicy.SYSTEM_DEFAULT}
_HISTORY = {"keep_last": HistoryPolicy.KEEP_LAST, "keep_all": HistoryPolicy.KEEP_ALL,
            "system_default": HistoryPolicy.SYSTEM_DEFAULT}
_LIVELINESS = {"automatic": LivelinessPolicy.AUTOMATIC, "manual_by_topic": LivelinessPolicy.MANUAL_BY_TOPIC,
               "system_default": LivelinessPolicy.SYSTEM_DEFAULT}


def qos_profile(settings: dict[str, Any], base: QoSProfile | None = None) -> QoSProfile:
    """A QoS profile from the interface's ``qos.*`` settings (durations in seconds), on top of ``base``."""
    profile = QoSProfile(depth=10) if base is None else QoSProfile(
        history=base.history, depth=base.depth, reliability=base.reliability, durability=base.durability)
    if "history" in settings:
        profile.history = _HISTORY[settings["history"]]
    if "depth" in settings:
        profile.depth = int(settings["depth"])
    if "reliability" in settings:
        profile.reliability = _RELIABILITY[settings["reliability"]]
    if "durability" in settings:
        profile.durability = _DURABILITY[settings["durability"]]
    if "liveliness" in settings:
        profile.liveliness = _LIVELINESS[settings["liveliness"]]
    for key in ("deadline", "lifespan", "liveliness_lease_duration"):
        if key in settings:
            setattr(profile, key, Duration(nanoseconds=round(float(settings[key]) * 1e9)))
    return profile


# ---- messages as the state document sees them ---------------------------------------------------


def _message_class(name: str) -> Any:
    package, _, type_name = name.partition("/")
    return getattr(importlib.import_module(f"{package}.msg"), type_name)


def _type_text(t: Any) -> str:
    from rosidl_parser import definition as d

    if isinstance(t, d.Array):
        return f"{_type_text(t.value_type)}[{t.size}]"
    if isinstance(t, d.BoundedSequence):
        return f"{_type_text(t.value_type)}[<={t.maximum_size}]"
    if isinstance(t, d.UnboundedSequence):
        return f"{_type_text(t.value_type)}[]"
    if isinstance(t, d.NamespacedType):
        return f"{t.namespaces[0]}/{t.name}"
    if isinstance(t, d.BoundedString):
        return f"string<={t.maximum_size}"
    if isinstance(t, d.UnboundedString):
        return "string"
    if isinstance(t, d.BoundedWString):
        return f"wstring<={t.maximum_size}"
    if isinstance(t, d.UnboundedWString):
        return "wstring"
    names = {"boolean": "bool", "octet": "byte", "float": "float32", "double": "float64",
             "long double": "float64", "wchar": "uint16"}
    return names.get(t.typename, t.typename)


def describe_message(name: str) -> dict[str, str]:
    """The fields of message ``package/Name`` and their types, in order."""
    cls = _message_class(name)
    return {field: _type_text(t) for field, t in zip(cls.get_fields_and_field_types(), cls.SLOT_TYPES, strict=True)}


# ---- parameters ----------------------------------------------------------------------------------

_PARAM_TYPES = {
    "bool": (ParameterType.PARAMETER_BOOL, "bool_value"),
    "integer": (ParameterType.PARAMETER_INTEGER, "integer_value"),
    "double": (ParameterType.PARAMETER_DOUBLE, "double_value"),
    "string": (ParameterType.PARAMETER_STRING, "string_value"),
    "bool_array": (ParameterType.PARAMETER_BOOL_ARRAY, "bool_array_value"),
    "integer_array": (ParameterType.PARAMETER_INTEGER_ARRAY, "integer_array_value"),
    "double_array": (ParameterType.PARAMETER_DOUBLE_ARRAY, "double_array_value"),
    "string_array": (ParameterType.PARAMETER_STRING_ARRAY, "string_array_value"),
}


def _descriptor(spec: ParamSpec) -> ParameterDescriptor:
    ptype, _ = _PARAM_TYPES[spec.kind]
    d = ParameterDescriptor(name=spec.name, type=ptype, description=spec.description,
                            additional_constraints=spec.constraints, read_only=spec.read_only)
    if spec.kind == "integer" and not spec.choices and (spec.low is not None or spec.high is not None):
        low = int(spec.low) if spec.low is not None else -(2 ** 63)
        high = int(spec.high) if spec.high is not None else 2 ** 63 - 1
        d.integer_range = [IntegerRange(from_value=low, to_value=high, step=0)]
    elif spec.kind == "double" and spec.low is not None and spec.high is not None:
        d.floating_point_range = [FloatingPointRange(from_value=float(spec.low), to_value=float(spec.high),
                                                     step=0.0)]
    return d


def _initial(spec: ParamSpec) -> Any:
    """The value a parameter is declared with: its default, or its type alone (set it at launch)."""
    ptype, slot = _PARAM_TYPES[spec.kind]
    if spec.default is None:
        return Parameter.Type(ptype)
    value = ParameterValue(type=ptype)
    default = spec.default
    if spec.kind == "double":
        default = float(default)
    elif spec.kind == "double_array":
        default = [float(x) for x in default]
    setattr(value, slot, default)
    return value


# ---- the node -------------------------------------------------------------------------------------


class LockedActionClient(ActionClient):
    """rclpy's ActionClient, its lock made first. Kilted's adds the client to the node before it makes the lock
    that ``get_num_entities`` takes, and an executor thread may build its wait set meanwhile (a configure runs in
    one of the executor's threads while the main thread spins): AttributeError, the process ended."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self._lock = threading.Lock()
        super().__init__(*args, **kwargs)


class ComponentExecutor(MultiThreadedExecutor):
    """rclpy's MultiThreadedExecutor, with rclpy's own fix of ros2/rclpy#1485 for the releases that lack it (Jazzy's
    rclpy 7.1.6): a timer cancelled between the executor's wait and its call (``_continue_schedule`` cancels a
    work timer at an activation) is skipped. Unfixed, the executor thread raised "timer is canceled": the timer
    stayed marked as taken and its mutually exclusive callback group busy, and ``spin_once`` ended the node."""

    def _take_timer(self, tmr: Any) -> Any:
        try:
            return super()._take_timer(tmr)
        except _rclpy.RCLError:
            if not tmr.is_canceled():
                raise
            return None


class WorkTimer:
    """A work timer: its name (the callback's), period, the rclpy timer, and when it last ran (ns since the epoch)."""

    def __init__(self, name: str, period_sec: float) -> None:
        self.name = name
        self.period_sec = period_sec
        self.timer: Any = None
        self.tick: Callable[[], None] = lambda: None
        self.last_ns = 0


class ComponentNode(LifecycleNode):
    """A managed node built from an interface; subclassed by the generated base class."""

    # Set by the generated base class.
    COMPONENT = ""
    VERSION = ""
    INTERFACE_HASH = ""
    SOURCE = ""
    NODE_NAME = ""
    PACKAGE = ""
    STATE_TYPE: Any = None
    STATE_SCHEMA: ClassVar[dict[str, str]] = {}
    PARAMETERS: tuple[ParamSpec, ...] = ()
    HANDLERS: ClassVar[dict[str, HandlerSpec]] = {}
    DIAGNOSTICS_RATE = 1.0
    #: The json target's file of the interface, installed as ``share/<PACKAGE>/<INTERFACE_FILE>`` (``Describe``
    #: answers it).
    INTERFACE_FILE = ""
    #: The same, compact, as base classes generated before runtime 1.2 carry it.
    INTERFACE_JSON = ""
    ACTION_SERVERS = 0
    CLIENTS = 0

    def __init__(self, node_name: str | None = None, **kwargs: Any) -> None:
        problems = type(self).interface_problems()
        if problems:
            raise InterfaceMismatch("; ".join(problems))
        self.main_group = MutuallyExclusiveCallbackGroup()
        self.action_group = ReentrantCallbackGroup()
        self.client_group = ReentrantCallbackGroup()
        self.diagnostics_group = MutuallyExclusiveCallbackGroup()
        self.control_group = MutuallyExclusiveCallbackGroup()
        super().__init__(node_name or self.NODE_NAME, **kwargs)
        self._guard_change_state()
        self.gate = Gate()
        self.finalized = threading.Event()
        self.active = False
        self.state: Any = self.STATE_TYPE() if self.STATE_TYPE is not None else None
        self.codec = StateCodec(self.COMPONENT, self.VERSION, self.INTERFACE_HASH, self.STATE_SCHEMA,
                                describe_message, lambda name: _message_class(name)())
        self._entities: list[tuple[str, Any]] = []
        self._lock = threading.Lock()
        self._counts = {"dropped_inactive": 0, "errors": 0}
        self._last_error = ""
        self._error_seen = False
        self._status: tuple[int, str] | None = None
        self._work_timers: list[WorkTimer] = []
        self._ticked = threading.Condition()
        self._schedule: dict[str, int] = {}
        for spec in self.PARAMETERS:
            self.declare_parameter(spec.name, _initial(spec), _descriptor(spec))
        self._param_specs = {spec.name: spec for spec in self.PARAMETERS}
        self.add_on_set_parameters_callback(self._check_parameters)
        self._diagnostics_pub = self.create_publisher(DiagnosticArray, DIAGNOSTICS_TOPIC, 10)
        self._diagnostics_timer = self.create_timer(1.0 / self.DIAGNOSTICS_RATE, self._publish_diagnostics,
                                                    callback_group=self.diagnostics_group)
        self.create_service(SaveState, "~/save_state", self._on_save_state, callback_group=self.control_group)
        self.create_service(RestoreState, "~/restore_state", self._on_restore_state,
                            callback_group=self.control_group)
        self.create_service(ComponentControl, "~/control", self._on_control, callback_group=self.control_group)
        self.create_service(Describe, "~/describe", self._on_describe, callback_group=self.control_group)
        self._create_diagnostics()

    def _guard_change_state(self) -> None:
        """Answer a transition the state machine refuses with ``success: false``, as Kilted's rclpy does: Jazzy's
        (7.1) lets its ``RCLError`` out of the ``~/change_state`` callback, which ends the process (a caller that
        sent one transition twice, e.g. after a lost answer, would kill the node)."""
        service = getattr(self, "_service_change_state", None)
        if service is None:
            return
        on_change_state = service.callback

        def guarded(request: Any, response: Any) -> Any:
            try:
                return on_change_state(request, response)
            except _rclpy.RCLError as e:
                self.get_logger().warning(f"transition {request.transition.id} refused in state "
                                          f"{self._state_machine.current_state[1]}: {e}")
                response.success = False
                return response

        service.callback = guarded

    # ---- what the user may call or override ------------------------------------------------------
    @classmethod
    def interface_problems(cls) -> list[str]:
        """Where the user's class does not match the interface (empty when it does)."""
        base = next((k for k in cls.__mro__ if "HANDLERS" in vars(k)), cls)
        return handler_problems(cls, base, cls.HANDLERS, HANDLER_PREFIXES, cls.SOURCE)

    def setup(self) -> None:
        """Called on configure, once the members exist: create work timers here. Raise to fail."""

    def teardown(self) -> None:
        """Called on cleanup and shutdown, before the members are destroyed."""

    def on_active(self) -> None:
        """Called when the node has become active."""

    def on_inactive(self) -> None:
        """Called when the node stops being active."""

    def state_restored(self) -> None:
        """Called after a state document was restored into ``self.state``."""

    def diagnostic_values(self) -> dict[str, Any]:
        """More key/values for /diagnostics (called from the diagnostics thread)."""
        return {}

    def report_status(self, level: str, message: str) -> None:
        """Set the level ("ok", "warn", "error") and message /diagnostics shows; ``report_status("ok", "")`` clears it."""
        self._status = None if level == "ok" and not message else (_LEVELS[level], message)

    def create_work_timer(self, period_sec: float, callback: Callable[[], None]) -> Any:
        """A timer whose calls are work transactions, run only while active; destroyed on cleanup.

        After a hand-over it continues the schedule of the node it replaced: its first call comes one
        period after that node's last call of the timer of the same name.
        """
        name = getattr(callback, "__name__", "timer")
        taken = sum(1 for t in self._work_timers if t.name == name or t.name.startswith(name + "#"))
        work = WorkTimer(name if not taken else f"{name}#{taken}", period_sec)
        run = self._work(callback, f"timer {name}")

        def tick() -> None:
            if run():
                with self._ticked:
                    work.last_ns = time.time_ns()
                    self._ticked.notify_all()
        work.tick = tick
        work.timer = self.create_timer(period_sec, tick, callback_group=self.main_group)
        self._work_timers.append(work)
        self._entities.append(("timer", work.timer))
        return work.timer

    def transaction(self) -> Any:
        """``with self.transaction():`` — a work transaction in user code (raises Paused while paused)."""
        return self.gate.transaction()

    def executor_threads(self) -> int:
        """Threads the executor needs so no group waits for another."""
        return 4 + 2 * self.ACTION_SERVERS + (1 if self.CLIENTS else 0)

    # ---- generated code fills these ----------------------------------------------------------------
    def _create_members(self) -> None:
        """Publishers, subscriptions, services, clients and actions (on configure)."""

    def _create_diagnostics(self) -> None:
        """The Δ services (at start)."""

    # ---- entities --------------------------------------------------------------------------------
    def _publisher(self, msg_type: Any, name: str, qos: dict[str, Any]) -> Any:
        pub = self.create_lifecycle_publisher(msg_type, name, qos_profile(qos))
        self._entities.append(("publisher", pub))
        return pub

    def _subscription(self, msg_type: Any, name: str, handler: str, qos: dict[str, Any]) -> None:
        callback = self._work(getattr(self, handler), f"{name} ({handler})")
        sub = self.create_subscription(msg_type, name, callback, qos_profile(qos), callback_group=self.main_group)
        self._entities.append(("subscription", sub))

    def _server(self, srv_type: Any, name: str, handler: str, qos: dict[str, Any]) -> None:
        srv = self.create_service(srv_type, name, self._serve(srv_type, getattr(self, handler), name, True),
                                  qos_profile=qos_profile(qos, qos_profile_services_default),
                                  callback_group=self.main_group)
        self._entities.append(("service", srv))

    def _diagnostics_server(self, srv_type: Any, name: str, handler: str, qos: dict[str, Any]) -> None:
        self.create_service(srv_type, name, self._serve(srv_type, getattr(self, handler), name, False),
                            qos_profile=qos_profile(qos, qos_profile_services_default),
                            callback_group=self.diagnostics_group)

    def _client(self, srv_type: Any, name: str, qos: dict[str, Any]) -> Any:
        client = self.create_client(srv_type, name, qos_profile=qos_profile(qos, qos_profile_services_default),
                                    callback_group=self.client_group)
        self._entities.append(("client", client))
        return client

    def _action_server(self, action_type: Any, name: str, execute: str, accept: str, cancel: str,
                       qos: dict[str, Any]) -> None:
        extra = {}
        if qos:
            services = qos_profile(qos, qos_profile_services_default)
            extra = {"goal_service_qos_profile": services, "result_service_qos_profile": services,
                     "cancel_service_qos_profile": services, "feedback_pub_qos_profile": qos_profile(qos)}
        run, accepts, cancels = getattr(self, execute), getattr(self, accept), getattr(self, cancel)

        def on_goal(goal: Any) -> GoalResponse:
            if not self.active or self.gate.paused:
                return GoalResponse.REJECT
            return GoalResponse.ACCEPT if accepts(goal) else GoalResponse.REJECT

        def on_cancel(goal_handle: Any) -> CancelResponse:
            return CancelResponse.ACCEPT if cancels(goal_handle) else CancelResponse.REJECT

        server = ActionServer(self, action_type, name, execute_callback=self._goal(action_type, run, name),
                              goal_callback=on_goal, cancel_callback=on_cancel, callback_group=self.action_group,
                              **extra)
        self._entities.append(("action", server))

    def _action_client(self, action_type: Any, name: str, qos: dict[str, Any]) -> Any:
        extra = {}
        if qos:
            services = qos_profile(qos, qos_profile_services_default)
            extra = {"goal_service_qos_profile": services, "result_service_qos_profile": services,
                     "cancel_service_qos_profile": services, "feedback_sub_qos_profile": qos_profile(qos)}
        client = LockedActionClient(self, action_type, name, callback_group=self.client_group, **extra)
        self._entities.append(("action", client))
        return client

    def _publish(self, publisher: Any, msg: Any) -> None:
        if publisher is None:
            raise RuntimeError("the node is not configured: publishers exist from configure to cleanup")
        publisher.publish(msg)

    def _call(self, client: Any, request: Any, timeout_sec: float) -> Any:
        if client is None:
            raise RuntimeError("the node is not configured: clients exist from configure to cleanup")
        if not client.wait_for_service(timeout_sec=timeout_sec):
            raise TimeoutError(f"{client.srv_name} is not available after {timeout_sec:g} s")
        return self._wait(client.call_async(request), timeout_sec, client.srv_name)

    def _send_goal(self, client: Any, goal: Any, feedback: Callable[[Any], None] | None,
                   timeout_sec: float) -> Any:
        if client is None:
            raise RuntimeError("the node is not configured: action clients exist from configure to cleanup")
        if not client.wait_for_server(timeout_sec=timeout_sec):
            raise TimeoutError(f"the action server is not available after {timeout_sec:g} s")
        handle = self._wait(client.send_goal_async(goal, feedback_callback=feedback), timeout_sec, "the goal")
        if not handle.accepted:
            raise RuntimeError("the goal was rejected")
        return self._wait(handle.get_result_async(), timeout_sec, "the result")

    @staticmethod
    def _wait(future: Any, timeout_sec: float, what: str) -> Any:
        done = threading.Event()
        future.add_done_callback(lambda _: done.set())
        if not done.wait(timeout_sec):
            future.cancel()
            raise TimeoutError(f"no answer from {what} within {timeout_sec:g} s")
        return future.result()

    def _destroy_members(self) -> None:
        for kind, entity in reversed(self._entities):
            try:
                if kind == "publisher":
                    self.destroy_lifecycle_publisher(entity)
                elif kind == "subscription":
                    self.destroy_subscription(entity)
                elif kind == "service":
                    self.destroy_service(entity)
                elif kind == "client":
                    self.destroy_client(entity)
                elif kind == "timer":
                    self.destroy_timer(entity)
                else:
                    entity.destroy()
            except Exception as e:  # noqa: BLE001 - destroy the others anyway
                self.get_logger().warning(f"destroying a {kind}: {e}")
        self._entities = []
        self._work_timers = []
        self._forget_members()

    def _forget_members(self) -> None:
        """Reset the generated attributes that hold members (generated)."""

    # ---- work transactions -------------------------------------------------------------------------
    def _failed(self, what: str, error: BaseException) -> None:
        with self._lock:
            self._counts["errors"] += 1
            self._error_seen = True
            self._last_error = f"{what}: {type(error).__name__}: {error}"
        self.get_logger().error(f"{self._last_error}\n{traceback.format_exc()}")

    def _work(self, handler: Callable[..., Any], what: str) -> Callable[..., bool]:
        def callback(*args: Any) -> bool:
            if not self.active:
                with self._lock:
                    self._counts["dropped_inactive"] += 1
                return False
            if not self.gate.enter():
                return False
            try:
                handler(*args)
            except Exception as e:  # noqa: BLE001 - one failed call must not stop the node
                self._failed(what, e)
            finally:
                self.gate.leave()
            return True
        return callback

    def _serve(self, srv_type: Any, handler: Callable[..., Any], name: str, work: bool) -> Callable[..., Any]:
        def callback(request: Any, response: Any) -> Any:
            if work and not self.active:
                self.get_logger().warning(f"{name}: called while {self._lifecycle_label()}: default response",
                                          throttle_duration_sec=5.0)
                return response
            if work and not self.gate.enter():
                why = "paused" if self.gate.paused else "its members are destroyed"
                self.get_logger().warning(f"{name}: called while {why}: default response", throttle_duration_sec=5.0)
                return response
            try:
                answer = handler(request, response)
                return response if answer is None else answer
            except Exception as e:  # noqa: BLE001
                self._failed(name, e)
                return srv_type.Response()
            finally:
                if work:
                    self.gate.leave()
        return callback

    def _goal(self, action_type: Any, handler: Callable[..., Any], name: str) -> Callable[..., Any]:
        def execute(goal_handle: Any) -> Any:
            if not self.gate.enter():
                goal_handle.abort()
                return action_type.Result()
            try:
                result = handler(goal_handle)
                if goal_handle.is_active:
                    if goal_handle.is_cancel_requested:
                        goal_handle.canceled()
                    else:
                        goal_handle.succeed()
                return action_type.Result() if result is None else result
            except Exception as e:  # noqa: BLE001
                self._failed(name, e)
                if goal_handle.is_active:
                    goal_handle.abort()
                return action_type.Result()
            finally:
                self.gate.leave()
        return execute

    # ---- lifecycle -------------------------------------------------------------------------------
    def _lifecycle_label(self) -> str:
        return str(self._state_machine.current_state[1])

    def on_configure(self, state: LifecycleState) -> TransitionCallbackReturn:
        missing = [s.name for s in self.PARAMETERS if self.get_parameter(s.name).type_ == Parameter.Type.NOT_SET]
        if missing:
            self.get_logger().error(f"cannot configure: no value for {', '.join(missing)} (set it in the "
                                    "parameter file or with --ros-args -p NAME:=VALUE)")
            return TransitionCallbackReturn.FAILURE
        self.gate.open()
        try:
            self._create_members()
            self.setup()
        except Exception as e:  # noqa: BLE001
            self._failed("configure", e)
            self._destroy_members()
            return TransitionCallbackReturn.FAILURE
        return super().on_configure(state)

    def on_activate(self, state: LifecycleState) -> TransitionCallbackReturn:
        result = super().on_activate(state)
        if result != TransitionCallbackReturn.SUCCESS:
            return result
        self.active = True
        self._continue_schedule()
        try:
            self.on_active()
        except Exception as e:  # noqa: BLE001
            self.active = False
            self._failed("activate", e)
            return TransitionCallbackReturn.FAILURE
        return result

    def on_deactivate(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.active = False
        try:
            self.on_inactive()
        except Exception as e:  # noqa: BLE001
            self._failed("deactivate", e)
        return super().on_deactivate(state)

    def on_cleanup(self, state: LifecycleState) -> TransitionCallbackReturn:
        self._end()
        return super().on_cleanup(state)

    def on_shutdown(self, state: LifecycleState) -> TransitionCallbackReturn:
        if self.active:
            self.active = False
            try:
                self.on_inactive()
            except Exception as e:  # noqa: BLE001
                self._failed("shutdown", e)
        self._end()
        self.finalized.set()
        executor = self.executor
        if executor is not None:
            executor.wake()  # ``main`` waits for work without a timeout: it looks at ``finalized`` now
        return super().on_shutdown(state)

    def on_error(self, state: LifecycleState) -> TransitionCallbackReturn:
        self.active = False
        self._end()
        return super().on_error(state)

    def _until_main_group_idle(self, timeout: float) -> tuple[bool, str]:
        """Wait (at most ``timeout`` s) until no callback of the main group runs: rclpy sends a service's answer
        after its callback returned, and so after the callback left the gate; a service destroyed meanwhile
        never answers ("cannot use Destroyable because destruction was requested")."""
        member = next((m for m in (ref() for ref in list(self.main_group.entities)) if m is not None), None)
        if member is None:
            return True, "closed"
        end = time.monotonic() + timeout
        while not self.main_group.can_execute(member):  # mutually exclusive: true when none of its callbacks runs
            if time.monotonic() > end:
                return False, f"a callback of the main group still running after {timeout:g} s"
            time.sleep(0.002)
        return True, "closed"

    def _end(self) -> None:
        # no work transaction runs on a member being destroyed (a tick that a signal's shutdown overtook)
        closed, why = self.gate.close(CLOSE_TIMEOUT_SEC)
        if closed:
            closed, why = self._until_main_group_idle(CLOSE_TIMEOUT_SEC)
        if not closed:
            self.get_logger().warning(f"members destroyed while {why}")
        if self._entities:
            try:
                self.teardown()
            except Exception as e:  # noqa: BLE001
                self._failed("teardown", e)
        self._destroy_members()

    # ---- parameters ------------------------------------------------------------------------------
    def _check_parameters(self, params: list[Parameter]) -> SetParametersResult:
        for p in params:
            spec = self._param_specs.get(p.name)
            if spec is None or p.type_ == Parameter.Type.NOT_SET:
                continue
            problem = spec.problem(p.value)
            if problem:
                return SetParametersResult(successful=False, reason=problem)
        return SetParametersResult(successful=True)

    def _parameter(self, name: str) -> Any:
        return self.get_parameter(name).value

    # ---- Σ and control ---------------------------------------------------------------------------
    @staticmethod
    def _timeout(request: Any) -> float:
        return request.timeout_sec if request.timeout_sec > 0 else DEFAULT_TIMEOUT_SEC

    def save_state(self, timeout_sec: float = DEFAULT_TIMEOUT_SEC) -> str:
        """The state document, taken between work transactions (TimeoutError when none ends in time)."""
        with self.gate.quiet(timeout_sec):
            return self.codec.save(self.state, {t.name: t.last_ns for t in self._work_timers if t.last_ns})

    def restore_state(self, document: str, timeout_sec: float = DEFAULT_TIMEOUT_SEC) -> Any:
        """Restore a state document between work transactions (StateError when refused)."""
        with self.gate.quiet(timeout_sec):
            report = self.codec.restore(self.state, document)
            self._schedule = dict(report.schedule)
        self.state_restored()
        return report

    def _await_tick(self, timeout: float) -> None:
        """Before a pause: let the next tick of a fast work timer run first (due within ``ALIGN_SEC``).

        A hand-over's silence on a timer's topic runs from OLD's last tick to NEW's first; pausing
        right after a tick leaves only the critical section in it, not also the part of a period
        that had gone by when the pause came.
        """
        if not self.active or self.gate.paused:
            return
        due: list[tuple[float, WorkTimer]] = []
        for work in self._work_timers:
            left = None if work.timer is None or work.timer.is_canceled() else work.timer.time_until_next_call()
            if left is not None:
                due.append((max(0.0, left / 1e9), work))
        if not due:
            return
        wait, work = min(due, key=lambda d: d[0])
        if wait > min(ALIGN_SEC, timeout):
            return
        with self._ticked:
            last = work.last_ns
            self._ticked.wait_for(lambda: work.last_ns != last, wait + min(work.period_sec, ALIGN_SEC))

    def _continue_schedule(self) -> None:
        """On activation after a restore: each work timer's next call one period after the saver's last one."""
        schedule, self._schedule = self._schedule, {}
        now = time.time_ns()
        for work in self._work_timers:
            last = schedule.get(work.name)
            if last is None or work.timer is None:
                continue
            delay = max(0.001, (last - now) / 1e9 + work.period_sec)
            work.timer.cancel()
            holder: list[Any] = []

            def first(work: WorkTimer = work, holder: list[Any] = holder) -> None:
                holder[0].cancel()  # once; destroyed with the other timers on cleanup
                work.timer.reset()
                work.tick()
            holder.append(self.create_timer(delay, first, callback_group=self.main_group))
            self._entities.append(("timer", holder[0]))

    def _on_save_state(self, request: Any, response: Any) -> Any:
        response.interface_hash = self.INTERFACE_HASH
        try:
            response.state = self.save_state(self._timeout(request))
        except TimeoutError as e:
            response.success, response.message = False, f"not saved: {e}"
            return response
        response.success = True
        response.message = f"saved {len(self.STATE_SCHEMA)} state variable(s) of {self.COMPONENT} {self.VERSION}"
        return response

    def _on_restore_state(self, request: Any, response: Any) -> Any:
        response.interface_hash = self.INTERFACE_HASH
        try:
            report = self.restore_state(request.state, self._timeout(request))
        except (StateError, TimeoutError) as e:
            response.success, response.message = False, f"refused: {e}"
            self.get_logger().warning(f"restore refused: {e}")
            return response
        response.success, response.message = True, report.message
        response.restored, response.kept = report.restored, report.kept
        self.get_logger().info(report.message)
        return response

    def _on_control(self, request: Any, response: Any) -> Any:
        timeout = self._timeout(request)
        ok, message = True, ""
        if request.command == PAUSE:
            self._await_tick(timeout)
            ok, message = self.gate.pause(timeout)
            if ok:  # the state at the pause, so that a hand-over needs no second round trip for it
                response.state = self.save_state(timeout)
        elif request.command == RESUME:
            ok, message = self.gate.resume()
        elif request.command == SAVE:
            try:
                response.state = self.save_state(timeout)
                message = "saved"
            except TimeoutError as e:
                ok, message = False, f"not saved: {e}"
        elif request.command != STATUS:
            ok, message = False, f"unknown command {request.command} (STATUS 0, PAUSE 1, RESUME 2, SAVE 3)"
        state_id, label = self._state_machine.current_state
        response.success, response.message = ok, message or f"{label}{', paused' if self.gate.paused else ''}"
        response.paused = self.gate.paused
        response.lifecycle_state = int(state_id)
        response.in_flight = max(0, self.gate.in_flight)
        response.transactions = self.gate.transactions
        response.component, response.version = self.COMPONENT, self.VERSION
        response.interface_hash = self.INTERFACE_HASH
        response.protocol_version, response.pid = PROTOCOL_VERSION, os.getpid()
        response.publisher_topics, response.publisher_matched = self._matched()
        return response

    def _matched(self) -> tuple[list[str], list[int]]:
        """Each publisher's topic and how many subscriptions it has matched (a hand-over waits for NEW's)."""
        topics: list[str] = []
        matched: list[int] = []
        for kind, entity in list(self._entities):
            if kind != "publisher":
                continue
            try:
                count = entity.get_subscription_count()
            except Exception:  # noqa: BLE001, S112 - destroyed by a cleanup meanwhile
                continue
            topics.append(entity.topic_name)
            matched.append(count)
        return topics, matched

    def _on_describe(self, request: Any, response: Any) -> Any:
        response.node_name = self.get_fully_qualified_name()
        response.component, response.version = self.COMPONENT, self.VERSION
        response.interface_hash = self.INTERFACE_HASH
        response.runtime, response.runtime_version = RUNTIME, RUNTIME_VERSION
        response.protocol_version = PROTOCOL_VERSION
        response.interface_json = interface_json(self.PACKAGE, self.INTERFACE_FILE, self.INTERFACE_JSON)
        return response

    # ---- Δ ---------------------------------------------------------------------------------------
    def _publish_diagnostics(self) -> None:
        label = self._lifecycle_label()
        with self._lock:
            counts = dict(self._counts)
            error_seen, self._error_seen = self._error_seen, False
            last_error = self._last_error
        if self._status is not None:
            level, message = self._status
        elif error_seen:
            level, message = DiagnosticStatus.ERROR, last_error
        elif self.gate.paused:
            level, message = DiagnosticStatus.WARN, "paused"
        elif label != "active":
            level, message = DiagnosticStatus.WARN, label
        else:
            level, message = DiagnosticStatus.OK, "active"
        values = {"lifecycle_state": label, "paused": self.gate.paused, "in_flight": self.gate.in_flight,
                  "transactions": self.gate.transactions, "refused_while_paused": self.gate.refused,
                  "dropped_while_inactive": counts["dropped_inactive"], "errors": counts["errors"],
                  "component": self.COMPONENT, "version": self.VERSION, "interface_hash": self.INTERFACE_HASH}
        if self.state is not None:
            for name in self.STATE_SCHEMA:
                try:
                    values[f"state.{name}"] = json.dumps(self.codec.save_value(self.state, name))[:200]
                except Exception:  # noqa: BLE001, S110 - being changed right now
                    pass
        try:
            values.update(self.diagnostic_values())
        except Exception as e:  # noqa: BLE001
            values["diagnostic_values"] = f"{type(e).__name__}: {e}"
        status = DiagnosticStatus(level=level, name=self.get_fully_qualified_name(), hardware_id=self.COMPONENT,
                                  message=message[:500],
                                  values=[KeyValue(key=str(k), value=str(v)) for k, v in values.items()])
        array = DiagnosticArray(status=[status])
        array.header.stamp = self.get_clock().now().to_msg()
        self._diagnostics_pub.publish(array)


# ---- starting a component ---------------------------------------------------------------------------


def default_params_file(package: str, file_name: str) -> str | None:
    """The parameter file installed with the package (``share/<package>/config/``), if any."""
    try:
        from ament_index_python.packages import get_package_share_directory

        path = os.path.join(get_package_share_directory(package), "config", file_name)
    except Exception:  # noqa: BLE001 - not installed through ament
        return None
    return path if os.path.isfile(path) else None


@contextmanager
def _quiet_exit() -> Iterator[None]:
    try:
        yield
    except (KeyboardInterrupt, ExternalShutdownException):
        pass


#: The node a standby holds until it is told: its DDS participant up and discovered before the component needs it.
STANDBY_NODE = "_iface_standby_"
#: Seconds between a standby's looks at its parent (it ends with the process that started it).
STANDBY_LOOK = 0.2
#: The environment variable that names the process a standby ends with (the manager sets it to its own pid, so
#: that one that ended while the standby was still importing is seen too); without it, the parent at start.
STANDBY_PARENT = "IFACE_STANDBY_PARENT"


def _standby_parent() -> int:
    """The process whose end ends a standby."""
    given = os.environ.get(STANDBY_PARENT, "").strip()
    return int(given) if given.isdigit() else os.getppid()


def _standby_signal() -> set[signal.Signals]:
    """SIGUSR1, the standby's order to become the component: blocked before ROS starts its threads, so every
    thread leaves it pending for ``sigtimedwait`` in the main thread, which takes it at once.

    Then a handler that does nothing: the manager tells a standby only once it has one (``SigCgt``), and a
    second SIGUSR1 after the first ends nothing."""
    told = {signal.SIGUSR1}
    signal.pthread_sigmask(signal.SIG_BLOCK, told)
    signal.signal(signal.SIGUSR1, lambda _signum, _frame: None)
    return told


def _standby_node() -> Node:
    """A hidden node with no endpoints, made only for the participant that comes with it.

    It takes no global ROS arguments, so ``__node:=`` and parameter files remap the component's node only,
    and it has no rosout, parameter or type description endpoints for discovery to carry.
    """
    return rclpy.create_node(f"{STANDBY_NODE}{os.getpid()}", use_global_arguments=False, enable_rosout=False,
                             start_parameter_services=False,
                             parameter_overrides=[Parameter("start_type_description_service", value=False)])


def _until_told(told: set[signal.Signals], parent: int) -> bool:
    """Wait for SIGUSR1; False when ROS shuts down (SIGINT, SIGTERM) or the process ``parent`` is no longer this
    one's parent (it ended first)."""
    while signal.sigtimedwait(told, STANDBY_LOOK) is None:
        if not rclpy.ok() or os.getppid() != parent:
            return False
    return True


def main(load: Callable[[], type[ComponentNode]], package: str, params_file_name: str,
         argv: list[str] | None = None) -> int:
    """Start the component: its default parameter file, then the command line's ROS arguments."""
    argv = list(sys.argv if argv is None else argv)
    own = rclpy.utilities.remove_ros_args(argv)[1:]
    parser = argparse.ArgumentParser(prog=f"python -m {package}",
                                     description=f"Start the {package} lifecycle node (ROS arguments after "
                                                 "--ros-args).")
    parser.add_argument("--activate", action="store_true", help="configure and activate at start")
    parser.add_argument("--no-default-params", action="store_true",
                        help=f"do not load the installed config/{params_file_name}")
    parser.add_argument("--standby", action="store_true",
                        help="a spare for a fast restart: start ROS and wait; make the node on SIGUSR1, end when "
                             "the process that started it ends first (the component manager's standby)")
    opts = parser.parse_args(own)
    try:
        cls = load()
    except Exception as e:  # noqa: BLE001 - one line, not a traceback
        print(f"{package}: cannot load the component's code: {type(e).__name__}: {e}", file=sys.stderr)
        return 2
    problems = cls.interface_problems()
    if problems:
        print(f"{package}: the code does not match the interface ({cls.SOURCE}, {cls.INTERFACE_HASH}):",
              file=sys.stderr)
        for p in problems:
            print(f"  {p}", file=sys.stderr)
        return 2
    params = None if opts.no_default_params else default_params_file(package, params_file_name)
    ros_argv = [argv[0], *(["--ros-args", "--params-file", params, "--"] if params else []), *argv[1:]]
    parent = _standby_parent()
    told = _standby_signal() if opts.standby else None
    rclpy.init(args=ros_argv)
    node: ComponentNode | None = None
    executor: ComponentExecutor | None = None
    try:
        with _quiet_exit():
            spare = None
            if told is not None:
                spare = _standby_node()
                if not _until_told(told, parent):
                    return 0
            node = cls()
            if spare is not None:
                spare.destroy_node()  # after the component's node: the participant stays up between the two
            node.get_logger().info(f"parameter file: {params}" if params else "parameter file: none installed")
            executor = ComponentExecutor(num_threads=node.executor_threads())
            executor.add_node(node)
            if opts.activate:
                node.trigger_configure()
                node.trigger_activate()
            # no timeout: an idle node sleeps until work comes (its timers, a message, a request), the shutdown
            # transition wakes it (``on_shutdown``), and so does SIGINT (rclpy's handler)
            while rclpy.ok() and not node.finalized.is_set():
                executor.spin_once()
            end = time.monotonic() + 0.5  # let the answer to the shutdown transition go out
            while rclpy.ok() and time.monotonic() < end:
                executor.spin_once(timeout_sec=0.05)
    finally:
        if executor is not None:
            executor.shutdown(timeout_sec=2.0)
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0
