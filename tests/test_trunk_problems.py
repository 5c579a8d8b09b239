"""Problems written fresh for the trunk's failure classes (thin and heavy picks, into a bowl,
onto a plate, a tower, a disjunctive goal) plan from the command line and their saved plans
replay in a fresh world; the end-to-end Edge and Hook tasks, which step physics while
holding and pushing, do too (slow). A planner that finds a skeleton refinement which does
not replay keeps searching and counts it."""
import glob
import json
import os

import pytest

from pdsketch_mech.commands import plan
from pdsketch_mech.commands import replay as replay_command
from pdsketch_mech.lang.loader import load_domain, load_problem
from pdsketch_mech.planner import bilevel
from pdsketch_mech.planner.execute import ExecutionResult
from pdsketch_mech.world.build import build_world

from conftest import DATA, ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")
HOOK_USE = os.path.join(ROOT, "domains", "mechanisms", "hook-use.pddl")
TRUNK = sorted(glob.glob(os.path.join(DATA, "trunk", "*.pddl")))


def plan_and_replay(domain, problem, tmp_path, capsys, *extra):
    """The plan document of `problem`, planned from the command line (solved) and replayed
    from its file in a fresh world (the goal holds at the end)."""
    out = tmp_path / "plan.json"
    status = plan.main([domain, problem, "--json", str(out), "--timeout", "300", *extra])
    err = capsys.readouterr().err
    assert status == 0, err
    document = json.loads(out.read_text())
    assert replay_command.main([problem, str(out), domain]) == 0, capsys.readouterr().err
    return document


@pytest.mark.parametrize("problem", TRUNK, ids=[os.path.basename(p)[:-5] for p in TRUNK])
def test_trunk_problem_plans_and_replays(problem, tmp_path, capsys):
    plan_and_replay(BASIS, problem, tmp_path, capsys)


@pytest.mark.slow
def test_edge_with_basis_operators_plans_and_replays(tmp_path, capsys):
    document = plan_and_replay(BASIS, os.path.join(ROOT, "problems", "edge.pddl"), tmp_path, capsys, "--basis-only")
    assert [s["name"] for s in document["plan"]][-1] == "grasp"


@pytest.mark.slow
def test_hook_use_plans_and_replays(tmp_path, capsys):
    document = plan_and_replay(HOOK_USE, os.path.join(ROOT, "problems", "hook-use.pddl"), tmp_path, capsys)
    assert "move-cont" in [s["name"] for s in document["plan"]]


def test_a_refinement_that_does_not_replay_is_rejected_and_the_search_goes_on(monkeypatch):
    calls = []
    real = bilevel.execute_plan

    def first_fails(task, problem, entries, recorder=None, vocabulary=None):
        calls.append(len(entries))
        if len(calls) == 1:
            return ExecutionResult(False, "the goal does not hold at the end")
        return real(task, problem, entries, recorder)

    monkeypatch.setattr(bilevel, "execute_plan", first_fails)
    domain, problem = load_problem(os.path.join(ROOT, "problems", "pick.pddl"), [load_domain([BASIS])])
    with build_world(problem) as world:
        result = bilevel.bilevel_plan(domain, problem, world, timeout=60, seed=0)
    assert result.status == "solved" and len(calls) == 2
    assert result.stats["rejected"] == 1
    assert "rejected: in a fresh world, the goal does not hold at the end" in result.stats["failures"]
