"""Semantics: the meaning of a parsed file. Names resolved, the seven sets derived, every check run.

- ``compile``: ``Workspace`` and ``Compilation``, the one compiled result every consumer uses (CLI
  commands, emitters, compat, the language server);
- ``resolve``: symbols and references, includes; ``sets``: the seven sets;
- ``validate``: the semantic checks, small per-node functions that yield located diagnostics;
- ``query``: what editors ask of a compiled model (the item at an offset, references, the outline);
- ``systems``: a system file's instances, their annotations and start order, and its checks.

May import: ``model``, ``syntax``.
"""
