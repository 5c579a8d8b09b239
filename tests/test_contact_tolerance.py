"""What a simulated step may do beyond its skeleton: extra support facts (refine.py
`tolerated_supports`), and the placements that make them happen (placement.py
`rest_on_relief`)."""
import os

import pytest

from pdsketch_mech.envs import TASKS, sample
from pdsketch_mech.lang.loader import load_domain
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.planner.bilevel import prepare_task
from pdsketch_mech.planner.skeleton import mismatch, skeleton_steps

from conftest import ROOT

LEVER = os.path.join(ROOT, "domains", "mechanisms", "lever.pddl")


@pytest.fixture(scope="module")
def lever_task():
    problem = parse_text(sample(TASKS["lever"], "train", 0).problem_text(), "lever-train-0.pddl")
    task, _ = prepare_task(load_domain([LEVER]), problem)
    return task


def _op(task, label):
    return next(i for i, op in enumerate(task.operators) if op.label.startswith(label))


def _bit(task, *fact):
    return 1 << task.fact_ids[fact]


def test_a_placed_weight_may_leave_the_lever_and_itself_resting_on_more_than_the_skeleton_says(lever_task):
    task = lever_task
    grasp, place, grasp_plate = skeleton_steps(task, [_op(task, "(lever weight plate table ledge")])
    assert place.name == "place" and place.args[:2] == ("weight", "plate")
    # The plate tipped into the pit touches the table; the weight's handle may lie on the wall.
    assert place.tolerated & _bit(task, "support", "plate", "table")
    assert place.tolerated & _bit(task, "support", "weight", "ledge")
    tipped = place.expected | _bit(task, "support", "plate", "table")
    assert not mismatch(tipped, place, ~0)
    # What the skeleton expects must still hold: a weight that fell off the plate fails.
    fell = (place.expected & ~_bit(task, "support", "weight", "plate")) | _bit(task, "support", "weight", "table")
    assert mismatch(fell, place, ~0)


def test_a_pushed_object_must_rest_on_what_it_rested_on_and_nothing_more(lever_task):
    # A push says nothing about where its object ends up: a plate pushed out of its cradle
    # onto the table, still grazing the ledge, did not do what the skeleton says.
    task = lever_task
    push = skeleton_steps(task, [_op(task, "(transit-cont plate ledge"), _op(task, "(grasp plate ledge")])[0]
    assert push.name == "transit-cont"
    assert not push.tolerated & _bit(task, "support", "plate", "table")
    assert mismatch(push.expected | _bit(task, "support", "plate", "table"), push, ~0)


def test_a_fact_the_goal_needs_false_is_never_tolerated():
    # Slope-and-Blocker's goal says off the table: a block set at the slope's foot, resting
    # on the slope and the table, must fail the check (goal_free_supports).
    problem = parse_text(sample(TASKS["slope-blocker"], "dev", 0).problem_text(), "slope-blocker-dev-0.pddl")
    task, _ = prepare_task(load_domain([os.path.join(ROOT, "domains", "mechanisms", "slope-blocker.pddl")]), problem)
    steps = skeleton_steps(task, [_op(task, "(slope-blocker blocker block table slope")])
    last = steps[-1]
    assert last.name == "place" and last.args[:2] == ("block", "slope")
    assert not last.tolerated & _bit(task, "support", "block", "table")
    assert last.tolerated & _bit(task, "support", "block", "blocker")
    assert mismatch(last.expected | _bit(task, "support", "block", "table"), last, ~0)
