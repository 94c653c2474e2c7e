"""When the manager restarts a failed instance: its policy, and the intensity limit (as OTP's supervisors).

An instance's ``restart`` annotation says whether it is restarted at all: ``never``, ``on-failure``
(the default: after a crash or a missed heartbeat, not after it finished cleanly) or ``always``.
The intensity limit caps how often: at most ``max_restarts`` restarts within any ``period``
seconds (OTP's intensity and period). Past it the instance stays down and is reported.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

POLICIES = ("never", "on-failure", "always")
DEFAULT_POLICY = "on-failure"
#: At most this many restarts of one instance ...
DEFAULT_MAX_RESTARTS = 3
#: ... within this many seconds.
DEFAULT_PERIOD = 60.0


def should_restart(policy: str, failed: bool) -> bool:
    """Whether an instance that stopped (``failed``: crashed or silent, not a clean exit) is restarted."""
    if policy == "always":
        return True
    if policy == "on-failure":
        return failed
    return False


@dataclass
class Intensity:
    """At most ``max_restarts`` restarts within ``period`` seconds; remembers when each was."""

    max_restarts: int = DEFAULT_MAX_RESTARTS
    period: float = DEFAULT_PERIOD
    times: deque[float] = field(default_factory=deque)

    def allow(self, now: float) -> bool:
        """Whether one more restart at ``now`` stays within the limit (if so, it is counted)."""
        while self.times and now - self.times[0] >= self.period:
            self.times.popleft()
        if len(self.times) >= self.max_restarts:
            return False
        self.times.append(now)
        return True
