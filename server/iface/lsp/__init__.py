"""The language server: thin pygls adapters over the shared model (``semantics.compile``, ``semantics.query``).

- ``server``: the pygls server and its lifecycle; ``features/``: one module per LSP feature;
- ``project``: open documents, the model thread, the compile scheduler and diagnostics publishing;
- ``documents``: buffers, versions, edits and offset mapping; ``versions``: compiled versions and views;
- ``index``: the workspace index (symbols across files); ``convert``: the only place that builds
  lsprotocol types; ``describe``, ``context``: hover text and completion context; ``settings``.

The only package that imports pygls or lsprotocol. May import: every stage but ``commands``.
"""
