# The user module of tests/runtime/data/thermostat_pro.iface for the manager tests (replaces the node.py iface writes once).
"""thermostat_pro's behaviour: holds a set point (its state), boosts far below it, tells the heater at 10 Hz.

For the tests: when ``$IFACE_TEST_FLAGS/<node name>.crash`` exists, the process dies on activate.
"""

from __future__ import annotations

import os

from room_sensor_msgs.msg import Temperature
from thermostat_msgs.msg import Heater
from thermostat_msgs.srv import SetPoint

from .base import ThermostatProBase


class ThermostatPro(ThermostatProBase):
    """Switches the heater on below the set point minus the hysteresis; counts a boost far below it."""

    def setup(self) -> None:
        self.heating = False
        self.create_work_timer(0.1, self.tick)

    def on_active(self) -> None:
        flags = os.environ.get("IFACE_TEST_FLAGS", "")
        if flags and os.path.exists(os.path.join(flags, f"{self.get_name()}.crash")):
            os._exit(3)

    def tick(self) -> None:
        self.publish_heater(Heater(on=self.heating, set_point=self.state.set_point))

    def on_temperature(self, msg: Temperature) -> None:
        heating = msg.celsius < self.state.set_point - self.params.hysteresis
        if msg.celsius < self.state.set_point - self.params.boost_below:
            self.state.boosts += 1
        if heating != self.heating:
            self.heating = heating
            self.state.switches += 1

    def handle_set_point(self, request: SetPoint.Request, response: SetPoint.Response) -> SetPoint.Response:
        self.state.set_point = request.celsius
        response.accepted = True
        return response
