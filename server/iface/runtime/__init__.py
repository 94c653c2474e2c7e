"""Running components: what a generated node is made of, and the protocol it speaks.

- ``protocol``: the runtime-facing definitions every generated node shares, whatever its
  language: the node-relative names of the save/restore/control services, their ``.srv``
  definitions (written into the interface package), the state document's format, the control
  commands. The hand-over (issue 14) and nodes in other languages use them unchanged.
- ``component``: a compiled interface seen as a node: its members with ROS types, QoS and the
  names of the handlers the user writes, its parameters with their checks, its state schema.
- ``usercode``: reads a user module (without running it) and says where it no longer matches
  the interface.
- ``rclpy``: the ``rclpy`` generation target (an ament_python lifecycle-node package).
- ``system``: a system file as the component manager reads it (``system_spec``: the instances in start
  order, each with its package, executable, node, restart policy, snapshot period and interface hash).
- ``launch``: the ``launch`` generation target (one ROS 2 launch file for a system file).
- the component manager (docs/system.md): ``snapshots`` (saved states on disk, atomic),
  ``restart`` (policy and intensity), ``processes`` (instance processes: started, recorded,
  adopted), ``link`` (calls to components over the protocol), ``manager`` (``/iface_manager``),
  ``manager_client`` and ``status_html`` (the ``system`` command's side).

May import: ``model``, ``syntax``, ``semantics``, ``text``, ``forms``, ``emit``, ``compat``.
"""
