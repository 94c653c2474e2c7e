"""Fixtures of the ros2/idl emitter tests: inputs, compiling and generating."""

from __future__ import annotations

from pathlib import Path

from iface.emit import Result, generate
from iface.semantics.compile import Compilation, Workspace

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
DATA = Path(__file__).parent / "data" / "ros2"
#: The inputs every target must generate from, by golden case name.
CASES = {
    # the paper's Listing 1 as the paper writes it (flat bodies, lower-case names); examples/listing1.iface
    # is the same interface written out as iface reads it
    "listing1": ROOT / "tests" / "core" / "data" / "valid" / "listing1.iface",
    "robot_arm": EXAMPLES / "robot_arm.iface",
    "injection": DATA / "injection.iface",
    "section_docs": DATA / "section_docs.iface",
}


def compile_file(path: Path) -> Compilation:
    """A fresh compilation of ``path``."""
    return Workspace().compile_path(str(path))


def compile_text(text: str, name: str = "snippet.iface", tmp: Path | None = None) -> Compilation:
    """A compilation of ``text`` as if it were the file ``name``."""
    folder = tmp or DATA
    return Workspace().compile_text(str(folder / name), text)


def run(target: str, comp: Compilation) -> Result:
    """Generate ``target`` and return the result."""
    return generate(comp, target)


def codes(result: Result) -> list[str]:
    """The diagnostic codes of a result, sorted."""
    return sorted(d.code for d in result.diagnostics)
