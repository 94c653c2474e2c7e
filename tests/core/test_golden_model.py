"""Golden model dumps for a few rich files, compared byte for byte (UPDATE_GOLDEN=1 rewrites)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from iface.forms.dump import dump_interface

from ..conftest import in_two_processes
from .helpers import DATA, compile_file

GOLDEN = Path(__file__).parent / "golden"
CASES = ["listing1.iface", "mini_robot.iface", "ros_types.iface", "thrift_features.thrift"]


@pytest.mark.parametrize("name", CASES)
def test_model_dump_matches_golden(name: str) -> None:
    comp = compile_file(DATA / "valid" / name)
    text = json.dumps(dump_interface(comp.interface), indent=2, ensure_ascii=False) + "\n"
    golden = GOLDEN / (name + ".json")
    if os.environ.get("UPDATE_GOLDEN") == "1":
        golden.write_text(text, encoding="utf-8")
    assert golden.read_text(encoding="utf-8") == text


def test_dump_is_deterministic_across_hash_seeds() -> None:
    one, two = in_two_processes("import json, sys\nfrom iface.semantics.compile import Workspace\n"
                                "from iface.forms.dump import dump_interface\n"
                                "print(json.dumps(dump_interface(Workspace().compile_path(sys.argv[1]).interface)))",
                                str(DATA / "valid" / "ros_types.iface"))
    assert one == two and '"name"' in one
