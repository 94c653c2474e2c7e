"""Drive the component manager through the acceptance scenario and report each step (run in a ROS 2 environment).

    python drive_manager.py CONFIG.json --out RESULT.json --logs DIR

Started by tests/runtime/test_manager.py with the ROS runtime's Python. The managers run as a user
runs them (``iface-lsp manager``, each in a session of its own, stopped by its own handle); the
clients are the real CLI (``iface-lsp system ...``); this driver's own node only polls the status,
sets a value and reads states back. Every wait is bounded.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the checkout: tests.ros_harness
from tests.ros_harness import ros2cli
from tests.ros_harness.probe import ManagerStatus, Probe, Report, check, import_interface, run
from tests.ros_harness.standby_probe import logged, ready_standby

SYSTEM_KEYS = {"instances", "findings"}
INSTANCE_KEYS = {"name", "node", "component", "state", "pid", "restarts", "interface_hash", "last_snapshot",
                 "container"}


class Manager:
    """``iface-lsp manager`` started in a session of its own, output to a log."""

    def __init__(self, cfg: dict[str, Any], logs: Path, label: str) -> None:
        self.label = label
        self.log_path = logs / f"{label}.log"
        self._log = open(self.log_path, "w")  # noqa: SIM115 - closed in stop()
        argv = [cfg["python"], "-m", "iface", "manager", cfg["system"], "--state-dir", cfg["state"],
                "--trust-store", cfg["store"], "--max-restarts", "2", "--heartbeat-timeout", "10", "--grace", "2"]
        self.proc = subprocess.Popen(argv, env=cfg["env"], stdout=self._log, stderr=subprocess.STDOUT,
                                     start_new_session=True)

    def log(self) -> str:
        self._log.flush()
        return self.log_path.read_text(errors="replace")

    def kill(self) -> None:
        os.kill(self.proc.pid, signal.SIGKILL)
        self.proc.wait(timeout=30)
        self._log.close()

    def terminate(self, timeout: float) -> int | None:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        try:
            return self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            return None

    def stop(self) -> None:
        if self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait(timeout=30)
        if not self._log.closed:
            self._log.close()


#: Only processes whose environment holds this folder (the test's own, in ROS_LOG_DIR) are looked at or
#: stopped: the instances run from the session's shared workspace, so their command lines do not name it.
OWN = ""


def node_processes(node: str, standby: bool | None = False) -> list[int]:
    """The pids of this test's processes started for ``node``: not standbys (``--standby``), only standbys
    (``standby=True``) or both (``None``)."""
    return ros2cli.node_processes(node, OWN, standby) if OWN else []


def command_line(pid: int) -> str:
    """The command line of ``pid``, its parts joined by spaces ("" when it is gone)."""
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
    except OSError:
        return ""


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("config", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--logs", type=Path, required=True)
    a = ap.parse_args()
    cfg = json.loads(a.config.read_text())
    global OWN
    OWN = cfg["own"]
    a.logs.mkdir(parents=True, exist_ok=True)
    flags = Path(cfg["env"]["IFACE_TEST_FLAGS"])
    report = Report(a.out)
    from thermostat_msgs.srv import SetPoint

    probe = Probe()
    managers: list[Manager] = []
    # stopped from outside (run_bounded's SIGTERM): still stop what this driver started
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))

    status = ManagerStatus(probe)
    settle = status.settle

    def all_active(s: dict[str, Any]) -> bool:
        return len(s) == 3 and all(i.state == "active" for i in s.values())

    def saved(node: str) -> dict[str, Any]:
        service = f"{node}/save_state"
        types = probe.wait_until(lambda: next((t for n, t in probe.node.get_service_names_and_types()
                                               if n == service and t), None), 30, service)
        save_t = import_interface(types[0])
        answer = probe.call(save_t, service, save_t.Request(timeout_sec=5.0), timeout=30, idempotent=True)
        check(answer.success, f"save_state of {node}: {answer.message}")
        return json.loads(answer.state)["values"]

    def cli(*args: str, timeout: float = 240) -> tuple[int, str, str]:
        cmd = [cfg["python"], "-m", "iface", "system", *args]
        done = subprocess.run(cmd, env=cfg["env"], capture_output=True, text=True, timeout=timeout, check=False)
        with (a.logs / "cli.log").open("a") as f:
            f.write(f"$ {' '.join(cmd)}\nexit {done.returncode}\n{done.stdout}\n{done.stderr}\n")
        return done.returncode, done.stdout, done.stderr

    def replace(new_iface: str, package: str) -> tuple[int, dict[str, Any]]:
        code, out, err = cli("replace", cfg["system"], "thermostat", "--new", new_iface, "--package", package,
                             "--timeout", "4")
        try:
            return code, json.loads(out)
        except ValueError:
            raise AssertionError(f"not one JSON record (exit {code}): {out[-500:]} {err[-500:]}") from None

    before: dict[str, Any] = {}

    try:
        def up() -> str:
            managers.append(Manager(cfg, a.logs, "manager1"))
            s = settle(all_active, 180, "every instance active")
            for name, inst in s.items():
                check(inst.interface_hash == cfg["hashes"][name], f"{name}: hash {inst.interface_hash}")
                check(inst.node == f"/{name}" and inst.pid > 0, f"{name}: node {inst.node} pid {inst.pid}")
            log = managers[0].log()
            order = [log.find(f"{n}: active") for n in ("sensor", "thermostat", "spare")]
            check(-1 not in order and order == sorted(order), f"not brought up in order: {order}")
            code, out, err = cli("status", cfg["system"], "--format", "json")
            check(code == 0, f"status exit {code}: {err}")
            data = json.loads(out)
            check(set(data) == SYSTEM_KEYS, f"keys {sorted(data)}")
            check(all(set(i) == INSTANCE_KEYS for i in data["instances"]), f"instance keys {data['instances']}")
            check(all(i["container"] is None for i in data["instances"]), "an instance in a container: none has one")
            check([i["name"] for i in data["instances"]] == ["sensor", "thermostat", "spare"], "order")
            code, page, err = cli("status", cfg["system"], "--format", "html")
            check(code == 0 and "<svg" in page and "thermostat [active]" in page and "<script" not in page,
                  f"html: exit {code} {err}")
            return f"up in order {order}; {', '.join(f'{n} pid {i.pid}' for n, i in s.items())}"

        if not report.step("up: every instance active in order, status with its hash (json, html)", up):
            return 1

        def snapshot() -> str:
            answer = probe.call(SetPoint, "/thermostat/set_point", SetPoint.Request(celsius=23.5), timeout=30)
            check(answer.accepted, "set point not accepted")
            code, out, err = cli("snapshot", cfg["system"])
            check(code == 0, f"snapshot exit {code}: {err}")
            files = json.loads(out)["files"]
            mine = [f for f in files if "/thermostat/" in f]
            check(len(files) == 3 and mine, f"files {files}")
            values = json.loads(Path(mine[0]).read_text())["values"]
            check(values["set_point"] == 23.5, f"snapshot values {values}")
            first = status()["thermostat"].last_snapshot
            s = settle(lambda s: s["thermostat"].last_snapshot > first, 30, "a periodic snapshot (1 s)")
            return f"{mine[0]}; periodic {first} -> {s['thermostat'].last_snapshot}"

        report.step("snapshot: on request, and per the instance's period", snapshot)

        def crash() -> str:
            old = status()["thermostat"]
            start = time.monotonic()
            os.kill(old.pid, signal.SIGKILL)
            s = settle(lambda s: s["thermostat"].state == "active" and s["thermostat"].pid not in (0, old.pid)
                       and s["thermostat"].restarts == old.restarts + 1, 90, "thermostat restarted")
            took = time.monotonic() - start
            values = saved("/thermostat")
            check(values["set_point"] == 23.5, f"state after the restart {values}")
            check(node_processes("thermostat") == [s["thermostat"].pid], f"{node_processes('thermostat')}")
            return f"active again with set_point 23.5 after {took:.2f} s; restarts {s['thermostat'].restarts}"

        report.step("kill -9 of an instance: active again with its last snapshot, restart counted", crash)

        def adopt() -> str:
            before.update({n: i.pid for n, i in status().items()})
            managers[0].kill()
            managers.append(Manager(cfg, a.logs, "manager2"))
            s = settle(all_active, 120, "managed again")
            check({n: i.pid for n, i in s.items()} == before, f"pids {before} -> {({n: i.pid for n, i in s.items()})}")
            for name, pid in before.items():
                check(node_processes(name) == [pid], f"{name}: processes {node_processes(name)}")
            log = managers[1].log()
            check(log.count("adopted pid") == 3, f"manager2 adopted {log.count('adopted pid')} instances")
            return f"all 3 adopted, none started twice: {before}"

        report.step("kill -9 of the manager: a new one manages every instance again, none started twice", adopt)

        def refused_compat() -> str:
            code, record = replace(cfg["bad_iface"], cfg["package"])
            check(code == 1 and record["result"] == "refused", f"exit {code} {record.get('result')}")
            check(any(st["step"] == "compat" and not st["ok"] for st in record["steps"]), f"{record['steps']}")
            s = status()["thermostat"]
            check(s.pid == before["thermostat"] and s.node == "/thermostat" and s.state == "active", "changed")
            check(not node_processes("thermostat_2"), "NEW was started")
            return record["steps"][-1]["detail"]

        report.step("replace refused by compat: nothing changes", refused_compat)

        def refused_trust() -> str:
            code, record = replace(cfg["new_iface"], cfg["unsigned"])
            check(code == 1 and record["result"] == "refused", f"exit {code} {record.get('result')}")
            check("not trusted" in json.dumps(record["steps"]), f"{record['steps']}")
            s = status()["thermostat"]
            check(s.pid == before["thermostat"] and s.state == "active", "changed")
            check(not node_processes("thermostat_2"), "NEW was started")
            return record["steps"][-1]["detail"]

        report.step("replace refused by trust: nothing changes", refused_trust)

        def rolled_back() -> str:
            (flags / "thermostat_2.crash").touch()
            code, record = replace(cfg["new_iface"], cfg["package"])
            (flags / "thermostat_2.crash").unlink()
            check(code == 1 and record["result"] == "rolled_back", f"exit {code} {record.get('result')} "
                                                                  f"{record.get('steps')}")
            s = status()["thermostat"]
            check(s.pid == before["thermostat"] and s.node == "/thermostat" and s.state == "active", f"{s}")
            values = saved("/thermostat")
            check(values["set_point"] == 23.5, f"OLD's state {values}")
            probe.wait_until(lambda: not node_processes("thermostat_2"), 30, "NEW's process gone")
            return f"OLD active again with set_point {values['set_point']}: {record['steps'][-1]['detail']}"

        report.step("replace rolled back when NEW crashes on activate: OLD active with its state", rolled_back)

        def replaced() -> str:
            code, record = replace(cfg["new_iface"], cfg["package"])
            check(code == 0 and record["result"] == "replaced", f"exit {code} {record}")
            check(record["state_after"]["set_point"] == 23.5, f"state after {record['state_after']}")
            s = status()["thermostat"]
            check(s.node == "/thermostat_2" and s.state == "active" and s.pid != before["thermostat"], f"{s}")
            check(s.interface_hash == cfg["hashes"]["thermostat"] and s.component == "thermostat",
                  f"{s.component} {s.interface_hash}")
            check(saved("/thermostat_2")["set_point"] == 23.5, "state not carried")
            probe.wait_until(lambda: not node_processes("thermostat"), 30, "OLD's process gone")
            others = status()
            for name in ("sensor", "spare"):
                check(others[name].pid == before[name] and others[name].restarts == 0,
                      f"{name} was restarted during the replacements: {list(others[name].findings)}")
            return f"{s.node} pid {s.pid} active with set_point 23.5; the other instances untouched"

        report.step("replace accepted: NEW active with OLD's state", replaced)

        def runs(other: dict[str, str], node: str, pid: int) -> None:
            """The instance is ``other`` as ``node``, in process ``pid``: status, command line, state."""
            s = status()["thermostat"]
            check(s.node == f"/{node}" and s.state == "active" and s.pid == pid, f"{s}")
            check(s.component == other["component"] and s.interface_hash == other["hash"],
                  f"status says {s.component} {s.interface_hash}, not {other['component']} {other['hash']}")
            check(other["exe"] in command_line(pid), f"pid {pid} runs {command_line(pid)!r}, not {other['exe']}")
            check(saved(f"/{node}")["set_point"] == 23.5, "state not carried")
            code, out, err = cli("status", cfg["system"], "--format", "json")
            mine = next(i for i in json.loads(out)["instances"] if i["name"] == "thermostat")
            check(code == 0 and mine["component"] == other["component"] and mine["interface_hash"] == other["hash"],
                  f"system status: exit {code} {mine} {err}")

        def replaced_by(key: str, node: str) -> str:
            other = cfg[key]
            code, record = replace(other["iface"], other["package"])
            check(code == 0 and record["result"] == "replaced", f"exit {code} {record}")
            check(record["state_after"]["set_point"] == 23.5, f"state after {record['state_after']}")
            s = status()["thermostat"]
            runs(other, node, s.pid)
            previous = f"thermostat_{int(node.rsplit('_', 1)[1]) - 1}"
            probe.wait_until(lambda: not node_processes(previous), 30, "OLD's process gone")
            before["thermostat"] = s.pid
            start = next((st["detail"] for st in record["steps"] if st["step"] == "start NEW"), "")
            return f"/{node} pid {s.pid} runs {other['component']} ({command_line(s.pid)}), set_point 23.5; {start}"

        report.step("replace by another implementation: NEW's package and executable run, with OLD's state",
                    lambda: replaced_by("pro", "thermostat_3"))

        def crash_new() -> str:
            old = status()["thermostat"]
            os.kill(old.pid, signal.SIGKILL)
            s = settle(lambda s: s["thermostat"].state == "active" and s["thermostat"].pid not in (0, old.pid)
                       and s["thermostat"].restarts == old.restarts + 1, 90, "thermostat_3 restarted")
            runs(cfg["pro"], "thermostat_3", s["thermostat"].pid)
            check(node_processes("thermostat_3") == [s["thermostat"].pid], f"{node_processes('thermostat_3')}")
            for gone in ("thermostat", "thermostat_2"):
                check(not node_processes(gone), f"{gone} runs again: {node_processes(gone)}")
            before["thermostat"] = s["thermostat"].pid
            return f"thermostat_pro restarted as pid {s['thermostat'].pid} with set_point 23.5"

        report.step("kill -9 of NEW: the manager restarts NEW (not OLD) with its state", crash_new)

        def adopt_new() -> str:
            pids = {n: i.pid for n, i in status().items()}
            managers[-1].kill()
            managers.append(Manager(cfg, a.logs, "manager3"))
            s = settle(all_active, 120, "managed again")
            check({n: i.pid for n, i in s.items()} == pids, f"pids {pids} -> {({n: i.pid for n, i in s.items()})}")
            runs(cfg["pro"], "thermostat_3", pids["thermostat"])
            log = managers[-1].log()
            check(log.count("adopted pid") == 3 and "thermostat_pro, active" in log, f"manager3: {log[-2000:]}")
            return f"thermostat_pro (pid {pids['thermostat']}) adopted as NEW, none started twice"

        report.step("kill -9 of the manager: a new one adopts NEW", adopt_new)
        report.step("replace by another implementation with an interface package of another name",
                    lambda: replaced_by("eco", "thermostat_4"))

        def crash_standby() -> str:
            spare_pid = ready_standby("sensor", OWN)
            check(logged(managers[-1].log, f"sensor: started standby pid {spare_pid}"),
                  f"standby {spare_pid} not the manager's: {managers[-1].log()[-1500:]}")
            check(logged(managers[-1].log, f"sensor: standby pid {spare_pid} discovered"),
                  f"the manager did not see standby {spare_pid} in its graph: {managers[-1].log()[-1500:]}")
            code, out, err = cli("snapshot", cfg["system"], "sensor")
            check(code == 0, f"snapshot exit {code}: {err}")
            kept = json.loads(Path(json.loads(out)["files"][0]).read_text())["values"]["readings"]
            old = status()["sensor"]
            start = time.monotonic()
            os.kill(old.pid, signal.SIGKILL)
            s = settle(lambda s: s["sensor"].state == "active" and s["sensor"].pid not in (0, old.pid)
                       and s["sensor"].restarts == old.restarts + 1, 60, "sensor restarted")
            took = time.monotonic() - start
            check(s["sensor"].pid == spare_pid, f"sensor restarted as pid {s['sensor'].pid}, not its standby {spare_pid}")
            after = managers[-1].log().split(f"sensor: standby pid {spare_pid} told to start", 1)
            check(len(after) == 2 and "sensor: restored snapshot" in after[1] and "sensor: started pid" not in after[1],
                  f"manager log after the kill: {after[-1][:1500]}")
            readings = saved("/sensor")["readings"]
            check(readings >= kept, f"readings {readings} after the restart, {kept} in the last snapshot")
            check(not node_processes("sensor"), f"a process started for the sensor: {node_processes('sensor')}")
            following = ready_standby("sensor", OWN, other_than=(spare_pid,))
            return (f"standby pid {spare_pid} active as /sensor after {took:.2f} s with readings {readings} (snapshot "
                    f"{kept}); next standby pid {following}")

        report.step("kill -9 of an instance with a standby: its standby is the instance, with its state; another "
                    "follows", crash_standby)

        def crash_loop() -> str:
            (flags / "spare.crash").touch()
            pid = status()["spare"].pid
            os.kill(pid, signal.SIGKILL)
            s = settle(lambda s: s["spare"].state == "failed", 120, "spare past the restart limit")
            check(s["spare"].restarts == 2, f"restarts {s['spare'].restarts}")
            check(any("stays down" in f for f in s["spare"].findings), f"{list(s['spare'].findings)}")
            code, out, _ = cli("status", cfg["system"])
            (flags / "spare.crash").unlink()
            check(code == 1 and "stays down" in out, f"status exit {code}: {out}")
            return f"failed after {s['spare'].restarts} restarts; {list(s['spare'].findings)[-1]}"

        report.step("a crash loop stops at the intensity limit and is reported", crash_loop)

        def down() -> str:
            pids = {n: i.pid for n, i in status().items() if i.pid}
            code = managers[-1].terminate(90)
            check(code == 0, f"manager exit {code}")
            log = managers[-1].log()
            order = [log.find(f"{n}: down") for n in ("thermostat", "sensor")]
            check(-1 not in order and order == sorted(order), f"not down in reverse order: {order}")
            for name, pid in pids.items():
                check(not Path(f"/proc/{pid}").exists() or "Z" in Path(f"/proc/{pid}/stat").read_text().split()[2],
                      f"{name} pid {pid} still runs")
            check(not node_processes("sensor", standby=None), f"left: {node_processes('sensor', standby=None)}")
            return f"down in reverse order, exit 0 ({pids})"

        report.step("SIGTERM: down in reverse order, exit 0", down)

        def again() -> str:
            managers.append(Manager(cfg, a.logs, "manager4"))
            s = settle(all_active, 180, "every instance active again")
            runs(cfg["eco"], "thermostat_4", s["thermostat"].pid)
            code = managers[-1].terminate(90)
            check(code == 0, f"manager exit {code}")
            return f"thermostat_eco started as /thermostat_4 (pid {s['thermostat'].pid}) with set_point 23.5"

        report.step("a manager started again runs NEW, with its state", again)
    finally:
        for m in managers:
            m.stop()
        for name in ("sensor", "thermostat", "thermostat_2", "thermostat_3", "thermostat_4", "spare"):
            for pid in node_processes(name, standby=None):
                try:
                    os.killpg(pid, signal.SIGKILL)
                except OSError:
                    pass
        probe.close()
    return 0


if __name__ == "__main__":
    run(main)
