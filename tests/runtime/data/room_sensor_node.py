# The user module of examples/room_sensor.iface for the manager tests (replaces the node.py iface writes once).
"""room_sensor's behaviour: publishes a temperature at its rate and counts its readings (its state).

For the tests: when ``$IFACE_TEST_FLAGS/<node name>.crash`` exists, the process dies on activate.
"""

from __future__ import annotations

import os

from room_sensor_msgs.msg import Temperature

from .base import RoomSensorBase


class RoomSensor(RoomSensorBase):
    """A steady 19.5 degC."""

    def setup(self) -> None:
        self.create_work_timer(1.0 / self.params.rate_hz, self.tick)

    def on_active(self) -> None:
        flags = os.environ.get("IFACE_TEST_FLAGS", "")
        if flags and os.path.exists(os.path.join(flags, f"{self.get_name()}.crash")):
            os._exit(3)

    def tick(self) -> None:
        self.state.readings += 1
        self.publish_temperature(Temperature(celsius=19.5))
