"""The check command's contract: formats, exit codes, both entry points."""

from __future__ import annotations

import json
import shutil
import subprocess

from tests.conftest import run_cli

from .helpers import DATA

VALID = DATA / "valid"
INVALID = DATA / "invalid"


def test_text_format_lines() -> None:
    r = run_cli("check", str(INVALID / "unknown-type_typo.iface"))
    assert r.returncode == 1
    lines = r.stdout.splitlines()
    assert lines[0].endswith("unknown-type_typo.iface:5:8: error[unknown-type]: unknown type 'Pos'; did you mean 'Pose'?")


def test_json_format() -> None:
    r = run_cli("check", "--format", "json", str(INVALID / "unknown-type_typo.iface"), str(VALID / "listing1.iface"))
    assert r.returncode == 1
    data = json.loads(r.stdout)
    keys = {"file", "line", "column", "end_line", "end_column", "severity", "code", "message"}
    assert all(set(d) == keys for d in data["diagnostics"])
    assert {d["severity"] for d in data["diagnostics"]} <= {"error", "warning", "information", "hint"}
    first = data["diagnostics"][0]
    assert (first["line"], first["column"], first["end_line"], first["end_column"]) == (5, 8, 5, 11)
    assert any(d["file"].endswith("listing1.iface") for d in data["diagnostics"])


def test_exit_zero_with_only_warnings() -> None:
    assert run_cli("check", str(VALID / "listing1.iface")).returncode == 0


def test_usage_errors_exit_two() -> None:
    assert run_cli("check").returncode == 2
    assert run_cli("check", "--format", "xml", str(VALID / "listing1.iface")).returncode == 2
    assert run_cli().returncode == 2


def test_console_script_matches_python_m() -> None:
    exe = shutil.which("iface-lsp")
    if exe is None:
        return
    a = subprocess.run([exe, "check", str(VALID / "listing1.iface")], capture_output=True, text=True)
    b = run_cli("check", str(VALID / "listing1.iface"))
    assert (a.returncode, a.stdout) == (b.returncode, b.stdout)


def test_include_path_option(tmp_path) -> None:
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "common.iface").write_text("struct Shared {\n    1: i32 x\n}\n")
    main = tmp_path / "main.iface"
    main.write_text('include "common.iface"\nstruct User {\n    1: common.Shared s\n}\n')
    assert run_cli("check", str(main)).returncode == 1
    r = run_cli("check", "-I", str(lib), str(main))
    assert r.returncode == 0, r.stdout


def test_dump_command() -> None:
    r = run_cli("dump", str(VALID / "mini_robot.iface"))
    assert r.returncode == 0
    data = json.loads(r.stdout)
    assert data["name"] == "drive" and data["sets"]["subscribed"][0]["name"] == "/cmd_vel"


def test_cli_starts_without_site_hooks() -> None:
    """A fresh install has no .pth hooks that import importlib.util for us (python -S)."""
    import sys
    import sysconfig
    from pathlib import Path

    server = Path(__file__).resolve().parents[2] / "server"
    code = ("import sys; sys.path[:0] = [%r, %r]; from iface.cli import main; "
            "sys.exit(main(['check', %r]))" % (str(server), sysconfig.get_paths()["purelib"],
                                                 str(VALID / "mini_robot.iface")))
    r = subprocess.run([sys.executable, "-S", "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_one_shot_commands_run_with_the_collector_paused_the_others_with_it_on(monkeypatch) -> None:
    """Issue 33: `check` and the other commands that read files and end pause the cyclic collector for their run
    (and give it back as it was: here, in process); those that run a ROS 2 node or live on keep it."""
    import gc
    import importlib

    from iface import cli
    from tests.conftest import run_main

    assert cli.ONE_SHOT <= set(cli.COMMANDS)
    assert not cli.ONE_SHOT & {"verify", "import", "handover", "manager", "system"}
    seen: dict[str, bool] = {}
    for name in ("check", "hash", "verify", "manager"):
        module = importlib.import_module(cli.COMMANDS[name][0])
        monkeypatch.setattr(module, "run", lambda args, name=name: seen.setdefault(name, gc.isenabled()) and 0)
        run_main(name, str(VALID / "listing1.iface"))
    assert seen == {"check": False, "hash": False, "verify": True, "manager": True}
    assert gc.isenabled()


def test_a_command_imports_only_its_own_module_and_version_and_help_none() -> None:
    """The parser imports the chosen command's module for its arguments, and no other: ``--version`` took 0.5
    CPU-s where ``check`` takes 0.3 because, with no command named, every command's module was imported."""
    import sys
    from pathlib import Path

    server = Path(__file__).resolve().parents[2] / "server"
    code = (f"import contextlib, io, sys; sys.path.insert(0, {str(server)!r}); from iface.cli import COMMANDS, main\n"
            "with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):\n"
            "    code = main(sys.argv[1:])\n"
            "print(code, *sorted(n for n, (m, _) in COMMANDS.items() if m in sys.modules))")
    loaded = {}
    for argv in (["--version"], ["--help"], [], ["bogus"], ["targets"], ["hash", "--help"]):
        r = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True, timeout=120,
                           check=False)
        assert r.returncode == 0, r.stderr
        loaded[" ".join(argv)] = r.stdout.split()
    assert loaded == {"--version": ["0"], "--help": ["0"], "": ["2"], "bogus": ["2"], "targets": ["0", "targets"],
                      "hash --help": ["0", "hash"]}


def test_a_named_command_gets_the_only_subparser(monkeypatch) -> None:
    """All 18 subparsers take 5 ms a call where one takes 0.7 ms, and the tests that run the CLI in process make
    thousands of calls (a review that built them all made ``core/test_every_command.py`` 90 CPU-s slower)."""
    from iface import cli
    from tests.conftest import run_main

    built: list[list[str]] = []
    parser = cli._parser
    monkeypatch.setattr(cli, "_parser", lambda available, chosen: built.append(sorted(available))
                        or parser(available, chosen))
    run_main("hash", str(VALID / "listing1.iface"))
    run_main("--version")
    assert built == [["hash"], sorted(cli._available())]
