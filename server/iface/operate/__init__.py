"""Operating a running system: the component manager, the hand-over, trust, and the calls they make.

- ``handover``: replace a running component by another (``decide`` offline, ``HandOver`` live: its steps
  public and named); its calls, as every call to a node here, go through the one client, ``live.link``.
- ``trust``: sign a component package and check it against a trust store.
- the component manager (docs/system.md): ``snapshots`` (saved states on disk, atomic),
  ``restart`` (policy and intensity), ``implementation`` (what an instance runs, and its replacement kept),
  ``processes`` (instance processes: started, their end told at once, recorded, adopted),
  ``containers`` (a component as a container loads it, its trust, whether NEW can share a process),
  ``in_container`` (the calls to a running container), ``container_host`` (the manager's containers: a
  failure domain each),
  ``manager`` (``/iface_manager``), ``manager_client`` and ``status_html`` (the ``system`` command's side).

May import: ``model``, ``syntax``, ``semantics``, ``text``, ``forms``, ``compat``, ``nodes`` (the protocol,
a system file's spec), ``live``.
"""
