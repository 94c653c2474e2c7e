"""One module per editor feature; each has ``register(server)``.

May import: what ``lsp`` may (every stage but ``commands``) and the other modules of ``lsp``; lsprotocol
values are built by ``lsp.convert``.
"""
