"""bench/suite_time.py reads a run's records (IFACE_TEST_CPU lines, JUnit report, run.json) into its figures."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path
from types import ModuleType

from tests.conftest import ROOT


def bench() -> ModuleType:
    spec = importlib.util.spec_from_file_location("suite_time", ROOT / "bench" / "suite_time.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["suite_time"] = module  # its dataclass looks its module up there
    spec.loader.exec_module(module)
    return module


JUNIT = """<?xml version="1.0" encoding="utf-8"?><testsuites><testsuite name="pytest" errors="0" failures="1"
skipped="2" tests="10" time="9.0"></testsuite></testsuites>"""


def records(folder: Path) -> Path:
    (folder / "cpu.gw0").write_text(  # from 1000.0: runtime/ 100 s, then 80 s
        "30.00\t100.00\ttests/runtime/test_launch.py::test_a[kilted]@tests/runtime/test_launch.py-kilted\t1000.00\n"
        "20.00\t80.00\ttests/runtime/test_launch.py::test_a[jazzy]@tests/runtime/test_launch.py-jazzy\t1100.00\n"
        "not a record\n", encoding="utf-8")
    (folder / "cpu.gw1").write_text(  # from 1000.0: another folder 60 s, then 2 s; the last one without a start
        "50.00\t60.00\ttests/core/test_every_command.py::test_x[a.iface]@tests/core/test_every_command.py\t1000.00\n"
        "1.00\t2.00\ttests/test_vscode_extension.py::test_npm\t1060.00\n"
        "1.00\t2.00\ttests/fmt/test_cli.py::test_old_record\n", encoding="utf-8")
    # the cores: 50 % idle in the first minute, 25 % in the second, 100 % in the third
    (folder / "machine.json").write_text(json.dumps([[1000.0, 0, 0], [1060.0, 60, 120], [1120.0, 90, 240],
                                                     [1180.0, 210, 360]]), encoding="utf-8")
    (folder / "junit.xml").write_text(JUNIT, encoding="utf-8")
    (folder / "run.json").write_text(json.dumps({
        "commit": "abc1234", "date": "2026-11-30 16:00 UTC", "exit": 1, "wall": 100.0, "user": 120.0,
        "system": 30.0, "cpu": 150.0, "cores": 2, "workers": "3", "load_before": "0.10 0.20 0.30",
        "load_after": "2.00 1.50 1.00"}), encoding="utf-8")
    return folder


def test_a_record_names_its_module_and_release() -> None:
    b = bench()
    test = b.parse_cpu_line("gw0", "1.50\t3.25\ttests/runtime/test_live.py::t[jazzy]@tests/runtime/test_live.py-jazzy"
                                   "\t1796050000.25")
    assert (test.cpu, test.wall, test.module, test.release, test.start) == \
        (1.5, 3.25, "tests/runtime/test_live.py", "jazzy", 1796050000.25)
    assert b.parse_cpu_line("gw0", "x\ty\tz") is None and b.parse_cpu_line("gw0", "") is None
    assert b.parse_cpu_line("main", "1\t2\ttests/fmt/test_cli.py::t").release == ""
    assert b.parse_cpu_line("main", "1\t2\ttests/fmt/test_cli.py::t").start is None
    assert b.folder_of("tests/runtime/test_live.py") == "runtime/"
    assert b.folder_of("tests/test_vscode_extension.py") == "test_vscode_extension.py"


def test_the_figures_of_a_kept_run(tmp_path: Path, capsys) -> None:
    assert bench().main(["--read", str(records(tmp_path))]) == 0
    out = capsys.readouterr().out
    assert "run: abc1234 2026-11-30 16:00 UTC, exit 1, 3 workers on 2 cores" in out
    assert "CPU 2.5 min (150 s, user 120 + system 30); cores idle 25%" in out
    assert "tests 10: 7 passed, 1 failed, 0 errors, 2 skipped" in out
    assert "in the tests: 244 worker-seconds, 102 CPU-seconds" in out
    lines = out.splitlines()
    row = {line.split("  ")[0].strip(): line.split()[-2:] for line in lines if "  " in line}
    assert row["runtime/"] == ["180", "50"] and row["core/"] == ["60", "50"]
    assert row["tests/runtime/test_launch.py [kilted]"] == ["100", "30"]
    assert row["tests/runtime/test_launch.py [jazzy]"] == ["80", "20"]
    assert row["worker gw0"] == ["180", "50"] and row["worker gw1"] == ["64", "52"]
    minutes = [line.split() for line in lines[lines.index(next(x for x in lines if x.strip().startswith("minute"))) + 1:]
               if line.strip() and line.split()[0].isdigit()]
    assert minutes == [["0", "50%", "1.0", "1.0"], ["1", "25%", "1.0", "0.0"], ["2", "100%", "1.0", "0.0"]]


def test_a_missing_folder_is_a_usage_error(tmp_path: Path, capsys) -> None:
    assert bench().main(["--read", str(tmp_path / "none")]) == 2
    assert "no such folder" in capsys.readouterr().err


def test_unreadable_records_are_said_in_one_line(tmp_path: Path, capsys) -> None:
    records(tmp_path)
    (tmp_path / "junit.xml").write_text("<testsuites", encoding="utf-8")
    assert bench().main(["--read", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "records not readable" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    (tmp_path / "junit.xml").write_text(JUNIT, encoding="utf-8")
    (tmp_path / "run.json").write_text("{}", encoding="utf-8")  # no figures of the run: its lines are left out
    assert bench().main(["--read", str(tmp_path)]) == 0
    for broken in ("[[1, 2]", "[[1000, 2], [1010, 3]]", "[1, 2]"):
        (tmp_path / "machine.json").write_text(broken, encoding="utf-8")
        assert bench().main(["--read", str(tmp_path)]) == 2


#: Lines as ``dump-acct`` prints them (acct 6.6): name, version, user and system ticks, elapsed, uid, gid, memory,
#: io, pid, ppid, flags, exit code, tty, start.
ACCT = """ros2            |v3|    74.00|     9.00|   162.00|     0|     0| 11394.00| 0.00|   12501|   12075|     |       0|__      |Tue Dec  1 02:10:05 2026
ros2            |v3|    80.00|    12.00|   171.00|     0|     0| 11394.00| 0.00|   12502|   12075|     |       0|__      |Tue Dec  1 02:10:07 2026
ros2            |v3|    60.00|     5.00|   150.00|     0|     0| 11394.00| 0.00|   12503|   12075|     |       0|__      |Tue Dec  1 02:10:09 2026
cc1plus         |v3|   822.00|   102.00|  1094.00|     0|     0| 51283.00| 0.00|   13228|   13227|     |       0|__      |Tue Dec  1 02:10:55 2026
bash            |v3|     0.00|     0.00|     0.00|     0|     0|  4488.00| 0.00|   10994|   10993| F   |       0|__      |Tue Dec  1 02:08:54 2026
not a record
"""


def test_processes_by_name_from_the_accounting_file() -> None:
    suite_time = bench()
    ended = [e for e in map(suite_time.parse_acct_line, ACCT.splitlines()) if e is not None]
    assert [(e.name, round(e.cpu, 2)) for e in ended] == [("ros2", 0.83), ("ros2", 0.92), ("ros2", 0.65),
                                                          ("cc1plus", 9.24), ("bash", 0.0)]
    lines = suite_time.by_name(ended, top=2)
    assert lines[0] == "processes by name (5 ended, 12 CPU-seconds)"
    assert lines[2].split() == ["cc1plus", "1", "9", "9.24"]
    assert lines[3].split() == ["ros2", "3", "2", "0.83"]  # 2.4 CPU-seconds, the median of three
    assert lines[4].split() == ["1", "others", "1", "0"]
