"""The .iface printer: docs, strings and numbers survive a print and a parse."""

from __future__ import annotations

import pytest

from iface.model import nodes as m
from iface.model.source import Span
from iface.semantics.compile import Workspace
from iface.syntax.transform import decode_literal
from iface.text.printer import PrintError, doc_lines, print_items, quote, value_text


@pytest.mark.parametrize("text", ["plain", 'say "hi"', "back\\slash", "tab\tnew\nline", "nul\0", "bell\a",
                                  "it's", "ünïcode ハロー", "# not a comment", "/* nor this */"])
def test_quote_decodes_back(text):
    assert decode_literal(quote(text)) == text


def test_doc_comment_cannot_be_closed_early():
    assert doc_lines("a */ b") == ["/** a *\\/ b */"]


@pytest.mark.parametrize("doc", ["one line", "two\nlines", "  indented\nnext", "* starred\n* list", "", "ends*"])
def test_docs_read_back(doc, tmp_path):
    s = Span(0, 0)
    struct = m.Struct("message", "M", s, s, [m.Field("a", m.BaseType("i32", Span(1, 1)), Span(2, 2), s, doc=doc)],
                      [], [], doc)
    path = tmp_path / "t.iface"
    path.write_text(print_items([struct]), encoding="utf-8")
    back = Workspace().compile_path(str(path)).interface.symbols["M"]
    assert back.doc == doc
    assert back.fields[0].doc == doc


def test_numbers_keep_their_spelling():
    s = Span(0, 0)
    assert value_text(m.Value("int", 16, s, "0x10")) == "0x10"
    assert value_text(m.Value("double", 1.5, s, "1.50")) == "1.50"
    assert value_text(m.Value("int", 16, s, "017")) == "16"
    assert value_text(m.Value("double", 1e20, s, "")) == "1e+20"
    with pytest.raises(PrintError):
        value_text(m.Value("double", float("inf"), s, ""))
