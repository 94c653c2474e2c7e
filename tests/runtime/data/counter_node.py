# The user module of examples/counter.iface for the hand-over tests (replaces the node.py iface writes once).
"""counter 1.0's behaviour: a work timer advances the count and publishes it."""

from __future__ import annotations

from counter_msgs.msg import Count
from counter_msgs.srv import Reset

from .base import CounterBase


class Counter(CounterBase):
    """Counts ticks in its state (what a replacement continues from) and publishes each count."""

    def setup(self) -> None:
        self.create_work_timer(1.0 / self.params.rate_hz, self.tick)

    def tick(self) -> None:
        self.state.count += 1
        self.publish_count(Count(value=self.state.count))

    def handle_reset(self, request: Reset.Request, response: Reset.Response) -> Reset.Response:
        self.state.count = 0
        response.done = True
        return response
