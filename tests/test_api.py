"""The Python API (docs/api.md): one Planner, many problems, the documents `plan --json` writes."""
import json
import os
import re
import subprocess
import sys

import pytest

from conftest import ROOT
from pdsketch_mech.api import PddlError, Planner


def steps(document):
    return [(step["name"], step["args"], step.get("mechanism")) for step in document["plan"]]


@pytest.fixture(scope="module")
def planner():
    return Planner("basis", mechanisms=["com"])


def test_the_example_in_the_docs_runs(capsys):
    with open(os.path.join(ROOT, "docs", "api.md"), encoding="utf-8") as handle:
        example = re.search(r"```python\n(.*?)```", handle.read(), re.S).group(1)
    exec(compile(example, "docs/api.md", "exec"), {})
    out = capsys.readouterr().out
    assert out.startswith("solved") and "no-such-problem: no such file" in out


def test_a_plan_is_the_same_whatever_was_planned_before_it_in_the_process(planner):
    first = planner.plan("com", timeout=120, seed=3)
    planner.plan("pick", timeout=120, seed=0)
    again = planner.plan("com", timeout=120, seed=3)
    assert first["status"] == again["status"] == "solved"
    assert steps(first) == steps(again) and first["plan"] == again["plan"]


def test_the_document_is_the_one_plan_json_writes(planner, tmp_path):
    out = tmp_path / "com.json"
    subprocess.run([sys.executable, "-m", "pdsketch_mech.plan", "basis", "com", "--mechanisms", "com",
                    "--seed", "3", "--json", str(out)], cwd=tmp_path, check=True, capture_output=True)
    written = json.loads(out.read_text())
    document = planner.plan("com", timeout=120, seed=3)
    assert set(written) == set(document)
    assert written["plan"] == json.loads(json.dumps(document["plan"]))


def test_replay_takes_a_document_or_a_file_and_refuses_another_problems_plan(planner, tmp_path):
    document = planner.plan("pick", timeout=60, seed=0, validate=True)
    assert document["replay"]["goal_reached"]
    path = tmp_path / "pick.json"
    path.write_text(json.dumps(document))
    assert planner.replay("pick", str(path))["goal_reached"]
    with pytest.raises(PddlError, match="made for problem"):
        planner.replay("com", document)


def test_bad_names_raise_one_clear_error():
    with pytest.raises(PddlError, match=r"hok: no such file, nor a shipped mechanism.*shipped: com, edge"):
        Planner("basis", mechanisms=["hok"])
    with pytest.raises(PddlError, match="basis.pdl: error: cannot read file"):
        Planner("basis.pdl")


@pytest.mark.slow
def test_bench_api_plans_and_replays_the_same_problems_both_ways():
    from pdsketch_mech.bench import api
    figures = api.measure_api("com", 2, 0, 120.0)
    assert len(figures["api_s"]) == len(figures["processes_s"]) == 2
    assert figures["api_total_s"] > 0 and figures["processes_total_s"] > 0
    assert api.report(figures)[0].startswith("api: 2 com problems")
