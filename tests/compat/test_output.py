"""JSON output against its schema, SARIF shape, contract, and byte-identical reruns."""

from __future__ import annotations

import json

import jsonschema
import pytest
from compat_support import DATA, HASH_SEEDS, cached, run_cli

from iface.compat import compare
from iface.compat.contract import contract
from iface.compat.report import SCHEMA_PATH, report_json

SCHEMA = json.loads(SCHEMA_PATH.read_text())
CASES = [("verdicts/arm_v1.iface", "verdicts/arm_v4.iface"), ("thrift/many/old.thrift", "thrift/many/new.thrift")]


def test_schema_is_valid() -> None:
    jsonschema.Draft202012Validator.check_schema(SCHEMA)


def test_every_fixture_report_matches_the_schema() -> None:
    validator = jsonschema.Draft202012Validator(SCHEMA)
    for folder in ("rules", "thrift"):
        for case in sorted(p for p in (DATA / folder).iterdir() if p.is_dir()):
            report = compare(cached(next(case.glob("old.*"))), cached(next(case.glob("new.*"))))
            validator.validate(report_json(report, str))
    system = [cached(DATA / "verdicts" / "monitor.iface")]
    validator.validate(report_json(compare(cached(DATA / "verdicts" / "arm_v1.iface"),
                                           cached(DATA / "verdicts" / "arm_v3.iface"), system), str))


@pytest.mark.parametrize(("old", "new"), CASES)
@pytest.mark.parametrize("fmt", ["text", "json", "sarif"])
def test_cli_output_is_deterministic(old: str, new: str, fmt: str) -> None:
    one, two = (run_cli("compat", old, new, "--format", fmt, hash_seed=seed) for seed in HASH_SEEDS)
    assert one.returncode == two.returncode == 1
    assert one.stdout == two.stdout and one.stdout
    if fmt == "json":
        data = json.loads(one.stdout)
        jsonschema.validate(data, SCHEMA)
        assert data["old"] == old and data["exit_code"] == 1
    if fmt == "sarif":
        run = json.loads(one.stdout)["runs"][0]
        assert json.loads(one.stdout)["version"] == "2.1.0"
        ids = [r["id"] for r in run["tool"]["driver"]["rules"]]
        for result in run["results"]:
            assert ids[result["ruleIndex"]] == result["ruleId"]
            assert result["level"] in ("error", "warning", "note")
            assert result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == new
            assert result["relatedLocations"][0]["physicalLocation"]["artifactLocation"]["uri"] == old


def test_contract() -> None:
    data = contract(cached(DATA / "verdicts" / "arm_v1.iface"))
    assumed = {(i["kind"], i["name"]) for i in data["assumptions"]}
    guaranteed = {(i["kind"], i["name"]) for i in data["guarantees"]}
    assert assumed == {("topic", "/arm/cmd"), ("parameter", "speed"), ("parameter", "retries"),
                       ("state", "moves"), ("state", "mode")}
    assert guaranteed == {("topic", "/arm/pose"), ("topic", "/arm/status"), ("service", "/arm/plan"),
                          ("state", "moves"), ("state", "mode")}
    speed = next(i for i in data["assumptions"] if i["name"] == "speed")
    assert speed == {"kind": "parameter", "name": "speed", "type": "float64", "default": "1.0", "unit": "m/s",
                     "range": [0.0, 3.0]}


def test_contract_cli() -> None:
    done = run_cli("contract", "verdicts/planner.iface")
    assert done.returncode == 0
    assert done.stdout == ("contract of planner 1.0: C = (A, G)\nA (assumptions):\n"
                           '  subscribes arm_msgs/Pose on "/arm/pose" (reliability=reliable)\n'
                           '  calls arm_msgs/Plan on "/arm/plan"\nG (guarantees):\n  publishes arm_msgs/Cmd on "/arm/cmd"\n')
