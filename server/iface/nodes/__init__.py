"""Generated nodes: what a component becomes as a ROS 2 node, the protocol it speaks, the targets that write it.

- ``protocol``: the runtime-facing definitions every generated node shares, whatever its
  language: the node-relative names of the save/restore/control services, their ``.srv``
  definitions (the ``iface_msgs`` package), the state document's format, the control commands.
- ``component``: a compiled interface seen as a node: its members with ROS types, QoS and the
  names of the handlers the user writes, its parameters with their checks, its state schema.
- ``usercode``: reads a user module (without running it) and says where it no longer matches
  the interface.
- ``nodepkg``, ``template_data``, ``qosmap``, ``keywords``, ``codes``: what both node targets share;
  ``shared``: the packages every component of an output folder shares (``iface_msgs`` and the runtimes).
- ``rclpy``, ``rclcpp``: the node targets (a lifecycle-node package in Python, in C++).
- ``system``: a system file as the manager and the launch target read it (``system_spec``: the
  instances in start order, each with its package, executable, node, restart policy, snapshot
  period and interface hash).
- ``launch``: the ``launch`` generation target (one ROS 2 launch file for a system file).
- ``remap``: remapping rules that hold on every ROS 2 release (an action's by its five ``_action/`` names).

Nothing here reads or runs a live system (that is ``live`` and ``operate``).

May import: ``model``, ``syntax``, ``semantics``, ``text``, ``forms``, ``emit``, ``compat``.
"""
