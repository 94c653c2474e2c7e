"""The headless command line: ``iface-lsp COMMAND …``, and ``iface-lsp --stdio`` for the server.

Each command lives in ``iface.commands.<name>`` with ``add_arguments(parser)``
and ``run(args) -> int``; it is imported only when used, so a check never
pays for the language server's imports.
"""

from __future__ import annotations

import argparse
import gc
import importlib
import importlib.util
import sys
import traceback
from collections.abc import Iterator, Sequence
from contextlib import contextmanager

from .commands import terminal

#: command name -> (module, one-line help)
COMMANDS: dict[str, tuple[str, str]] = {
    "check": ("iface.commands.check", "check .iface and .thrift files and print their diagnostics"),
    "fmt": ("iface.commands.fmt", "format files in place (or --check that they are formatted)"),
    "generate": ("iface.commands.generate", "generate platform files for a target"),
    "targets": ("iface.commands.targets", "list the generation targets"),
    "schema": ("iface.commands.schema", "print the JSON Schema of the json target's output"),
    "import": ("iface.commands.import_", "import ROS 2, PX4 or JSON interfaces into .iface files"),
    "roundtrip": ("iface.commands.roundtrip", "import, regenerate and compare: prints 'N of M identical'"),
    "compat": ("iface.commands.compat", "decide whether NEW can replace OLD"),
    "hash": ("iface.commands.hash", "print the canonical hash of an interface"),
    "contract": ("iface.commands.contract", "print the assumptions and guarantees of a component"),
    "graph": ("iface.commands.graph", "print the system graph of several components"),
    "impact": ("iface.commands.impact", "show what replacing one component affects"),
    "dump": ("iface.commands.dump", "print the model of a file as JSON (for debugging and goldens)"),
    "handover": ("iface.commands.handover", "replace a running component by a compatible one, moving its state"),
    "verify": ("iface.commands.verify", "check the running ROS 2 graph against the declared interfaces"),
    "manager": ("iface.commands.manager", "run the component manager of a system: up, watched, state kept, replaced"),
    "system": ("iface.commands.system", "ask a running component manager: status, replace, snapshot"),
    "sign": ("iface.commands.sign", "sign a component package (ed25519), verify it, or create a key"),
}

#: Commands that read their files, write their answer and end: they run with the cyclic collector paused, as
#: mypy runs a check (what they build lives until they end and is freed by reference counting; the young
#: collections would only traverse it, 15-25% of a `check` of a large file). The others run a ROS 2 node or
#: a process that lives on (verify, import --from node, handover, manager, system): the collector stays on.
ONE_SHOT = frozenset({"check", "fmt", "generate", "targets", "schema", "roundtrip", "compat", "hash", "contract",
                      "graph", "impact", "dump", "sign"})


@contextmanager
def collector_paused(paused: bool) -> Iterator[None]:
    """The cyclic garbage collector off while the block runs (when ``paused``), then as it was."""
    enabled = gc.isenabled()
    if paused:
        gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _parser(available: dict[str, tuple[str, str]], chosen: str | None) -> argparse.ArgumentParser:
    """The command line's parser: the commands of ``available`` with their help, and the ``chosen`` one's arguments
    (importing its module); with no command chosen (``--version``, ``--help``, a name that is no command) no module
    is imported."""
    parser = argparse.ArgumentParser(
        prog="iface-lsp",
        description="iface: one explicit interface file per robotic component; checks, generators, "
                    "importers, compatibility and a language server.",
        epilog="Exit codes: 0 ok, 1 findings, 2 usage or I/O error, 3 internal error (a bug: --debug shows "
               "its traceback).")
    parser.add_argument("--stdio", action="store_true", help="run the language server on stdin/stdout")
    parser.add_argument("--tcp", metavar="HOST:PORT", help="run the language server on a TCP socket")
    parser.add_argument("--version", action="store_true", help="print the version and exit")
    parser.add_argument("--debug", action="store_true",
                        help="show the traceback of an internal error (may stand anywhere on the command line)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (module, help_text) in available.items():
        cmd = sub.add_parser(name, help=help_text, description=help_text)
        cmd.set_defaults(_module=module, prog=f"iface-lsp {name}")
        if name == chosen:
            importlib.import_module(module).add_arguments(cmd)
    return parser


def _available() -> dict[str, tuple[str, str]]:
    out = {}
    for name, (module, help_text) in COMMANDS.items():
        if importlib.util.find_spec(module) is not None:
            out[name] = (module, help_text)
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``iface-lsp`` console script."""
    args_list = list(sys.argv[1:] if argv is None else argv)
    if any(a == "--stdio" or a == "--tcp" or a.startswith("--tcp=") for a in args_list):
        # the server starts without building the commands' parsers (their imports cost startup time)
        pre = argparse.ArgumentParser(prog="iface-lsp")
        pre.add_argument("--stdio", action="store_true")
        pre.add_argument("--tcp", metavar="HOST:PORT")
        known = pre.parse_args(args_list)
        try:
            from .lsp.server import serve
        except ImportError as e:
            return internal_error("iface-lsp", e, "--debug" in args_list)
        return serve(tcp=known.tcp)
    debug = "--debug" in args_list
    args_list = [a for a in args_list if a != "--debug"]
    with terminal.guarded_output():
        return _run(args_list, debug)


def _run(args_list: list[str], debug: bool) -> int:
    """Parse the command line and run one command; see the epilog for the exit codes."""
    available = _available()
    # a named command gets the only subparser (all 18 take 5 ms a call, one 0.7 ms, and the tests that run the
    # CLI in process make thousands of calls); only its module is imported, for its arguments
    first = next((a for a in args_list if not a.startswith("-")), None)
    named = first if first in available else None
    try:
        parser = _parser({named: available[named]} if named else available, named)
    except ImportError as e:
        return internal_error(f"iface-lsp {named}", e, debug)
    try:
        args = parser.parse_args(args_list)
    except SystemExit as e:
        return e.code if isinstance(e.code, int) else 2
    if args.version:
        from . import __version__
        print(f"iface-lsp {__version__}")
        return 0
    if not args.command:
        parser.print_help(sys.stderr)
        return 2
    with collector_paused(args.command in ONE_SHOT):
        return run_command(args._module, args, debug)


def run_command(module_name: str, args: argparse.Namespace, debug: bool) -> int:
    """Run the command module's ``run(args)`` and give its exit code: 130 on Ctrl-C, 143 on SIGTERM, and 3 with one
    line (``args.prog: internal error: …``; the traceback too with ``debug``) on any other exception, a bug."""
    try:
        module = importlib.import_module(module_name)
        with terminal.interruptible():
            return int(module.run(args))
    except KeyboardInterrupt:
        return 130
    except terminal.Terminated:
        return 143
    except Exception as e:  # noqa: BLE001 - every other exception is a bug: one line, exit 3
        return internal_error(args.prog, e, debug)


def internal_error(prog: str, e: Exception, debug: bool) -> int:
    """Say ``prog: internal error: …`` in one line on stderr (the traceback before it with ``debug``) and give 3.

    A module of another package that is not there is an installation without iface's dependencies, not a bug: the
    line says how to install them."""
    if debug:
        traceback.print_exc()
    missing = e.name if isinstance(e, ModuleNotFoundError) else None
    if missing and missing.split(".")[0] != "iface":
        why = " (iface's dependencies are not all installed: run `pip install .` in iface's folder)"
    else:
        why = " (a bug in iface: please report it with the input; --debug shows the traceback)"
    print(f"{prog}: internal error: {terminal.one_line(f'{type(e).__name__}: {e}')}" + ("" if debug else why),
          file=sys.stderr)
    return 3


if __name__ == "__main__":
    sys.exit(main())
