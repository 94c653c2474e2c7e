# The user module of examples/counter_v2.iface for the hand-over tests (replaces the node.py iface writes once).
"""counter 2.0's behaviour: as 1.0, and the parity of each count."""

from __future__ import annotations

from counter_msgs.msg import Count, Parity
from counter_msgs.srv import Reset

from .base import CounterBase


class Counter(CounterBase):
    """Counts ticks in its state, publishes each count and, if asked, its parity."""

    def setup(self) -> None:
        self.create_work_timer(1.0 / self.params.rate_hz, self.tick)

    def tick(self) -> None:
        self.state.count += 1
        self.publish_count(Count(value=self.state.count))
        if self.params.publish_parity:
            self.publish_parity(Parity(even=self.state.count % 2 == 0))

    def handle_reset(self, request: Reset.Request, response: Reset.Response) -> Reset.Response:
        self.state.count = 0
        response.done = True
        return response
