# Written once by iface from listing1.iface: this file is yours to edit. `iface-lsp generate` never
# overwrites it, not even with --force. When the interface changes, base.py is regenerated and the
# node refuses to start (as `iface-lsp generate --check` does) until the handlers below match it.
"""The behaviour of the listing1 component: what it does with its members."""

from __future__ import annotations

from typing import Any

from listing1.action import Action1, Action2
from listing1.srv import Diagnostics, Service1, Service2

from .base import Listing1Base


class Listing1(Listing1Base):
    """listing1: keep self.state current (what ~/save_state saves and a replacement restores)."""

    def setup(self) -> None:
        """On configure, once the members exist: e.g. self.create_work_timer(0.1, self.tick)."""

    def handle_service1(
        self,
        request: Service1.Request,
        response: Service1.Response
    ) -> Service1.Response:
        """provides Service1 on Service1."""
        return response

    def handle_service2(
        self,
        request: Service2.Request,
        response: Service2.Response
    ) -> Service2.Response:
        """provides Service2 on Service2."""
        return response

    def execute_action1(self, goal_handle: Any) -> Action1.Result:
        """provides Action1 on Action1: goal_handle.request is the goal."""
        return Action1.Result()

    def execute_action2(self, goal_handle: Any) -> Action2.Result:
        """provides Action2 on Action2: goal_handle.request is the goal."""
        return Action2.Result()

    def handle_diagnostics(
        self,
        request: Diagnostics.Request,
        response: Diagnostics.Response
    ) -> Diagnostics.Response:
        """diagnostics diagnostics on ~/diagnostics."""
        return response
