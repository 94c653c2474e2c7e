"""Live truth: read a running ROS 2 graph, write it as ``.iface``, and check it against declared interfaces.

``reading`` holds what the graph tells of a node (a ``NodeReading``) as plain data (no ROS import); ``graph`` reads it
through rclpy (imported only when a command needs it); ``to_iface`` writes a reading as an
``.iface`` file; ``verify`` compares readings with compiled interfaces and yields findings. ``link`` is the one
client that calls running nodes' services (rclpy, imported when used): the graph reader's, the hand-over's,
the component manager's and the ``system`` commands' calls all go through it.

May import: ``model``, ``syntax``, ``semantics``, ``text``, ``forms``, ``compat``, ``nodes`` (the protocol's names).
"""
