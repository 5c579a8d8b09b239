"""Basis operators change the contact graph as their effects say; the bilevel planner solves
manipulation problems end to end, and its plans replay in a fresh world."""
import glob
import json
import os
import time

import numpy as np
import pytest

from pdsketch_mech.commands import plan
from pdsketch_mech.lang.loader import load_domain, load_problem
from pdsketch_mech.operators import basis
from pdsketch_mech.planner.bilevel import bilevel_plan
from pdsketch_mech.planner.replay import replay
from pdsketch_mech.planner.serialize import plan_entries
from pdsketch_mech.samplers.contact import sample_contacts
from pdsketch_mech.samplers.grasp import sample_grasps
from pdsketch_mech.samplers.placement import sample_placements
from pdsketch_mech.samplers.trajectory import grasp_motion, place_motion, push_motion
from pdsketch_mech.world.build import build_world
from pdsketch_mech.world.contacts import read_contacts

from conftest import ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")


def problem_path(name):
    return os.path.join(ROOT, "problems", name + ".pddl")


def loaded(name):
    return load_problem(problem_path(name), [load_domain([BASIS])])


def first(generator, make_trajectory):
    """The first sample whose trajectory can be planned."""
    for value in generator:
        trajectory = make_trajectory(value)
        if trajectory is not None:
            return value, trajectory
    raise AssertionError("no feasible sample")


def test_grasp_then_place_change_the_contact_graph():
    rng = np.random.default_rng(0)
    _, problem = loaded("pick-place")
    with build_world(problem) as world:
        world.settle()
        grasp, trajectory = first(sample_grasps(world, "block", rng), lambda g: grasp_motion(world, "block", g, rng))
        assert basis.grasp(world, "block", grasp, trajectory).ok
        graph = read_contacts(world)
        assert graph.holding == "block" and ("block", "table") not in graph.support
        held = world.snapshot()
        landed = []
        for placement in sample_placements(world, "block", "plate", rng):
            trajectory = place_motion(world, placement, rng)
            if trajectory is None:
                continue
            if not basis.place(world, "block", placement, trajectory).ok:  # e.g. no retreat
                world.restore(held)
                continue
            graph = read_contacts(world)
            assert graph.holding is None
            assert ("block", "plate") in graph.support or ("block", "table") in graph.support
            landed.append(("block", "plate") in graph.support)  # on the dish's sloped rim it slides off
            if landed[-1] or len(landed) == 5:
                break
            world.restore(held)  # holding again before the sampler's next draw
        assert landed[-1], "none of 5 placements stayed on the plate"


def test_push_moves_the_object_and_keeps_its_support():
    rng = np.random.default_rng(1)
    _, problem = loaded("pick")
    with build_world(problem) as world:
        world.settle()
        before = np.array(world.pose("block")[0])
        contact, trajectory = first(sample_contacts(world, "block", "table", rng),
                                    lambda c: push_motion(world, c, rng))
        assert basis.push(world, contact, trajectory).ok
        moved = np.array(world.pose("block")[0]) - before
        assert np.linalg.norm(moved[:2]) > 0.02                       # pushed at least 2 cm
        assert np.dot(moved[:2], contact.direction[:2]) > 0          # along the push
        assert ("block", "table") in read_contacts(world).support


@pytest.mark.parametrize("name", ["pick", "pick-place", "stack"])
def test_planner_solves_and_the_plan_replays(name):
    domain, problem = loaded(name)
    with build_world(problem) as world:
        result = bilevel_plan(domain, problem, world, timeout=60, seed=0)
    assert result.status == "solved", result.stats
    entries = json.loads(json.dumps(plan_entries(result.steps, result.values)))  # through JSON, as a saved plan would be
    replayed = replay(domain, problem, entries)
    assert replayed.goal_reached, replayed.message


def test_impossible_goal_is_unsolved_within_the_timeout(write_files):
    # The box is beyond the arm's reach and there is no mechanism to use the hook.
    domain, problem = load_problem(problem_path("hook-use"), [load_domain([BASIS])])
    start = time.perf_counter()
    with build_world(problem) as world:
        result = bilevel_plan(domain, problem, world, timeout=8, seed=0)
    assert result.status == "unsolved"
    assert time.perf_counter() - start < 8 + 3


def test_plan_command_json_and_render(tmp_path, capsys):
    out, gif = tmp_path / "plan.json", tmp_path / "plan.gif"
    status = plan.main([BASIS, problem_path("pick"), "--seed", "3", "--json", str(out), "--render", str(gif),
                        "--timeout", "60"])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    lines = captured.out.splitlines()
    assert lines[-1].startswith("(grasp block table ")
    document = json.loads(out.read_text())
    assert document["status"] == "solved" and document["seed"] == 3
    step = document["plan"][-1]
    assert {v["type"] for v in step["params"].values()} == {"grasp", "trajectory"}
    assert document["stats"]["samples"]["grasp"] >= 1
    assert gif.stat().st_size > 10000 and "the goal holds" in captured.err


def test_replay_command(tmp_path, capsys):
    out = tmp_path / "plan.json"
    assert plan.main([BASIS, problem_path("pick"), "--json", str(out), "--timeout", "60"]) == 0
    from pdsketch_mech.commands import replay as replay_command
    assert replay_command.main([problem_path("pick"), str(out)]) == 0
    assert "the goal holds" in capsys.readouterr().err
    document = json.loads(out.read_text())
    document["plan"] = []  # an empty plan does not reach the goal
    out.write_text(json.dumps(document))
    assert replay_command.main([problem_path("pick"), str(out)]) == 1
    out.write_text("{not json")
    assert replay_command.main([problem_path("pick"), str(out)]) == 2


def test_same_seed_same_plan_across_processes(tmp_path):
    import subprocess
    import sys
    documents = []
    for i in range(2):
        out = tmp_path / f"plan{i}.json"
        subprocess.run([sys.executable, "-m", "pdsketch_mech.plan", BASIS, problem_path("stack"), "--seed", "5",
                        "--json", str(out)], cwd=ROOT, check=True, capture_output=True)
        documents.append(json.loads(out.read_text()))
    assert documents[0]["plan"] == documents[1]["plan"] and documents[0]["status"] == "solved"
    assert documents[0]["stats"]["sim_steps"] > 0


def test_goal_already_true_gives_an_empty_plan(write_files, capsys):
    text = open(problem_path("pick")).read().replace("(:goal (holding block))", "(:goal (support block table))")
    (path,) = write_files(**{"p.pddl": text})
    assert plan.main([BASIS, path, "--timeout", "30"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.startswith("solved: 0 steps")


def test_scene_contradicting_init_is_reported(write_files, capsys):
    text = open(problem_path("stack")).read().replace("(support a table)", "(support a b)")
    (path,) = write_files(**{"p.pddl": text})
    status = plan.main([BASIS, path, "--timeout", "5"])
    err = capsys.readouterr().err
    assert status == 1  # symbolically the goal holds at :init: the only skeleton is the empty plan, which the scene refutes
    assert "warning: the scene and :init disagree: (support a b) is not true in the scene" in err


@pytest.mark.slow
def test_a_problem_whose_first_skeletons_are_all_unrefinable_is_still_solved():
    """Completeness (planner/schedule.py): the first three skeletons put a block on blocks
    beyond reach, and their placements never find a value, yet none of them is ever found
    dead (the block they place was grasped first). Every skeleton keeps a share of the work,
    so the fourth, which stacks another block within reach, gets its turn."""
    path = os.path.join(ROOT, "tests", "data", "first-skeletons-unrefinable.pddl")
    domain, problem = load_problem(path, [load_domain([BASIS])])
    with build_world(problem) as world:
        result = bilevel_plan(domain, problem, world, timeout=120, seed=0)
    assert result.status == "solved"
    assert [(s.name, s.args[:2]) for s in result.steps] == [("grasp", ("b", "table")), ("place", ("b", "a"))]
    log = result.stats["skeleton_log"]
    unrefinable = [e for e in log if "(place a far" in e["skeleton"]]
    assert len(unrefinable) == 3 and all(e["effort"] > 0 for e in unrefinable)
    assert log[-1]["rank"] == 4


def test_a_first_step_that_looks_dead_for_its_first_visits_is_revisited_and_the_problem_solved(monkeypatch):
    """Completeness through the dead-step path (docs/planner.md): the block's grasps find no
    value on their first four visits, so the grasp is believed dead where the block lies and
    every skeleton that begins with it is set aside. The belief is revisited once the work
    has doubled; the grasp then works and the plan is found."""
    from pdsketch_mech.planner.bindings import StepSampler
    real = StepSampler.samples
    dry = {"visits": 0}

    def unlucky_first_visits(self, world, step, rng, parents=None, per_value=1):
        if step.operator == "grasp" and dry["visits"] < 4:
            dry["visits"] += 1
            return iter(())
        return real(self, world, step, rng, parents, per_value)
    monkeypatch.setattr(StepSampler, "samples", unlucky_first_visits)
    domain, problem = load_problem(os.path.join(ROOT, "problems", "pick.pddl"), [load_domain([BASIS])])
    with build_world(problem) as world:
        result = bilevel_plan(domain, problem, world, timeout=120, seed=0)
    assert result.status == "solved" and [s.name for s in result.steps][-1] == "grasp"
    stats = result.stats
    assert stats["revived"] >= 1 and stats["returned"] >= 1 and stats["pruned"] >= 1   # set aside, then back
    assert not stats["dead_steps"]                                                      # cleared for good


def _plan_with(problem_path, paths, mechanisms):
    domain, problem = load_problem(problem_path, [load_domain(paths)])
    with build_world(problem) as world:
        return bilevel_plan(domain, problem, world, timeout=120, seed=0, use_mechanisms=mechanisms)


def test_with_mechanisms_loaded_the_basis_operators_search_runs_as_it_does_alone():
    """The contract by construction (docs/planner.md, "Two searches side by side"): with every
    shipped mechanism loaded on a scene that needs none (two objects swap plates), the basis
    operators' own search creates the skeletons `--basis-only` creates and gives each the
    same work, and the whole run stays within head_start + W / plain_share (+ one slice)."""
    from pdsketch_mech.planner.budget import DEFAULT_BUDGET as budget
    path = os.path.join(ROOT, "problems", "contract", "scene-swap-plates.pddl")
    every = sorted(glob.glob(os.path.join(ROOT, "domains", "mechanisms", "*.pddl")))
    alone = _plan_with(path, [BASIS], False)
    both = _plan_with(path, [BASIS] + every, True)
    assert alone.status == both.status == "solved"
    plain = [(e["skeleton"], e["effort"]) for e in both.stats["skeleton_log"] if e["search"] == "basis"]
    assert plain == [(e["skeleton"], e["effort"]) for e in alone.stats["skeleton_log"]]
    assert both.stats["plain_work"] == alone.stats["work"]
    assert any(e["search"] == "mechanisms" for e in both.stats["skeleton_log"])   # the mechanisms had their turn
    assert both.stats["work"] <= budget.head_start + alone.stats["work"] / budget.plain_share + budget.slice


@pytest.mark.slow
def test_a_users_mechanism_that_does_not_apply_costs_at_most_the_plain_share_of_the_work():
    """On a Slope-and-Blocker scene the basis operators solve (the blocker on the slope,
    then the block against it), a user's shelf pull is loaded whose skeletons (the blocker
    on the slope, then pull the block onto it) look as short and never keep their promise:
    the plan comes within head_start + W / plain_share units, W the basis operators' own."""
    from pdsketch_mech.planner.budget import DEFAULT_BUDGET as budget
    path = os.path.join(ROOT, "problems", "contract", "dev-slope-blocker-15.pddl")
    user = os.path.join(ROOT, "problems", "contract", "user-mechanism", "shelf-pull.mech.pddl")
    alone, both = _plan_with(path, [BASIS], False), _plan_with(path, [user], True)
    assert alone.status == both.status == "solved"
    assert both.stats["mechanisms"]["shelf-pull"]["skeletons"] >= 1   # it was tried
    assert both.stats["work"] <= budget.head_start + alone.stats["work"] / budget.plain_share + budget.slice
