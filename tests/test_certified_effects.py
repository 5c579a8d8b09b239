"""A mechanism's certified facts are its effect: the outcome of a push or a release that
physics decides (a box pushed across a gap, a block let go on a ramp it slides off) plans, and
the paper's six mechanisms are unchanged by it (their steps already achieve what they certify)."""
from __future__ import annotations

import glob
import json
import os

import pytest

from pdsketch_mech.envs.generate import sample
from pdsketch_mech.envs.task_names import resolve_task
from pdsketch_mech.lang.loader import load_domain
from pdsketch_mech.lang.nodes import TRUE
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.planner.bilevel import prepare_task
from pdsketch_mech.symbolic.task import bits

from conftest import ROOT

MECHANISMS = os.path.join(ROOT, "domains", "mechanisms")
PAPER = {"edge": "edge", "hook": "hook-use", "lever": "lever", "poking": "poking", "com": "com",
         "slope-blocker": "slope-blocker"}


def composed(task, op):
    """The steps' own composed effect (add, delete)."""
    added = deleted = 0
    for step_id in op.steps:
        step = task.operators[step_id]
        added, deleted = (added & ~step.delete) | step.add, (deleted & ~step.add) | step.delete
    return added, deleted


@pytest.mark.parametrize("task_name", sorted(PAPER))
def test_the_papers_mechanisms_certify_nothing_their_steps_do_not_achieve(task_name):
    loaded = load_domain([os.path.join(MECHANISMS, f"{PAPER[task_name]}.pddl")])
    for seed in (0, 1):
        problem = parse_text(sample(resolve_task(task_name), "dev", seed).problem_text())
        task, _ = prepare_task(loaded, problem, use_mechanisms=True)
        macros = [op for op in task.operators if op.steps]
        assert macros and all((op.add, op.delete) == composed(task, op) for op in macros)


def test_a_certified_support_is_the_macros_effect_and_supersedes_where_it_was_put():
    loaded = load_domain([os.path.join(MECHANISMS, "ramp-slide.pddl")])
    problem = parse_text(sample(resolve_task("ramp-slide")).problem_text())
    task, _ = prepare_task(loaded, problem, use_mechanisms=True)
    (macro,) = [op for op in task.operators if op.steps and op.args[:4] == ("block", "table", "ramp", "platform")]
    facts = {task.facts[i] for i in bits(macro.add)}
    assert ("support", "block", "platform") in facts and ("support", "block", "ramp") not in facts
    assert ("support", "block", "ramp") in {task.facts[i] for i in bits(composed(task, macro)[0])}


def test_ramp_slide_plans_and_replays(tmp_path):
    from pdsketch_mech.commands import plan as plan_cli

    problem = tmp_path / "ramp.pddl"
    problem.write_text(sample(resolve_task("ramp-slide"), "dev", 1).problem_text())
    out = tmp_path / "plan.json"
    status = plan_cli.main([os.path.join(MECHANISMS, "ramp-slide.pddl"), str(problem), "--seed", "1",
                            "--timeout", "60", "--json", str(out), "--validate"])
    document = json.load(open(out))
    assert status == 0 and [s["mechanism"] for s in document["plan"]] == ["ramp-slide", "ramp-slide"]


@pytest.mark.slow
def test_gap_push_plans_and_replays(tmp_path):
    from pdsketch_mech.commands import plan as plan_cli

    out = tmp_path / "plan.json"
    status = plan_cli.main([os.path.join(MECHANISMS, "gap-push.pddl"),
                            os.path.join(ROOT, "domains", "tasks", "gap-push.pddl"), "--seed", "0", "--timeout", "120",
                            "--json", str(out), "--validate"])
    assert status == 0
    assert {s["mechanism"] for s in json.load(open(out))["plan"]} == {"gap-push"}


def test_every_shipped_fragment_is_its_files_mechanism_certifying_an_effect():
    """Each shipped fragment type-checks with no warning (its learned sampler's checkpoint is
    beside it) and defines the one mechanism its file is named after, which certifies a fact."""
    paths = sorted(glob.glob(os.path.join(MECHANISMS, "*.pddl")))
    names = [os.path.basename(path)[:-len(".pddl")] for path in paths]
    assert set(PAPER.values()) | {"gap-push", "ramp-slide"} <= set(names)
    for path, name in zip(paths, names):
        loaded = load_domain([path])
        assert not loaded.warnings, (name, loaded.warnings)
        (mechanism,) = loaded.domain.mechanisms
        assert mechanism.name == name and mechanism.certified != TRUE, name


LIFT_OVER = """; A mechanism written for this test: its steps include a free motion of the held object
; (the basis search leaves free motions out unless a mechanism lists them).
(define (domain lift-over)
  (:extends "BASIS")
  (:requirements :mechanisms)
  (:mechanism lift-over
    :parameters (?x ?s ?y - item ?g - grasp ?t1 - traj ?q - conf ?t2 - traj ?p - placement ?t3 - traj)
    :precondition (and (handempty) (support ?x ?s) (not (= ?x ?y)))
    :certified (and (support ?x ?y) (handempty))
    :actions ((grasp ?x ?s ?g ?t1) (move ?x ?q ?t2) (place ?x ?y ?p ?t3))))
"""


def test_a_new_mechanism_with_its_own_step_sequence_is_refined_and_replays_with_no_planner_code(tmp_path):
    """The planner reads a mechanism's steps and the basis vocabulary, nothing written for
    the mechanism: its macro (grasp, a free move of the held block, place) is refined by the
    planner's own search and the plan replays in a fresh world."""
    from collections import Counter

    import numpy as np

    from pdsketch_mech.lang.loader import load_domain, load_problem
    from pdsketch_mech.planner.bilevel import bilevel_plan, prepare_task
    from pdsketch_mech.planner.bindings import StepSampler
    from pdsketch_mech.planner.execute import execute_plan, settle_start
    from pdsketch_mech.planner.refine import Refinement
    from pdsketch_mech.planner.serialize import plan_entries
    from pdsketch_mech.planner.skeleton import skeleton_steps
    from pdsketch_mech.world.build import build_world

    from plan_fakes import skeleton_of

    fragment = tmp_path / "lift-over.pddl"
    fragment.write_text(LIFT_OVER.replace("BASIS", os.path.join(ROOT, "domains", "basis.pddl")))
    domain, problem = load_problem(os.path.join(ROOT, "problems", "stack.pddl"), [load_domain([str(fragment)])])
    task, placeholders = prepare_task(domain, problem)
    (macro,) = [i for i, op in enumerate(task.operators) if op.label == "(lift-over a table b)"]
    steps = skeleton_steps(task, [macro])
    assert [(s.name, s.mechanism) for s in steps] == [("grasp", "lift-over"), ("move", "lift-over"),
                                                      ("place", "lift-over")]
    sampler = StepSampler({s.name: s for s in domain.domain.streams}, placeholders, Counter())
    with build_world(problem) as world:
        settle_start(world)
        search = Refinement(skeleton_of(steps, fixed={"table"}, plan=[macro]), world.snapshot(), world, task,
                            sampler, np.random.default_rng(0))
        values = None
        while values is None and not search.exhausted and search.effort < 200:
            values = search.run(float("inf"), 3)
    assert values is not None
    assert execute_plan(task, problem, plan_entries(steps, values)).goal_reached
    # and the planner, given the fragment, solves the problem (whichever skeleton it refines first)
    with build_world(problem) as world:
        assert bilevel_plan(domain, problem, world, timeout=60, seed=0).status == "solved"
