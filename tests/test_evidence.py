"""The planner's one store of evidence (planner/evidence.py): outcomes shared between
skeletons that ask the scene the same question (the same step after the same steps), dead
pristine steps, detours, and the estimate they give a skeleton."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from pdsketch_mech.planner import refine
from pdsketch_mech.planner.budget import DEFAULT_BUDGET
from pdsketch_mech.planner.evidence import Evidence

FLOOR, UNBLOCK_GAIN = DEFAULT_BUDGET.floor, DEFAULT_BUDGET.unblock_gain
from pdsketch_mech.planner.refine import Refinement
from pdsketch_mech.planner.skeleton import Step

from plan_fakes import OneValueSampler, hook_steps, skeleton_of, still_world

HELD, TOOL_ON_TABLE, TOOL_ON_SLOPE = 0b001, 0b010, 0b100
INIT = TOOL_ON_TABLE


def _evidence() -> Evidence:
    """A store for a task with no operators (the skeletons below are written by hand)."""
    task = SimpleNamespace(operators=[], facts=[], init=0, static_facts=[], successor=None)
    return Evidence(task)


def _sk(steps, rank):
    return skeleton_of(steps, rank)


def _straight_on(rank=17):
    """Hold the box, put it on the slope with the tool on the table (it slides off)."""
    return _sk([Step("grasp", ("box", "table", "#g1"), HELD | TOOL_ON_TABLE),
                Step("place", ("box", "slope", "#p1"), TOOL_ON_TABLE)], rank)


def _box_as_blocker(rank=19):
    """Another skeleton asking the same: the box on the slope, the tool still on the table."""
    return _sk([Step("grasp", ("box", "table", "#g2"), HELD | TOOL_ON_TABLE),
                Step("place", ("box", "slope", "#p2"), TOOL_ON_TABLE),
                Step("grasp", ("tool", "table", "#g3"), HELD)], rank)


def _tool_first(rank=18):
    """The box put on the slope once the tool lies across it: another state before the place."""
    return _sk([Step("place", ("tool", "slope", "#p3"), TOOL_ON_SLOPE),
                Step("grasp", ("box", "table", "#g4"), HELD | TOOL_ON_SLOPE),
                Step("place", ("box", "slope", "#p4"), TOOL_ON_SLOPE)], rank)


def _outcomes(evidence, skeleton, index, ok, times):
    for _ in range(times):
        evidence.simulated(skeleton, index, ok)


def test_failures_in_one_skeleton_lower_the_estimate_of_another_asking_the_same():
    """The chance that the step is not dead in that context, against the prior 1/2, with
    the rate at which the step works where it has worked (here: with the tool on the slope)."""
    evidence = _evidence()
    _outcomes(evidence, _tool_first(), 2, False, 8)
    _outcomes(evidence, _tool_first(), 2, True, 1)
    _outcomes(evidence, _straight_on(), 1, False, 8)
    unlucky = (1 - 2 / 11) ** 8                   # works at (1 + 1) / (9 + 2) where it works
    assert evidence.estimate(_box_as_blocker()) == pytest.approx(2 * unlucky / (1 + unlucky))
    assert evidence.estimate(_box_as_blocker(), owner=19) == evidence.estimate(_box_as_blocker())


def test_a_step_that_has_worked_nowhere_is_judged_by_how_often_steps_work_where_they_do():
    evidence = _evidence()
    _outcomes(evidence, _tool_first(), 0, True, 3)     # another step: 3 of 4 where it works
    _outcomes(evidence, _tool_first(), 0, False, 1)
    _outcomes(evidence, _straight_on(), 1, False, 2)
    unlucky = (1 - 4 / 6) ** 2
    assert evidence.estimate(_box_as_blocker()) == pytest.approx(2 * unlucky / (1 + unlucky))


def test_a_skeletons_own_outcomes_do_not_count_twice():
    evidence = _evidence()
    _outcomes(evidence, _straight_on(), 1, False, 40)
    assert evidence.estimate(_straight_on(), owner=17) == 1.0


def test_the_same_step_after_other_steps_is_another_question():
    evidence = _evidence()
    _outcomes(evidence, _straight_on(), 1, False, 40)
    assert evidence.estimate(_tool_first(), owner=18) == 1.0


def test_a_step_dead_where_it_lies_that_works_in_another_context_lifts_skeletons_that_begin_alike():
    """The grasp of a box out of reach runs dry where the box lies; after a hook it works.
    Skeletons that begin with the hook get UNBLOCK_GAIN, the one that got past too; a step
    that is merely easy here (the grasp of the tool) lifts nothing."""
    evidence = _evidence()
    where_it_lies = _sk([Step("grasp", ("box", "table", "#g"), HELD)], 5)
    for _ in range(10):
        evidence.ran_dry(("grasp", ("box", "table"), None))
    assert evidence.is_dead("grasp", ("box", "table"), None)
    hooked = skeleton_of(hook_steps(Step("place", ("box", "slope", "#p"), 0)), 17)
    for index in range(3):
        _outcomes(evidence, hooked, index, True, 3)
    blocker = skeleton_of(hook_steps(Step("place", ("box", "table", "#p2"), 0)), 18)
    assert evidence.estimate(blocker) == pytest.approx(UNBLOCK_GAIN)
    assert evidence.estimate(hooked, owner=17) == pytest.approx(UNBLOCK_GAIN)
    other = skeleton_of([Step("grasp", ("tool", "table", "#g1"), 0), Step("place", ("tool", "slope", "#p"), 0)], 19)
    assert evidence.estimate(other) == 1.0               # shares only the easy first step
    assert evidence.blocks(where_it_lies.pristine)           # where it lies: deferred instead


def test_the_estimate_has_a_floor():
    evidence = _evidence()
    _outcomes(evidence, _straight_on(), 0, False, 10_000)
    _outcomes(evidence, _straight_on(), 1, False, 10_000)
    assert evidence.estimate(_box_as_blocker()) == FLOOR


def test_a_pristine_step_dies_after_repeated_dry_visits_unless_it_was_ever_feasible():
    evidence = _evidence()
    box, tool = ("grasp", ("box", "table"), None), ("grasp", ("tool", "table"), None)
    assert not evidence.ran_dry(box) and not evidence.ran_dry(box) and evidence.ran_dry(box)
    assert evidence.is_dead("grasp", ("box", "table", "#g7"), None) and evidence.deaths == 1
    evidence.found(tool)
    assert not any(evidence.ran_dry(tool) for _ in range(10)) and not evidence.is_dead("grasp", ("tool", "table"), None)
    assert evidence.blocks([None, box]) and not evidence.blocks([tool, None])
    assert not evidence.ran_dry(None)


def test_refinement_reports_each_simulated_outcome_under_its_steps_context(monkeypatch):
    monkeypatch.setattr(refine, "execute_step",
                        lambda world, snapshot, name, args, values, **kwargs: SimpleNamespace(ok=name == "grasp", reason="slid"))
    monkeypatch.setattr(refine, "observed_state", lambda task, world, vocabulary=None: HELD | TOOL_ON_TABLE)
    monkeypatch.setattr(refine, "contact_mask", lambda task, vocabulary=None: 0b111)
    evidence = _evidence()
    skeleton = _straight_on()
    sampler = SimpleNamespace(samples=lambda world, context, rng, parents: iter([{"#v": 1}]),
                              note_simulated=lambda values: None, note_outcome=lambda values, ok: None)
    search = Refinement(skeleton, None, still_world(), None, sampler, np.random.default_rng(0), evidence=evidence)
    search.run(deadline=float("inf"), max_work=2)   # the grasp simulates, the place fails
    grasp, place = skeleton.questions
    assert evidence.counts(grasp) == (1, 0) and evidence.counts(place) == (0, 1)
    assert evidence.counts(place, owner=17) == (0, 0)


def test_a_dead_grasp_that_simulates_after_a_hook_is_recorded_as_unblocked(monkeypatch):
    monkeypatch.setattr(refine, "execute_step", lambda *args, **kwargs: SimpleNamespace(ok=True))
    monkeypatch.setattr(refine, "observed_state", lambda task, world, vocabulary=None: 0)
    monkeypatch.setattr(refine, "contact_mask", lambda task, vocabulary=None: 0)
    evidence = _evidence()
    for _ in range(evidence.dead_after):
        evidence.ran_dry(("grasp", ("box", "table"), None))
    steps = hook_steps(Step("place", ("box", "slope", "#p"), 0))
    search = Refinement(skeleton_of(steps), None, still_world(), None, OneValueSampler(), np.random.default_rng(0),
                        evidence=evidence)
    search.run(deadline=float("inf"), max_work=3)
    assert search.unblocked == {2}
    assert evidence.counts(search.skeleton.questions[2]) == (1, 0)


def test_learned_groundings_enter_the_estimate_as_their_gap_to_the_best_rival():
    evidence = _evidence()
    promised = ((1, 0),)
    weak, strong = ("hook-use", ("apple", "box")), ("hook-use", ("tool", "box"))
    evidence.promise.register([(weak, promised), (strong, promised)])
    evidence.promise.observe("hook-use", ("apple", "box"), "?g", math.log(1e-4))
    evidence.promise.observe("hook-use", ("tool", "box"), "?g", math.log(1e-2))
    apple = skeleton_of([Step("grasp", ("apple", "table", "#g"), 0, "hook-use", promised, 0, ("apple", "box"))])
    tool = skeleton_of([Step("grasp", ("tool", "table", "#g"), 0, "hook-use", promised, 0, ("tool", "box"))])
    assert evidence.estimate(tool) == 1.0
    assert evidence.estimate(apple) == FLOOR     # 1/100 of the rival's, below the floor
    assert evidence.log_terms(apple)["groundings"] == pytest.approx(math.log(FLOOR))   # 1/100, bounded


def test_the_steps_that_got_past_a_dead_step_lift_every_mechanism_that_takes_it_after_them():
    """A push made the tool graspable inside a lever; a hook that grasps the tool after the
    same push shares the gain before its own grasp has worked."""
    evidence = _evidence()
    for _ in range(evidence.dead_after):
        evidence.ran_dry(("grasp", ("tool", "table"), None))
    push = Step("transit-cont", ("tool", "table", "#c"), 0)
    lever = skeleton_of([push, Step("grasp", ("tool", "table", "#g"), HELD, "lever", (), 0, ("tool", "box"))], 4)
    hook = skeleton_of([push, Step("grasp", ("tool", "table", "#g"), HELD, "hook-use", (), 0, ("tool", "box"))], 3)
    assert evidence.estimate(hook) == 1.0
    _outcomes(evidence, lever, 1, True, 1)
    assert evidence.estimate(hook) == pytest.approx(UNBLOCK_GAIN)
    assert evidence.estimate(skeleton_of([lever.steps[1]], 9)) == 1.0   # not after the push


def test_a_mechanism_whose_promise_keeps_failing_weighs_on_every_skeleton_that_uses_it():
    """Laplace's rule over the mechanism's outcomes in other skeletons, whatever grounding:
    a user's trick whose certified facts failed 40 times never ranks with an unknown plan."""
    evidence = _evidence()
    assert evidence.log_kept("hook-use") == 0.0                     # nothing known: the uninformed 1/2
    evidence._promises["hook-use"] = [0, 40]
    assert math.exp(evidence.log_kept("hook-use")) == pytest.approx(2 / 42)
    evidence._promises_by_owner[("hook-use", 7)] = [0, 40]
    assert evidence.log_kept("hook-use", owner=7) == 0.0            # its own failures are in its effort
    evidence._promises["hook-use"] = [30, 20]
    assert evidence.log_kept("hook-use") == 0.0                     # it works more often than not: no weight


def test_a_way_past_a_dead_step_keeps_its_gain_while_the_step_is_revisited():
    """Revisiting a dead verdict (the step believed alive again for a while) does not undo
    what a push that got past it showed; only the step proving feasible where the scene
    began does."""
    evidence = _evidence()
    key = ("grasp", ("tool", "table"), None)
    for _ in range(evidence.dead_after):
        evidence.ran_dry(key)
    push = Step("transit-cont", ("tool", "table", "#c"), 0)
    lever = skeleton_of([push, Step("grasp", ("tool", "table", "#g"), HELD, "lever", (), 0, ("tool", "box"))], 4)
    _outcomes(evidence, lever, 1, True, 1)
    assert evidence.advance(10 ** 6) and key not in evidence.dead          # believed alive again
    assert evidence.estimate(lever) == pytest.approx(UNBLOCK_GAIN)
    evidence.found(key)                                                     # feasible where the scene began
    assert evidence.estimate(lever) == 1.0


def test_a_step_dead_with_one_mechanisms_samplers_blocks_only_skeletons_that_draw_from_them():
    """A shelf pull's anchored grasps of a spoon ran dry three times: another anchored
    mechanism's grasp of the same spoon is still tried (and the generic grasp too); a
    mechanism without proposals of its own (learned ones only reorder) draws the generic grasp."""
    task = SimpleNamespace(operators=[], facts=[], init=0, static_facts=[], successor=None)
    evidence = Evidence(task, own_samplers={"shelf-pull", "slope-blocker"})
    anchored = ("grasp", ("spoon", "table"), "shelf-pull")
    for _ in range(evidence.dead_after):
        evidence.ran_dry(anchored)
    assert evidence.is_dead("grasp", ("spoon", "table", "#g"), "shelf-pull")
    assert not evidence.is_dead("grasp", ("spoon", "table", "#g"), "slope-blocker")
    assert evidence.blocks([anchored]) and not evidence.blocks([("grasp", ("spoon", "table"), "slope-blocker")])
    assert not evidence.blocks([("grasp", ("spoon", "table"), None)])
    assert not evidence.is_dead("grasp", ("spoon", "table", "#g"), "lever")   # generic: not the dead one
    assert evidence.was_dead("grasp", ("spoon", "table", "#g")) and "(grasp spoon table) in shelf-pull" in evidence.labels()
    evidence.found(anchored)
    assert not evidence.was_dead("grasp", ("spoon", "table", "#g")) and not evidence.labels()
