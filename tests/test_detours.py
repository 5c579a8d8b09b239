"""Detours no dead step explains (planner/detours.py) lower a skeleton's share of work:
pushes of the tool, a distractor lifted and put back; a box out of reach hooked closer and
put down is explained once its grasp is dead."""
import os
import time

import pytest

from pdsketch_mech.envs import TASKS, sample
from pdsketch_mech.lang.loader import load_domain
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.planner.bilevel import prepare_task
from pdsketch_mech.planner.detours import DETOUR_WEIGHT, detour_weight, unexplained_detours
from pdsketch_mech.planner.pristine import DEAD_AFTER, PristineFailures, touch_masks
from pdsketch_mech.planner.schedule import heaviest, next_turn
from pdsketch_mech.planner.supply import WINDOW, SkeletonSupply

from conftest import ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")
MECHANISMS = [os.path.join(ROOT, "domains", "mechanisms", f"{m}.pddl")
              for m in ("com", "edge", "hook-use", "lever", "poking", "slope-blocker")]


@pytest.fixture(scope="module")
def hook_slope():
    """Hook-then-Place-on-Slope, test instance 0: a box (`target`) beyond reach, a ladle
    (`tool`), a brick."""
    problem = parse_text(sample(TASKS["hook-slope"], "dev", 0).problem_text(), "hook-slope-dev-0.pddl")
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


def test_the_supply_defers_skeletons_that_repeat_a_dead_step_and_hands_them_out_last(hook_slope):
    task, _, _ = hook_slope
    memo = PristineFailures()
    supply = SkeletonSupply(task, memo, deadline=time.perf_counter() + 60, max_skeletons=12)
    dead = ("grasp", ("target", "table"))
    assert dead in supply.peek()[2]       # the first skeleton grasps the box where it lies
    for _ in range(DEAD_AFTER):
        memo.ran_dry(dead)
    handed = [supply.take() for _ in range(12)]
    # the skeleton looked at before the step died is set aside too, not handed out
    assert not any(dead in taken[2] for taken in handed)
    assert supply.deferrals >= 1 and supply.taken == 12
    later = supply.take()                 # the cap is reached: deferred ones come now
    assert later is not None and supply.memo.blocks(later[2])


def test_a_light_skeleton_does_not_hold_back_the_ones_behind_it(hook_slope):
    """The planner creates the upcoming skeleton it weighs most (the first on ties); those
    the search found before it wait in the window and come later, in their order."""
    assert heaviest([DETOUR_WEIGHT ** 3, 1.0, 1.0]) == 1 and heaviest([0.5, 0.5]) == 0
    task, _, _ = hook_slope
    supply = SkeletonSupply(task, PristineFailures(), deadline=time.perf_counter() + 60, max_skeletons=50)
    window = supply.upcoming()
    assert len(window) == WINDOW and supply.peek() is window[0]
    labels = [tuple(t[0]) for t in window]
    assert tuple(supply.take(3)[0]) == labels[3]            # the fourth jumps the queue
    assert [tuple(t[0]) for t in supply.upcoming()[:3]] == labels[:3] and supply.taken == 1
    assert [tuple(supply.take()[0]) for _ in range(3)] == labels[:3]


def test_the_window_never_hands_out_more_than_the_cap_from_the_search(hook_slope):
    task, _, _ = hook_slope
    supply = SkeletonSupply(task, PristineFailures(), deadline=time.perf_counter() + 60, max_skeletons=3)
    assert len(supply.upcoming()) == 3
    handed = [supply.take(2), supply.take(1), supply.take()]
    assert all(handed) and supply.take() is None and supply.taken == 3
