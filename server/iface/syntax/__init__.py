"""Syntax: text → model. The grammar, the lexers, chunking into top-level definitions, parsing with recovery.

- ``grammar``: finds ``grammar.lark`` and builds the LALR parser once;
- ``lexer``: the fast scanner for clean text (lark's lexer stays on the recovery path);
- ``driver``: a clean whole file parsed by lark's LALR tables driven from one loop;
- ``chunks``: top-level definitions as independent chunks, cached across edits;
- ``parse``: ``parse_text`` with error recovery (one error per broken definition, the rest kept);
- ``edits``: an edited document's parse made from its last one (only the chunks the edit touched);
- ``transform``: the lark tree → model nodes, run inside the parser.

May import: ``model``.
"""
