"""Writing ``.iface`` text. Two writers, one job each.

- ``printer``: a model → ``.iface`` text (what importers write); parses back to an equal model;
- ``formatter``: source text → the same text in the house style, every comment kept (``iface-lsp fmt``
  and the editor's formatting).

May import: ``model``, ``syntax``.
"""
