# The user module of every_member for the end-to-end tests: it replaces the node.py that iface
# writes once, as a developer would, and must survive regeneration.
"""every_member's behaviour: a counter in its state, a long service, clients of a peer."""

from __future__ import annotations

import time
from typing import Any

from every_member_msgs.action import Travel
from every_member_msgs.msg import Command, Event, Heartbeat, Sample, Waypoint
from every_member_msgs.srv import Count, Diagnostics, LimitsGetLimit, LimitsReset, Work

from .base import EveryMemberBase


class EveryMember(EveryMemberBase):
    """Counts commands; relays to a peer on negative steps."""

    NOT_HANDLERS = ("on_tick",)

    def setup(self) -> None:
        self.beats = 0
        self.ticks = 0
        self.create_work_timer(0.2, self.on_tick)

    def on_tick(self) -> None:
        self.ticks += 1
        self.publish_sample(Sample(seq=self.ticks, value=self.params.gain, label=self.params.label,
                                   mode=self.state.mode))

    def on_command(self, msg: Command) -> None:
        if msg.reset:
            self.state.counter = 0
        elif msg.step < 0:
            answer = self.call_count(Count.Request(add=-msg.step), timeout_sec=5.0)
            self.state.last_label = f"peer:{answer.counter}"
            goal = Travel.Goal(waypoints=[Waypoint(x=1.0, y=2.0, name="a"), Waypoint(x=3.0, y=4.0, name="b")])
            result = self.send_travel_goal(goal, timeout_sec=10.0)
            self.publish_events(Event(text=f"peer travel visited {result.result.visited}"))
        else:
            self.state.counter += msg.step
            self.state.history = list(self.state.history)[-9:] + [msg.step]
            self.state.position = [float(self.state.counter), 0.5, -1.0]
            self.state.flags = bytes([msg.step % 256])
        self.state.mode = Sample.MODE_RUNNING
        self.publish_events(Event(text=f"counter {self.state.counter}"))

    def on_heartbeat(self, msg: Heartbeat) -> None:
        self.beats += 1

    def handle_work(self, request: Work.Request, response: Work.Response) -> Work.Response:
        self.state.busy = True
        time.sleep(request.seconds)
        self.state.busy = False
        response.done = True
        response.counter = self.state.counter
        return response

    def handle_count(self, request: Count.Request, response: Count.Response) -> Count.Response:
        self.state.counter += request.add
        response.counter = self.state.counter
        return response

    def handle_get_limit(self, request: LimitsGetLimit.Request, response: LimitsGetLimit.Response) -> Any:
        response.result = len(request.name) * self.params.retries
        return response

    def handle_reset(self, request: LimitsReset.Request, response: LimitsReset.Response) -> LimitsReset.Response:
        self.state.counter = 0
        return response

    def execute_travel(self, goal_handle: Any) -> Travel.Result:
        visited = 0
        for i, waypoint in enumerate(goal_handle.request.waypoints):
            self.state.target = waypoint
            goal_handle.publish_feedback(Travel.Feedback(index=i))
            visited += 1
            time.sleep(0.05)
        return Travel.Result(reached=True, visited=visited)

    def handle_diagnostics(self, request: Diagnostics.Request, response: Diagnostics.Response) -> Any:
        response.summary = f"level {request.level}, {'busy' if self.state.busy else 'idle'}"
        response.counter = self.state.counter
        return response
