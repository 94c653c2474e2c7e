"""Syntax: text → model. The grammar, the lexers, chunking into top-level definitions, parsing with recovery.

- ``grammar``: finds ``grammar.lark`` and builds the LALR parser once;
- ``lexer``: the fast scanner for clean text (lark's lexer stays on the recovery path);
- ``chunks``: top-level definitions as independent chunks, cached across edits;
- ``parse``: ``parse_text`` with error recovery (one error per broken definition, the rest kept);
- ``transform``: the lark tree → model nodes, run inside the parser.

May import: ``model``.
"""
