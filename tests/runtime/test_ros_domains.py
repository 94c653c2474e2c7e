"""Two test runs side by side never share a ROS_DOMAIN_ID (their nodes have the same names)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TAKE = ("import sys; sys.path.insert(0, sys.argv[1]); from tests.ros_harness.ros import free_domain; "
        "print(' '.join(str(free_domain()) for _ in range(60)), flush=True); sys.stdin.read()")


def test_runs_side_by_side_take_disjoint_domains() -> None:
    """Three processes that each ask for 60 domains, one after the other: none holds more than its share, so the
    last still finds free ones (taking one per request, the first two held all 101 and the third took random
    ones, shared with theirs)."""
    runs: list[subprocess.Popen[str]] = []
    taken: list[set[int]] = []
    try:
        for _ in range(3):
            run = subprocess.Popen([sys.executable, "-c", TAKE, str(ROOT)], stdin=subprocess.PIPE,
                                   stdout=subprocess.PIPE, text=True)
            runs.append(run)
            assert run.stdout is not None
            taken.append(set(map(int, run.stdout.readline().split())))
    finally:
        for run in runs:
            run.communicate("", timeout=30)
    assert len(taken) == 3 and all(domains and domains <= set(range(1, 102)) for domains in taken)
    for i, j in ((0, 1), (0, 2), (1, 2)):
        assert not taken[i] & taken[j], f"runs {i} and {j} share domains {sorted(taken[i] & taken[j])}"
