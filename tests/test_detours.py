"""Detours no dead step explains (skeleton.detour_steps, evidence.py) lower a skeleton's
estimate: pushes of the tool, a distractor lifted and put back; a box out of reach hooked
closer and put down is explained once its grasp is dead. The supply keeps a window of
upcoming skeletons, so one with detours does not hold back those behind it."""
import os
import time

import pytest

from pdsketch_mech.envs import TASKS, sample
from pdsketch_mech.lang.loader import load_domain
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.planner.bilevel import prepare_task
from pdsketch_mech.planner.budget import DEFAULT_BUDGET
from pdsketch_mech.planner.evidence import Evidence
from pdsketch_mech.planner.schedule import lowest, score
from pdsketch_mech.planner.skeleton import detour_steps as unexplained_detours, touch_masks
from pdsketch_mech.planner.supply import SkeletonSupply

from conftest import ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")
MECHANISMS = [os.path.join(ROOT, "domains", "mechanisms", f"{m}.pddl")
              for m in ("com", "edge", "hook-use", "lever", "poking", "slope-blocker")]


@pytest.fixture(scope="module")
def hook_slope():
    """Hook-then-Place-on-Slope, dev instance 0: a box (`target`) beyond reach, a ladle
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
    assert unexplained_detours(task, lift_brick, masks, flagged=box) == 2   # two operators
    # The paper's composition: hook the box closer and put it down (back to the initial
    # symbols), then the slope-and-blocker mechanism.
    composition = _plan(task, "(hook-use tool target table)", "(place target table",
                        "(slope-blocker tool target table slope)")
    assert unexplained_detours(task, composition, masks, flagged=box) == 0
    assert unexplained_detours(task, composition, masks, flagged=1 << bits["brick"]) == 2
    assert unexplained_detours(task, _plan(task, "(hook-use tool target table)"), masks, flagged=0) == 0


def _supply(task, evidence=None):
    evidence = evidence or Evidence(task)
    return SkeletonSupply(task, evidence, deadline=time.perf_counter() + 60), evidence


def test_each_operator_in_an_unexplained_detour_halves_the_estimate(hook_slope):
    task, _, _ = hook_slope
    supply, evidence = _supply(task)
    window = supply.upcoming()
    plain = next(s for s in window if not evidence.detours(s.plan))
    assert evidence.estimate(plain) == 1.0
    wandering = [s for s in supply.upcoming() if evidence.detours(s.plan)]
    for skeleton in wandering:
        assert evidence.estimate(skeleton) == max(2.0 ** -evidence.detours(skeleton.plan), 1 / 32)


def test_objects_another_search_found_dead_steps_about_explain_detours_here(hook_slope):
    """With mechanisms loaded the mechanisms' search takes the objects the basis operators'
    search found dead steps about (side_by_side.py): a push of the box then explains itself
    in the other search too, as if it had found the dead grasp itself."""
    task, masks, bits = hook_slope
    plain, mechanisms = Evidence(task), Evidence(task)
    for _ in range(DEFAULT_BUDGET.dead_after):
        plain.ran_dry(("grasp", ("target", "table"), 0))
    assert plain.flagged_objects() == ["target"]
    push_box = _plan(task, "(transit-cont target table", "(grasp target table")
    assert mechanisms.detours(push_box) == 1
    mechanisms.flag(plain.flagged_objects() + ["no-such-object"])
    assert mechanisms.detours(push_box) == 0 and mechanisms.flagged == plain.flagged


def test_the_supply_defers_skeletons_that_repeat_a_dead_step_and_hands_them_out_last(hook_slope):
    task, _, _ = hook_slope
    supply, evidence = _supply(task)
    dead = ("grasp", ("target", "table"), None)
    assert dead in supply.upcoming()[0].pristine     # the first skeleton grasps the box where it lies
    for _ in range(DEFAULT_BUDGET.dead_after):
        evidence.ran_dry(dead)
    handed = []
    for _ in range(12):
        handed.append(supply.upcoming()[0])
        supply.take(handed[-1])
    # the skeleton looked at before the step died is set aside too, not handed out
    assert not any(dead in skeleton.pristine for skeleton in handed)
    assert supply.deferrals >= 1 and supply.taken == 12
    # set aside, not dropped: they come back once the step is believed alive again
    evidence.advance(max(evidence.revisit_at.values()))
    assert any(dead in skeleton.pristine for skeleton in supply.upcoming())


def test_a_skeleton_with_detours_does_not_hold_back_the_ones_behind_it(hook_slope):
    """The schedule creates the upcoming skeleton with the lowest score; those the search
    found before it stay in view and come later, in their order."""
    task, _, _ = hook_slope
    supply, evidence = _supply(task)
    window = supply.upcoming()
    window_size = DEFAULT_BUDGET.window
    assert len(window) == window_size and [s.number for s in window] == list(range(1, window_size + 1))
    first = window[0]
    estimates = {s.number: (1 / 8 if s is first else 1.0) for s in window}
    # as the planner scores them: all as the next rank, the search's order on ties
    chosen = lowest([(score(1, 0, estimates[s.number], DEFAULT_BUDGET.slice), (1, s.order, s.number), s)
                     for s in window])
    assert chosen is window[1]   # the next in the search's order jumps the queue
    supply.take(chosen)
    assert first in supply.upcoming() and supply.taken == 1


def test_when_every_path_repeats_a_dead_step_the_supply_returns_instead_of_searching_on(hook_slope):
    """The search gives paths through dead steps without end once only those are left; the
    supply sets `lookahead` of them aside and returns, so the planner can revisit a belief."""
    task, _, _ = hook_slope
    evidence = Evidence(task)
    supply = SkeletonSupply(task, evidence, deadline=time.perf_counter() + 20)
    evidence.blocks = lambda keys: True   # as if every skeleton repeated a dead pristine step
    started = time.perf_counter()
    assert supply.upcoming() == supply._deferred[:1]
    assert supply.deferrals == DEFAULT_BUDGET.lookahead and time.perf_counter() - started < 15
    supply.upcoming()   # until a verdict changes, the search is not asked again
    assert supply.deferrals == DEFAULT_BUDGET.lookahead
    evidence.revivals += 1   # a dead step believed alive again: ask it
    supply.upcoming()
    assert supply.deferrals == 2 * DEFAULT_BUDGET.lookahead


def test_the_dead_step_due_first_is_revived_when_nothing_else_can_be_worked_on(hook_slope):
    task, _, _ = hook_slope
    evidence = Evidence(task)
    early, late = ("grasp", ("target", "table"), None), ("grasp", ("tool", "table"), None)
    for key in (early, late):   # the later one dies after more work: its revisit is further off
        for _ in range(DEFAULT_BUDGET.dead_after):
            evidence.ran_dry(key)
        evidence.advance(evidence.revisit_at[early] - 1)
    assert early in evidence.dead and late in evidence.dead
    assert evidence.revisit_at[early] < evidence.revisit_at[late]
    assert evidence.revive_earliest() and early not in evidence.dead and evidence.revived[-1] == early
    assert evidence.revive_earliest() and evidence.revived[-1] == late
    assert not evidence.revive_earliest()
