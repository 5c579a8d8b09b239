"""Detours no dead step explains (planner/detours.py) lower a skeleton's share of work:
pushes of the tool, a distractor lifted and put back; a box out of reach hooked closer and
put down is explained once its grasp is dead."""
import os

import pytest

from pdsketch_mech.envs import TASKS, sample
from pdsketch_mech.lang.loader import load_domain
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.planner.bilevel import prepare_task
from pdsketch_mech.planner.detours import DETOUR_WEIGHT, detour_weight, unexplained_detours
from pdsketch_mech.planner.pristine import touch_masks
from pdsketch_mech.planner.schedule import next_turn

from conftest import ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")
MECHANISMS = [os.path.join(ROOT, "domains", "mechanisms", f"{m}.pddl")
              for m in ("com", "edge", "hook-use", "lever", "poking", "slope-blocker")]


@pytest.fixture(scope="module")
def hook_slope():
    """Hook-then-Place-on-Slope, test instance 0: a box (`target`) beyond reach, a ladle
    (`tool`), a brick."""
    problem = parse_text(sample(TASKS["hook-slope"], "test", 0).problem_text(), "hook-slope-test-0.pddl")
    task, _ = prepare_task(load_domain([BASIS] + MECHANISMS), problem)
    masks, bits = touch_masks(task)
    return task, masks, bits


def _plan(task, *prefixes):
    """Operator ids of the operators whose labels start with `prefixes`, in order."""
    return [next(i for i, op in enumerate(task.operators) if op.label.startswith(p)) for p in prefixes]


def test_a_push_of_an_object_no_dead_step_names_is_an_unexplained_detour(hook_slope):
    task, masks, bits = hook_slope
    box = 1 << bits["target"]
    push_tool = _plan(task, "(transit-cont tool table", "(hook-use tool target table)")
    push_box = _plan(task, "(transit-cont target table", "(grasp target table")
    assert unexplained_detours(task, push_tool, masks, flagged=box) == 1
    assert unexplained_detours(task, push_box, masks, flagged=box) == 0   # the box needs moving
    assert unexplained_detours(task, push_box, masks, flagged=0) == 1     # nothing known dead yet
    two_pushes = _plan(task, "(transit-cont tool table", "(transit-cont brick table", "(hook-use tool target table)")
    assert unexplained_detours(task, two_pushes, masks, flagged=box) == 2


def test_a_grasp_and_place_back_is_a_detour_unless_it_handles_a_flagged_object(hook_slope):
    task, masks, bits = hook_slope
    box = 1 << bits["target"]
    lift_brick = _plan(task, "(grasp brick table", "(place brick table", "(hook-use tool target table)")
    assert unexplained_detours(task, lift_brick, masks, flagged=box) == 1
    # The paper's composition: hook the box closer and put it down (back to the initial
    # symbols), then the slope-and-blocker mechanism.
    composition = _plan(task, "(hook-use tool target table)", "(place target table",
                        "(slope-blocker tool target table slope)")
    assert unexplained_detours(task, composition, masks, flagged=box) == 0
    assert unexplained_detours(task, composition, masks, flagged=1 << bits["brick"]) == 1
    assert unexplained_detours(task, _plan(task, "(hook-use tool target table)"), masks, flagged=0) == 0


def test_each_unexplained_detour_delays_a_new_skeleton():
    assert detour_weight(0) == 1.0 and detour_weight(2) == DETOUR_WEIGHT ** 2 < detour_weight(1) < 1.0
    active = [(1, 8)]                                   # the first skeleton has had 8 units
    assert next_turn(active, 2) == 2                    # a plain second skeleton comes now
    assert next_turn(active, 2, detour_weight(1)) == 1  # one that wanders waits
    assert next_turn([(1, 40)], 2, detour_weight(1)) == 2
