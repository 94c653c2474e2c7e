"""``ros2 iface VERB``: ros2cli's extension, the verbs of iface that talk to a running system.

``import`` (``iface-lsp import --from node``), ``verify`` (``iface-lsp verify``), ``status``, ``replace`` and
``snapshot`` (``iface-lsp system …``): each verb declares the options of the command it stands for (through
that command's own ``add_arguments`` helpers) and runs that command's ``run`` (``cli.run_command``), so the
output and the exit codes are the same; messages start with ``ros2 iface VERB``. ros2cli's conventions on
top: ``--spin-time`` (it sets the option that bounds the wait for the graph: ``--timeout`` of import and
verify, ``--manager-timeout`` of the manager's verbs), ``--no-daemon`` on the verbs that read the graph
(iface always reads the graph with a probe node of its own and never starts or asks the ROS 2 daemon; the
option is accepted, and completion of node names honours it), and argcomplete completers for every argument.

The ``ros2`` command loads this module through the entry points the package declares (``ros2cli.command``:
``iface``; the verb group ``iface.verb``). It imports ros2cli, which is there only where ROS 2 is sourced:
nothing in iface imports it (tests/core/test_layering.py holds that).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import Any

from ros2cli.command import CommandExtension, add_subparsers_on_demand
from ros2cli.plugin_system import PLUGIN_SYSTEM_VERSION, satisfies_version

from .cli import run_command
from .commands import import_, system, terminal, verify

#: The entry point group of the verbs (declared as a ros2cli extension point in pyproject.toml).
VERB_GROUP = "iface.verb"


class IfaceCommand(CommandExtension):
    """Import running nodes as .iface files, verify a running system, ask its component manager."""

    def add_arguments(self, parser: argparse.ArgumentParser, cli_name: str, *, argv: list[str] | None = None) -> None:
        self._subparser = parser
        add_subparsers_on_demand(parser, cli_name, "_verb", VERB_GROUP, required=False, argv=argv)

    def main(self, *, parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
        if not hasattr(args, "_verb"):  # `ros2 iface` alone: its help, as ros2cli's commands do
            self._subparser.print_help()
            return 0
        return int(args._verb.main(args=args))


class VerbExtension:
    """The extension point of ``ros2 iface``'s verbs: ``NAME`` (set to the entry point's name), ``add_arguments``
    and ``main``."""

    NAME: str | None = None
    EXTENSION_POINT_VERSION = "0.1"

    def __init__(self) -> None:
        super().__init__()
        satisfies_version(PLUGIN_SYSTEM_VERSION, "^0.1")

    def add_arguments(self, parser: argparse.ArgumentParser, cli_name: str) -> None:
        """Declare the verb's arguments."""

    def main(self, *, args: argparse.Namespace) -> int:
        """Run the verb: its exit code."""
        raise NotImplementedError


class _Adapter(VerbExtension):
    """A verb that runs one ``iface-lsp`` command (``COMMAND``, a module of ``commands/``) with the parsed arguments."""

    COMMAND = ""
    #: The destination of the option that ``--spin-time`` sets (``timeout``, ``manager_timeout``).
    spin_dest = ""

    def spin_time(self, parser: argparse.ArgumentParser, bounds: argparse.Action, what: str) -> None:
        """ros2cli's ``--spin-time``: it sets the option ``bounds``. Kept as ``spin_time`` too (only when given),
        where ros2cli's node name completer reads how long to look at the graph."""
        self.spin_dest = bounds.dest
        parser.add_argument("--spin-time", type=float, default=argparse.SUPPRESS, metavar="S",
                            help=f"ros2cli's name for {bounds.option_strings[0]} (sets it): {what}")

    def main(self, *, args: argparse.Namespace) -> int:
        args.prog = f"ros2 iface {self.NAME}"
        if self.spin_dest and hasattr(args, "spin_time"):
            setattr(args, self.spin_dest, args.spin_time)
        with terminal.guarded_output():
            return run_command(self.COMMAND, args, bool(args.debug))


def _no_daemon(parser: argparse.ArgumentParser, completes_nodes: bool) -> None:
    more = (" Completion of NODE asks the daemon, as ros2cli's completers do, unless --no-daemon is on the line (it "
            "then looks at the graph for --spin-time, default 0.5 s).") if completes_nodes else ""
    parser.add_argument("--no-daemon", action="store_true",
                        help="accepted as ros2cli's graph verbs accept it: iface always reads the graph with a probe "
                             "node of its own and never starts or asks the ROS 2 daemon." + more)


def _debug(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--debug", action="store_true", help="show the traceback of an internal error")


def _completer(action: argparse.Action, make: Callable[[], Any]) -> None:
    """Set ``action.completer`` (argcomplete's), when argcomplete is there."""
    try:
        action.completer = make()  # type: ignore[attr-defined]
    except ImportError:
        pass


def _files(*suffixes: str) -> Callable[[], Any]:
    def make() -> Any:
        from argcomplete.completers import FilesCompleter

        return FilesCompleter(allowednames=suffixes, directories=True)
    return make


def _folders() -> Any:
    from argcomplete.completers import DirectoriesCompleter

    return DirectoriesCompleter()


def _nodes() -> Any:
    from ros2node.api import NodeNameCompleter

    return NodeNameCompleter()


def instance_names(prefix: str, parsed_args: argparse.Namespace, **_: Any) -> list[str]:
    """The instances of the system file already on the command line (argcomplete's completer of INSTANCE)."""
    from .nodes.system import system_spec

    try:
        spec = system_spec(parsed_args.system)
    except Exception:  # noqa: BLE001 - no system file (yet), or one with errors: nothing to offer
        return []
    return [i.name for i in spec.instances if i.name.startswith(prefix)]


class ImportVerb(_Adapter):
    """Describe running ROS 2 nodes as .iface files, read off the graph (iface-lsp import --from node)."""

    COMMAND = "iface.commands.import_"

    def add_arguments(self, parser: argparse.ArgumentParser, cli_name: str) -> None:
        nodes = parser.add_argument("inputs", nargs="*", metavar="NODE", help="running nodes: /name or /ns/name")
        out, timeout = import_.add_node_arguments(parser)
        import_.add_output_arguments(parser)
        self.spin_time(parser, timeout, "seconds to wait for discovery and for each answer")
        _no_daemon(parser, completes_nodes=True)
        _debug(parser)
        parser.set_defaults(source="node", deps=None)
        _completer(nodes, _nodes)
        _completer(out, _folders)


class VerifyVerb(_Adapter):
    """Check the running ROS 2 graph against the declared interfaces (iface-lsp verify)."""

    COMMAND = "iface.commands.verify"

    def add_arguments(self, parser: argparse.ArgumentParser, cli_name: str) -> None:
        actions = verify.add_arguments(parser)
        self.spin_time(parser, actions["timeout"], "seconds to wait for discovery and for each answer")
        _no_daemon(parser, completes_nodes=False)
        _debug(parser)
        _completer(actions["files"], _files("iface", "thrift"))
        _completer(actions["include_path"], _folders)


class _ManagerVerb(_Adapter):
    """A verb of ``iface-lsp system``: ACTION is its own name."""

    COMMAND = "iface.commands.system"

    def arguments(self, actions: dict[str, argparse.Action], parser: argparse.ArgumentParser) -> None:
        self.spin_time(parser, actions["manager_timeout"], "how long to wait for the manager to answer")
        _debug(parser)
        parser.set_defaults(action=self.NAME)
        _completer(actions["system"], _files("iface"))
        if "instance" in actions:
            actions["instance"].completer = instance_names  # type: ignore[attr-defined]
        if "new" in actions:
            _completer(actions["new"], _files("iface"))
            _completer(actions["package"], _folders)


class StatusVerb(_ManagerVerb):
    """The status of every instance of a running system, from its component manager (iface-lsp system status)."""

    def add_arguments(self, parser: argparse.ArgumentParser, cli_name: str) -> None:
        self.arguments(system.add_status_arguments(parser), parser)


class ReplaceVerb(_ManagerVerb):
    """Replace an instance of a running system through its component manager (iface-lsp system replace)."""

    def add_arguments(self, parser: argparse.ArgumentParser, cli_name: str) -> None:
        self.arguments(system.add_replace_arguments(parser), parser)


class SnapshotVerb(_ManagerVerb):
    """Save the state of a running system's instances now (iface-lsp system snapshot)."""

    def add_arguments(self, parser: argparse.ArgumentParser, cli_name: str) -> None:
        self.arguments(system.add_snapshot_arguments(parser), parser)
