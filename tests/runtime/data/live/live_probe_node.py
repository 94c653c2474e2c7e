# Written once by iface from live_probe.iface: this file is yours to edit. `iface-lsp generate` never
# overwrites it, not even with --force. When the interface changes, base.py is regenerated and the
# node refuses to start (as `iface-lsp generate --check` does) until the handlers below match it.
"""The behaviour of the live_probe component: what it does with its members."""

from __future__ import annotations

from typing import Any

from live_probe_msgs.action import Seek
from live_probe_msgs.msg import Reading
from live_probe_msgs.srv import Health, Reset

from .base import LiveProbeBase


class LiveProbe(LiveProbeBase):
    """live_probe: keep self.state current; it is what ~/save_state saves and a replacement restores."""

    def setup(self) -> None:
        """Called on configure, once the members exist (e.g. self.create_work_timer(0.1, self.tick))."""

    def on_input(self, msg: Reading) -> None:
        """subscribes Reading on /probe/input."""

    def handle_reset(self, request: Reset.Request, response: Reset.Response) -> Reset.Response:
        """provides Reset on /probe/reset."""
        return response

    def execute_seek(self, goal_handle: Any) -> Seek.Result:
        """provides Seek on /probe/seek: goal_handle.request is the goal."""
        return Seek.Result()

    def handle_diagnostics(self, request: Health.Request, response: Health.Response) -> Health.Response:
        """diagnostics Health on ~/diagnostics."""
        return response
