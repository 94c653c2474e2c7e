"""The README's quick start runs as written, and every interface shown in README.md and docs/tutorial.md checks clean.

The quick start's ```iface block is saved as the file its text names (``drive.iface``) in a folder that holds
the repository's ``examples/``; each line of its ```sh block runs there with this checkout's ``iface-lsp``
(``python -m iface``) and exits 0, without a warning; where the line's comment starts with what the command
prints (``ok:``, ``verdict:``), the output has it.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
TUTORIAL = ROOT / "docs" / "tutorial.md"
#: A comment that quotes what the command prints.
PRINTED = ("ok:", "verdict:")


def section(text: str, heading: str) -> str:
    """The text of the section ``heading`` (up to the next heading of any level)."""
    start = text.index(heading)
    end = text.find("\n#", start + len(heading))
    return text[start:] if end < 0 else text[start:end]


def blocks(text: str, language: str) -> list[str]:
    """The fenced blocks of ``language`` in ``text``."""
    return re.findall(rf"^```{language}\n(.*?)^```$", text, re.MULTILINE | re.DOTALL)


def iface_lsp(argv: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "server"))
    return subprocess.run([sys.executable, "-m", "iface", *argv], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=300, check=False)


def test_the_quick_start_runs_as_written(tmp_path: Path) -> None:
    quick = section(README.read_text(encoding="utf-8"), "## Quick start")
    (interface,) = blocks(quick, "iface")
    (commands,) = blocks(quick, "sh")
    name = re.search(r"Save an interface as `([\w.]+\.iface)`", quick)
    assert name, "the quick start names the file it saves"
    (tmp_path / name.group(1)).write_text(interface, encoding="utf-8")
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    lines = [line for line in commands.splitlines() if line.strip()]
    assert len(lines) >= 3
    for line in lines:
        command, _, comment = line.partition("#")
        argv = shlex.split(command)
        assert argv[0] == "iface-lsp", line
        done = iface_lsp(argv[1:], tmp_path)
        assert done.returncode == 0, f"{line}\n{done.stdout}\n{done.stderr}"
        assert "warning" not in done.stdout + done.stderr, f"{line}\n{done.stdout}\n{done.stderr}"
        said = comment.strip()
        if said.startswith(PRINTED):
            assert said in done.stdout, f"{line}\n{done.stdout}"


@pytest.mark.parametrize("document", [README, TUTORIAL], ids=["README.md", "docs/tutorial.md"])
def test_every_interface_shown_checks_clean(document: Path, tmp_path: Path) -> None:
    text = document.read_text(encoding="utf-8")
    shown = blocks(text, "iface")
    assert shown, f"{document.name} shows no ```iface block"
    for number, interface in enumerate(shown):
        path = tmp_path / f"shown{number}.iface"
        path.write_text(interface, encoding="utf-8")
        done = iface_lsp(["check", str(path)], tmp_path)
        assert done.returncode == 0 and "warning" not in done.stdout, f"{interface}\n{done.stdout}{done.stderr}"


def _help_commands(*argv: str) -> set[str]:
    """The sub-commands ``iface-lsp [ARGV] --help`` lists under its positional arguments."""
    done = iface_lsp([*argv, "--help"], ROOT)
    assert done.returncode == 0, done.stderr
    listing = done.stdout.split("positional arguments:", 1)[1].split("options:", 1)[0]
    return set(re.findall(r"^ {4}(\w+)\b", listing, re.MULTILINE))


def _ros2_verbs() -> set[str]:
    import tomllib
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    return set(project["entry-points"]["iface.verb"])


def test_the_command_table_names_every_command_and_only_those() -> None:
    text = README.read_text(encoding="utf-8")
    table = section(text, "## Commands")
    commands = _help_commands()
    actions = _help_commands("system")
    assert {"check", "generate", "system"} <= commands and actions == {"status", "replace", "snapshot"}
    named = set(re.findall(r"`iface-lsp (\w+)", table)) | set(re.findall(r"`(\w+) [A-Z-]", table))
    assert sorted(commands - named) == [], "commands missing from README's table"
    assert sorted(a for a in actions if f"`iface-lsp system {a} " not in table) == []
    verbs = _ros2_verbs()
    assert len(verbs) == 5
    assert sorted(v for v in verbs if not re.search(rf"ros2 iface (\w+\\\|)*{v}\b", table)) == []
    # and every `iface-lsp WORD` the README shows anywhere is a command (or an option of the server)
    shown = set(re.findall(r"iface-lsp (\w[\w-]*)", text))
    assert sorted(shown - commands) == [], "README shows commands iface-lsp does not have"
    shown_verbs = set(re.findall(r"ros2 iface (\w+)", text))
    assert sorted(shown_verbs - verbs) == []
