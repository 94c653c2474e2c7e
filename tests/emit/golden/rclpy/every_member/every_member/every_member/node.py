# Written once by iface from every_member.iface: this file is yours to edit. `iface-lsp generate`
# never overwrites it, not even with --force. When the interface changes, base.py is regenerated and
# the node refuses to start (as `iface-lsp generate --check` does) until the handlers below match
# it.
"""The behaviour of the every_member component: what it does with its members."""

from __future__ import annotations

from typing import Any

from every_member_msgs.action import Travel
from every_member_msgs.msg import Command, Heartbeat
from every_member_msgs.srv import Count, Diagnostics, LimitsGetLimit, LimitsReset, Work

from .base import EveryMemberBase


class EveryMember(EveryMemberBase):
    """every_member: keep self.state current (what ~/save_state saves and a replacement
    restores).
    """

    def setup(self) -> None:
        """On configure, once the members exist: e.g. self.create_work_timer(0.1, self.tick)."""

    def on_command(self, msg: Command) -> None:
        """subscribes Command on /station/command."""

    def on_heartbeat(self, msg: Heartbeat) -> None:
        """subscribes Heartbeat on heartbeat."""

    def handle_work(self, request: Work.Request, response: Work.Response) -> Work.Response:
        """provides Work on /station/work."""
        return response

    def handle_count(self, request: Count.Request, response: Count.Response) -> Count.Response:
        """provides Count on ~/count."""
        return response

    def handle_get_limit(
        self,
        request: LimitsGetLimit.Request,
        response: LimitsGetLimit.Response
    ) -> LimitsGetLimit.Response:
        """provides Limits.get_limit on /station/limits/get_limit."""
        return response

    def handle_reset(
        self,
        request: LimitsReset.Request,
        response: LimitsReset.Response
    ) -> LimitsReset.Response:
        """provides Limits.reset on /station/limits/reset."""
        return response

    def execute_travel(self, goal_handle: Any) -> Travel.Result:
        """provides Travel on /station/travel: goal_handle.request is the goal."""
        return Travel.Result()

    def handle_diagnostics(
        self,
        request: Diagnostics.Request,
        response: Diagnostics.Response
    ) -> Diagnostics.Response:
        """diagnostics diagnostics on ~/diagnostics."""
        return response
