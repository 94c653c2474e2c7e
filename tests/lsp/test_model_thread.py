"""Work handed to the model thread without waiting: the parser's warm-up, and failures that are logged."""

from __future__ import annotations

import logging
from typing import Any

import pytest

from iface.lsp.features.configuration import warm_up
from iface.lsp.project import Project
from iface.syntax import grammar, parse


def test_the_warm_up_builds_the_parser_and_its_error_messages(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(parse, "_parser", None)
    monkeypatch.setattr(grammar, "_descriptions", {})
    warm_up()
    assert parse._parser is not None
    assert grammar._descriptions["IDENTIFIER"] == "a name"
    assert grammar._descriptions["$END"] == "end of file"


def test_the_warm_up_runs_on_the_model_thread_without_a_logged_failure(
        monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture) -> None:
    monkeypatch.setattr(parse, "_parser", None)
    monkeypatch.setattr(grammar, "_descriptions", {})
    project = Project(lambda *_: None)
    with caplog.at_level(logging.ERROR, logger="iface.lsp"):
        project.submit(warm_up)
        project.model.shutdown(wait=True)
    assert caplog.records == []
    assert parse._parser is not None and grammar._descriptions


def test_a_failure_of_work_not_waited_for_is_logged(caplog: pytest.LogCaptureFixture) -> None:
    project = Project(lambda *_: None)

    def broken(*args: Any) -> None:
        raise ImportError("no module named iface.lsp.grammar")

    with caplog.at_level(logging.ERROR, logger="iface.lsp"):
        project.submit(broken, 1)
        project.model.shutdown(wait=True)
    [record] = caplog.records
    assert record.message == "work on the model thread failed"
    assert record.exc_info is not None and isinstance(record.exc_info[1], ImportError)
