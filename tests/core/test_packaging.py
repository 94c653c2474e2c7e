"""The grammar ships inside the package: a plain (non-editable) install finds it."""

from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

from iface.nodes.shared import source_files

ROOT = Path(__file__).resolve().parents[2]


def test_wheel_contains_grammar_and_entry_points(tmp_path: Path) -> None:
    r = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q",
                        "-w", str(tmp_path), str(ROOT)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    (wheel,) = tmp_path.glob("iface-*.whl")
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())
        assert "iface/grammar.lark" in names
        assert z.read("iface/grammar.lark").decode() == (ROOT / "grammar.lark").read_text()
        ep = next(n for n in names if n.endswith("entry_points.txt"))
        text = z.read(ep).decode()
        assert "iface-lsp = iface.cli:main" in text and "[iface.targets]" in text
        # the runtime packages generate copies: every file of them, and nothing else (no byte-code cache)
        for runtime in ("iface_runtime_py", "iface_runtime_cpp"):
            prefix = f"iface/nodes/runtimes/{runtime}/"
            shipped = {n[len(prefix):]: z.read(n).decode() for n in names if n.startswith(prefix)}
            assert shipped == dict(source_files(runtime)), runtime
        # `ros2 iface` (issue 36): ros2cli finds the command, its verb group and the verbs by entry points
        assert "[ros2cli.command]\niface = iface.ros2_command:IfaceCommand" in text
        assert "[ros2cli.extension_point]\niface.verb = iface.ros2_command:VerbExtension" in text
        verbs = text.split("[iface.verb]\n", 1)[1].split("\n\n", 1)[0].splitlines()
        assert [v.split(" = ")[0] for v in verbs] == ["import", "replace", "snapshot", "status", "verify"]
        assert "iface/ros2_command.py" in names
