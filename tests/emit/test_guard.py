"""The registry's guard: an exception inside a target is a diagnostic naming it, never a traceback."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import jinja2
import pytest

from iface.emit import GenerationError, Result, Target, plugins, registry
from iface.semantics.compile import Compilation

from .helpers import CASES, compile_file

#: A target module whose generate raises, installed through a real entry point in the CLI test.
BROKEN_MODULE = '''
from iface.emit import Target


def generate(comp, options):
    return {"files": []}["missing"]  # a bug: KeyError


TARGET = Target("boom", "a target with a bug", generate)
'''


def _raises(exc: Exception) -> Target:
    def generate(comp: Compilation, options: dict[str, Any]) -> Result:
        raise exc
    return Target("boom", "a target with a bug", generate)


def test_an_exception_becomes_an_internal_error_naming_the_target() -> None:
    comp = compile_file(CASES["listing1"])
    result = registry.guarded(_raises(ZeroDivisionError("division by zero"))).generate(comp, {})
    assert result.files == [] and result.has_errors
    (d,) = result.diagnostics
    assert d.code == "internal-error" and d.path == comp.path
    assert "the boom target failed: ZeroDivisionError: division by zero" in d.message


def test_a_template_error_is_a_generation_error() -> None:
    comp = compile_file(CASES["listing1"])
    with pytest.raises(GenerationError, match="boom templates: TemplateNotFound: msg.j2"):
        registry.guarded(_raises(jinja2.TemplateNotFound("msg.j2"))).generate(comp, {})
    with pytest.raises(GenerationError, match="^already reported$"):
        registry.guarded(_raises(GenerationError("already reported"))).generate(comp, {})


class _EntryPoint:
    def __init__(self, name: str, value: Target) -> None:
        self.name = name
        self.value = value

    def load(self) -> Target:
        return self.value


def test_every_target_from_the_registry_is_guarded(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(plugins, "entry_points", lambda group: [_EntryPoint("boom", _raises(RuntimeError("x")))])
    result = registry.generate(compile_file(CASES["listing1"]), "boom")
    assert [d.code for d in result.diagnostics] == ["internal-error"]


def test_the_installed_plugins_are_read_once_per_search_path(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """Reading every installed distribution's entry points costs tens of milliseconds: once per process and
    ``sys.path``, not once per command (a generate run asks for its target twice)."""
    scans: list[str] = []

    def entry_points(group: str) -> list[_EntryPoint]:
        scans.append(group)
        return [_EntryPoint("boom", _raises(RuntimeError("x")))]

    monkeypatch.setattr(plugins, "entry_points", entry_points)
    assert list(registry.targets()) == list(registry.targets()) == ["boom"]
    assert registry.get_target("boom") is not None
    assert scans == [registry.GROUP]
    monkeypatch.syspath_prepend(str(tmp_path))  # another search path: read again
    assert list(registry.targets()) == ["boom"] and len(scans) == 2


def test_the_cli_reports_a_broken_target_without_a_traceback(tmp_path: Path) -> None:
    site = tmp_path / "site"
    dist = site / "broken_target-1.0.dist-info"
    dist.mkdir(parents=True)
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: broken-target\nVersion: 1.0\n")
    (dist / "entry_points.txt").write_text("[iface.targets]\nboom = broken_target:TARGET\n")
    (site / "broken_target.py").write_text(BROKEN_MODULE)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), os.environ.get("PYTHONPATH", "")])}
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "iface", "generate", str(CASES["listing1"]), "-t", "boom",
                           "-o", str(out)], capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 3  # an internal error (issue 15): not a finding (1), not a usage error (2)
    text = proc.stdout + proc.stderr
    assert "error[internal-error]: the boom target failed: KeyError: 'missing'" in text
    assert "Traceback" not in text and not out.exists()
    listed = subprocess.run([sys.executable, "-m", "iface", "targets"], capture_output=True, text=True, env=env,
                            timeout=300)
    assert "boom" in listed.stdout and "ros2" in listed.stdout


def test_a_broken_template_override_is_a_usage_error_for_every_target(tmp_path: Path) -> None:
    (tmp_path / "msg.j2").write_text("{% if %}\n")
    source = Path(__file__).parent / "data" / "px4" / "flight_arm.iface"
    proc = subprocess.run([sys.executable, "-m", "iface", "generate", str(source), "-t", "px4", "-o",
                           str(tmp_path / "out"), "--templates", str(tmp_path)], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 2
    assert "px4 templates: TemplateSyntaxError" in proc.stderr and "Traceback" not in proc.stderr
