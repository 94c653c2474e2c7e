"""The headless commands of ``iface-lsp``: one module each, with ``add_arguments`` and ``run``.

``common`` loads files and prints diagnostics; ``load`` refuses inputs with errors for the commands that
compare. Exit codes: 0 ok, 1 findings, 2 usage or I/O, 3 internal error. Nothing outside this package
imports it.

May import: every stage but ``lsp``.
"""
