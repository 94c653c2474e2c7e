"""The model as data: the JSON form (with its schema) and the golden dump.

- ``jsonform``: the JSON form of a compiled interface and back (the ``json`` target and importer);
  ``iface.schema.json`` is its JSON Schema;
- ``dump``: every node with its kind, fields and source range, for ``iface-lsp dump`` and golden tests.

May import: ``model``, ``syntax``, ``semantics``, ``text``.
"""
