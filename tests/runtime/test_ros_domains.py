"""Two test runs side by side never share a ROS_DOMAIN_ID (their nodes have the same names)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TAKE = ("import sys; sys.path.insert(0, sys.argv[1]); from tests.ros_harness.ros import free_domain; "
        "print(' '.join(str(free_domain()) for _ in range(50)), flush=True); sys.stdin.read()")


def test_two_runs_take_disjoint_domains() -> None:
    runs = [subprocess.Popen([sys.executable, "-c", TAKE, str(ROOT)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                             text=True) for _ in range(2)]
    try:
        taken = [set(map(int, run.stdout.readline().split())) for run in runs if run.stdout]
    finally:
        for run in runs:
            run.communicate("", timeout=30)
    assert len(taken) == 2 and all(domains <= set(range(1, 102)) for domains in taken)
    assert not taken[0] & taken[1], f"shared domains {sorted(taken[0] & taken[1])}"
