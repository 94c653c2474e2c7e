"""The ROS 2 test harness: what the ROS tests and the benches use to build and run generated components.

- ``ros``: the ROS 2 runtime (the venv of ``../shared/ros2-runtime``), the environment of a process
  (sourced workspaces, loopback only, a ROS domain of its own), ``generate`` and ``build``
  (interface and shared packages built once per content, as underlays), ``run_bounded``.
- ``systems``: the component manager's test system (room sensor, thermostat, counter, replacements).
- ``probe``: what every driver shares (needs rclpy: imported inside the ROS environment only):
  ``Report``, ``Component`` (a process stopped by its own handle), ``Probe`` (the driver's own node,
  every wait bounded), ``Protocol`` (the component protocol's calls).
- ``drive_*.py``: the drivers, each a script run with the ROS runtime's Python that plays one
  scenario and writes each step's outcome: ``drive_nodes`` (generated rclpy components),
  ``drive_rclcpp`` (a C++ component), ``drive_container`` (C++ components in one container),
  ``drive_handover``, ``drive_manager``, ``drive_qos``.
"""
