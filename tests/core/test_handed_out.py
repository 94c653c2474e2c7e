"""The order in which the workers get the modules (tests/conftest.py, ``handed_out``): ROS modules, which mostly
wait, two for each one that computes, so that two cores stay busy."""

from __future__ import annotations

from tests.conftest import CPP_FIRST, LONG, ROOT, SHORT, WAITING_PER_COMPUTING, handed_out

GROUPS = [
    "tests/core/test_cli.py", "tests/core/test_every_command.py", "tests/emit/test_reserved_names.py",
    "tests/lsp/test_limits.py", "tests/fmt/test_cli.py",
    "tests/runtime/test_launch.py-kilted", "tests/runtime/test_launch.py-jazzy", "tests/runtime/test_launch.py",
    "tests/runtime/test_manager.py-kilted", "tests/runtime/test_manager.py-jazzy",
    "tests/runtime/test_rclcpp_e2e.py-kilted", "tests/runtime/test_live_offline.py",
]


def test_every_group_once() -> None:
    assert sorted(handed_out(GROUPS)) == sorted(GROUPS)
    assert handed_out([]) == []


def test_a_cpp_builder_first_then_the_longest_that_computes() -> None:
    order = handed_out(GROUPS)
    assert order[0] == "tests/runtime/test_rclcpp_e2e.py-kilted"
    assert order[1] == "tests/core/test_every_command.py"
    assert sum(not g.startswith("tests/runtime/") for g in order[:3]) == 1  # the three workers' first groups


def test_one_release_after_the_other_so_that_a_worker_changes_release_once() -> None:
    order = handed_out(GROUPS)
    jazzy = [i for i, g in enumerate(order) if g.endswith("-jazzy")]
    kilted = [i for i, g in enumerate(order) if g.endswith("-kilted")]
    assert jazzy and kilted and max(kilted) < min(jazzy)


def test_two_worker_seconds_waiting_for_each_one_computing_while_both_last() -> None:
    def seconds(group: str) -> float:
        if group == "tests/runtime/test_launch.py":  # its tests that run once, not per release
            return SHORT
        return LONG.get(group.split(".py")[0] + ".py", SHORT)

    order = handed_out(GROUPS)
    waited = computed = 0.0
    for group in order:
        if group.startswith("tests/runtime/"):
            assert waited <= WAITING_PER_COMPUTING * computed or group == order[0] or \
                all(g.startswith("tests/runtime/") for g in order[order.index(group):]), (group, waited, computed)
            waited += seconds(group)
        else:
            assert waited > WAITING_PER_COMPUTING * computed or \
                all(not g.startswith("tests/runtime/") for g in order[order.index(group):]), (group, waited, computed)
            computed += seconds(group)


def test_the_tables_name_modules_that_exist() -> None:
    for module in (*LONG, *CPP_FIRST):
        assert (ROOT / module).is_file(), module
