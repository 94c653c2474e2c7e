"""iface: one explicit, machine-checkable interface file per robotic component.

The package root holds the entry points: ``cli`` (``iface-lsp``) and ``__main__`` (``python -m iface``).
The stages live in the subpackages, in pipeline order: ``model``, ``syntax``, ``semantics``, ``text``,
``forms``, ``emit``, ``importers``, ``compat``, ``runtime``, then ``commands`` and ``lsp``
(docs/architecture.md, tests/core/test_layering.py).

May import: every stage (this root only defines ``__version__``; ``cli`` is the one module that
reaches ``commands`` and ``lsp``).
"""

__version__ = "0.1.0"
