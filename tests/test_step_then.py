"""A mechanism step's `:then`: what physics makes so after the step (a pull drops the target off a
shelf onto the table, which a later step of the same mechanism grasps it from). The language
reads and writes it, extraction writes it where a demonstration goes on after such a fall, and
the planner takes it as the step's effect and checks it in simulation."""
from __future__ import annotations

import json
import os
import shutil
from dataclasses import replace

import pytest

from pdsketch_mech.commands import demo as demo_cli
from pdsketch_mech.commands import learn as learn_cli
from pdsketch_mech.commands import plan as plan_cli
from pdsketch_mech.envs.generate import sample
from pdsketch_mech.envs.task_file import load_task_file
from pdsketch_mech.lang.errors import PddlError
from pdsketch_mech.lang.loader import load_domain
from pdsketch_mech.lang.nodes import TRUE
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.lang.writer import write_mechanism
from pdsketch_mech.learning.compare import differences
from pdsketch_mech.planner.bilevel import prepare_task
from pdsketch_mech.planner.skeleton import skeleton_steps
from pdsketch_mech.symbolic.task import bits

from conftest import ROOT

TRICK = os.path.join(ROOT, "problems", "tricks", "shelf-pick")
PULL_THEN = ":then (and (support ?target ?support) (not (support ?target ?target-support)))"


def _fragment(actions: str) -> str:
    return f"""(define (domain pull) (:extends "basis") (:requirements :mechanisms)
  (:mechanism pull
    :parameters (?tool ?target ?support ?target-support - item ?g1 - grasp ?t1 - traj ?c - contact
                 ?t2 - traj ?p - placement ?t3 - traj ?g2 - grasp ?t4 - traj)
    :precondition (and (handempty) (support ?tool ?support) (support ?target ?target-support))
    :certified (holding ?target)
    :actions ({actions})))"""


STEPS = ("(grasp ?tool ?support ?g1 ?t1) (move-cont ?tool ?target ?target-support ?c ?t2) {then} "
         "(place ?tool ?support ?p ?t3) (grasp ?target ?support ?g2 ?t4)")


def test_a_steps_then_is_read_and_written_back():
    mechanism = parse_text(_fragment(STEPS.format(then=PULL_THEN)), "pull.pddl").mechanisms[0]
    assert [c.then == TRUE for c in mechanism.actions] == [True, False, True, True]
    again = parse_text(f"(define (domain pull) (:requirements :mechanisms) {write_mechanism(mechanism)})", "x")
    assert write_mechanism(again.mechanisms[0]) == write_mechanism(mechanism)
    assert PULL_THEN in write_mechanism(mechanism)


@pytest.mark.parametrize("actions, message", [
    (":then (support ?target ?support) " + STEPS.format(then=""), ":then must follow a step"),
    (STEPS.format(then=PULL_THEN + " :then (handempty)"), "one :then per step"),
    (STEPS.format(then=":then (or (handempty) (holding ?tool))"), "facts and negated facts"),
    (STEPS.format(then=":then (rests ?target ?support)"), "rests"),
])
def test_a_misplaced_or_malformed_then_is_one_located_error(tmp_path, actions, message):
    path = tmp_path / "pull.pddl"
    path.write_text(_fragment(actions))
    with pytest.raises(PddlError) as error:
        load_domain([str(path)])
    assert message in str(error.value) and error.value.loc is not None


def _instance(tmp_path, seed: int = 0) -> str:
    out = tmp_path / f"shelf-pick-{seed}.pddl"
    out.write_text(sample(load_task_file(os.path.join(TRICK, "shelf-pick.dist.json")), "dev", seed).problem_text())
    return str(out)


def test_the_planner_takes_a_then_as_the_steps_effect_and_expects_it_after_that_step(tmp_path):
    loaded = load_domain([os.path.join(TRICK, "shelf-pick.mech.pddl")])
    problem = parse_text(open(_instance(tmp_path)).read())
    task, _ = prepare_task(loaded, problem, use_mechanisms=True)
    macros = [i for i, op in enumerate(task.operators) if op.steps and op.args[:4] == ("hook", "block", "table", "shelf")]
    assert macros, "the mechanism applies where the block starts on the shelf"
    macro = task.operators[macros[0]]
    assert not macro.pre & (1 << task.fact_ids[("support", "block", "table")]), \
        "the grasp from the table needs nothing of the start: the pull's :then provides it"
    steps = skeleton_steps(task, [macros[0]])
    states = [{task.facts[i] for i in bits(step.expected)} for step in steps]
    assert ("support", "block", "table") not in states[0]
    assert ("support", "block", "table") in states[1] and ("support", "block", "shelf") not in states[1]
    # Before the pull, the block may already be on the table (it fell early), but must not have
    # left the shelf: the pull needs it there.
    early_added, early_deleted = ({task.facts[i] for i in bits(mask)} for mask in steps[0].early)
    assert ("support", "block", "table") in early_added and ("support", "block", "shelf") not in early_deleted


def test_a_demonstration_that_goes_on_after_a_fall_extracts_whole(tmp_path, capsys):
    for suffix in (".pddl", ".demo.json"):
        shutil.copy(os.path.join(TRICK, "shelf-pick" + suffix), tmp_path / ("shelf-pick" + suffix))
    assert demo_cli.main(["record", str(tmp_path / "shelf-pick.demo.json")]) == 0
    fragment = tmp_path / "shelf-pick.mech.pddl"
    assert learn_cli.main(["extract", str(tmp_path / "shelf-pick"), "--out", str(fragment)]) == 0
    said = capsys.readouterr().err
    assert "after step 2 (move-cont), physics: ?target rests on ?support; not: ?target rests on ?target-support" in said
    mechanism = load_domain([str(fragment)]).domain.mechanisms[0]
    assert [c.name for c in mechanism.actions] == ["grasp", "move-cont", "place", "grasp"]
    assert PULL_THEN in write_mechanism(mechanism)
    assert "(not (= ?support ?target-support))" in write_mechanism(mechanism), "a fall onto where it was is none"


@pytest.mark.slow
def test_a_mechanism_with_a_fall_plans_on_a_held_out_scene_and_replays(tmp_path):
    out = tmp_path / "plan.json"
    status = plan_cli.main([os.path.join(TRICK, "shelf-pick.mech.pddl"), _instance(tmp_path, 1), "--seed", "1",
                            "--timeout", "120", "--json", str(out), "--validate"])
    plan = json.load(open(out))["plan"]
    assert status == 0 and [s["mechanism"] for s in plan] == ["shelf-pick"] * 4


def test_re_extraction_tells_a_fragment_whose_then_differs():
    mechanism = load_domain([os.path.join(TRICK, "shelf-pick.mech.pddl")]).domain.mechanisms[0]
    without = replace(mechanism, actions=tuple(replace(c, then=TRUE) for c in mechanism.actions))
    assert differences(mechanism, mechanism) == []
    assert differences(mechanism, without) == [
        "what physics does after step 2 (:then): (and (support ?target ?support) "
        "(not (support ?target ?target-support))) vs nothing"]


UNCHOCK = os.path.join(ROOT, "tests", "data", "unchock")   # a helper's trick, written from docs/


def _extract(tmp_path, demo: str):
    for name in ("unchock.pddl", f"{demo}.demo.json"):
        shutil.copy(os.path.join(UNCHOCK, name), tmp_path / name)
    assert demo_cli.main(["record", str(tmp_path / f"{demo}.demo.json")]) == 0
    fragment = tmp_path / f"{demo}.mech.pddl"
    assert learn_cli.main(["extract", str(tmp_path / demo), "--out", str(fragment)]) == 0
    return fragment, load_domain([str(fragment)]).domain.mechanisms[0]


def test_lifting_a_chock_away_is_no_push_and_the_slide_it_lets_happen_is_the_grasps_then(tmp_path):
    """The cube leaning on the chock touches it while the chock is lifted, moving the other way:
    no push. The cube slides down during the grasp's lift, so the grasp's :then says it."""
    _, mechanism = _extract(tmp_path, "unchock")
    assert [c.name for c in mechanism.actions] == ["grasp", "place", "grasp", "place"]
    assert mechanism.actions[0].then != TRUE and all(c.then == TRUE for c in mechanism.actions[1:])


def test_an_object_physics_moved_that_no_step_touched_is_explained_by_the_step_in_progress(tmp_path):
    """The hand shoves the chock aside and never touches the cube, which slides down: the
    shove's :then says where the cube went."""
    _, mechanism = _extract(tmp_path, "unchock-push")
    assert [c.name for c in mechanism.actions] == ["transit-cont", "grasp", "place"]
    assert mechanism.actions[0].then != TRUE


@pytest.mark.slow
def test_the_unchock_mechanism_plans_on_a_steeper_slope_and_replays(tmp_path):
    fragment, _ = _extract(tmp_path, "unchock")
    out = tmp_path / "plan.json"
    status = plan_cli.main([str(fragment), os.path.join(UNCHOCK, "unchock-steep.pddl"), "--timeout", "120",
                            "--json", str(out), "--validate"])
    assert status == 0 and {s["mechanism"] for s in json.load(open(out))["plan"]} == {"unchock"}
