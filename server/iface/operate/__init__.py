"""Operating a running system: the component manager, the hand-over, trust, and the calls they make.

- ``link``: the one protocol client: calls to components (lifecycle, ``~/control``, save, restore)
  over rclpy, with service lookup, a client cache and idempotent resends.
- ``handover``: replace a running component by another (``decide`` offline, ``HandOver`` live).
- ``trust``: sign a component package and check it against a trust store.
- the component manager (docs/system.md): ``snapshots`` (saved states on disk, atomic),
  ``restart`` (policy and intensity), ``processes`` (instance processes: started, recorded,
  adopted), ``manager`` (``/iface_manager``), ``manager_client`` and ``status_html`` (the
  ``system`` command's side).

May import: ``model``, ``syntax``, ``semantics``, ``text``, ``forms``, ``compat``, ``nodes`` (the protocol,
a system file's spec), ``live``.
"""
