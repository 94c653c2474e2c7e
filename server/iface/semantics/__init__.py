"""Semantics: the meaning of a parsed file. Names resolved, the seven sets derived, every check run.

- ``compile``: ``Workspace`` and ``Compilation``, the one compiled result every consumer uses (CLI
  commands, emitters, compat, the language server);
- ``resolve``: symbols and references, includes; ``suggest``: did-you-mean; ``sets``: the seven sets
  and their findings;
- ``validate``: the semantic checks, small per-node functions that yield located diagnostics;
- ``analysis``: resolution and checks kept per definition and wiring, so that an edit redoes only what
  it changed;
- ``query``: what editors ask of a compiled model (the item at an offset, references, the outline);
- ``systems``: a system file's instances, their annotations and start order, and its checks.

May import: ``model``, ``syntax``.
"""
