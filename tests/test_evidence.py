"""The planner's one store of evidence (planner/evidence.py): outcomes shared between
skeletons that ask the scene the same question (the same step after the same steps), dead
pristine steps, detours, and the estimate they give a skeleton."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from pdsketch_mech.planner import refine
from pdsketch_mech.planner.evidence import FLOOR, Evidence
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
        evidence.simulated(skeleton.contexts[index], skeleton.number, ok)


def test_failures_in_one_skeleton_lower_the_estimate_of_another_asking_the_same():
    evidence = _evidence()
    _outcomes(evidence, _straight_on(), 1, False, 8)
    # anywhere: 1/10 (Laplace); in that context, with that prior: (0 + 0.2) / 10
    assert evidence.estimate(_box_as_blocker()) == pytest.approx(0.02 / 0.1)
    assert evidence.estimate(_box_as_blocker(), owner=19) == evidence.estimate(_box_as_blocker())


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
    Skeletons that begin with the hook get the lift; a step that is merely easy here (the
    grasp of the tool) lifts nothing."""
    evidence = _evidence()
    where_it_lies = _sk([Step("grasp", ("box", "table", "#g"), HELD)], 5)
    for _ in range(10):
        evidence.ran_dry(("grasp", ("box", "table")), where_it_lies.contexts[0], owner=5)
    assert evidence.is_dead("grasp", ("box", "table"))
    hooked = skeleton_of(hook_steps(Step("place", ("box", "slope", "#p"), 0)), 17)
    for index in range(3):
        _outcomes(evidence, hooked, index, True, 3)
    blocker = skeleton_of(hook_steps(Step("place", ("box", "table", "#p2"), 0)), 18)
    anywhere = 4 / 15                                   # the box's grasp: 3 successes, 10 dry visits
    assert evidence.estimate(blocker) == pytest.approx((3 + 2 * anywhere) / 5 / anywhere)
    other = skeleton_of([Step("grasp", ("tool", "table", "#g1"), 0), Step("place", ("tool", "slope", "#p"), 0)], 19)
    assert evidence.estimate(other) == 1.0               # shares only the easy first step
    assert evidence.estimate(where_it_lies, owner=5) == 1.0   # its own dry visits are in its effort
    assert evidence.estimate(where_it_lies) < 0.5            # another skeleton asking the same: lower


def test_the_estimate_has_a_floor():
    evidence = _evidence()
    _outcomes(evidence, _straight_on(), 0, False, 10_000)
    _outcomes(evidence, _straight_on(), 1, False, 10_000)
    assert evidence.estimate(_box_as_blocker()) == FLOOR


def test_a_pristine_step_dies_after_repeated_dry_visits_unless_it_was_ever_feasible():
    evidence = _evidence()
    box, tool = ("grasp", ("box", "table")), ("grasp", ("tool", "table"))
    assert not evidence.ran_dry(box) and not evidence.ran_dry(box) and evidence.ran_dry(box)
    assert evidence.is_dead("grasp", ("box", "table", "#g7")) and evidence.deaths == 1
    evidence.found(tool)
    assert not any(evidence.ran_dry(tool) for _ in range(10)) and not evidence.is_dead("grasp", ("tool", "table"))
    assert evidence.blocks([None, box]) and not evidence.blocks([tool, None])
    assert not evidence.ran_dry(None)


def test_refinement_reports_each_simulated_outcome_under_its_steps_context(monkeypatch):
    monkeypatch.setattr(refine, "execute_step",
                        lambda world, snapshot, name, args, values: SimpleNamespace(ok=name == "grasp", reason="slid"))
    monkeypatch.setattr(refine, "observed_state", lambda task, world: HELD | TOOL_ON_TABLE)
    monkeypatch.setattr(refine, "contact_mask", lambda task: 0b111)
    evidence = _evidence()
    skeleton = _straight_on()
    sampler = SimpleNamespace(samples=lambda world, context, rng, parents: iter([{"#v": 1}]),
                              note_simulated=lambda values: None, note_outcome=lambda values, ok: None)
    search = Refinement(skeleton, None, still_world(), None, sampler, np.random.default_rng(0), evidence=evidence)
    search.run(deadline=float("inf"), max_work=2)   # the grasp simulates, the place fails
    grasp, place = skeleton.contexts
    assert evidence.counts(grasp) == (1, 0) and evidence.counts(place) == (0, 1)
    assert evidence.counts(place, owner=17) == (0, 0)


def test_a_dead_grasp_that_simulates_after_a_hook_is_recorded_as_unblocked(monkeypatch):
    monkeypatch.setattr(refine, "execute_step", lambda *args: SimpleNamespace(ok=True))
    monkeypatch.setattr(refine, "observed_state", lambda task, world: 0)
    monkeypatch.setattr(refine, "contact_mask", lambda task: 0)
    evidence = _evidence()
    for _ in range(evidence.dead_after):
        evidence.ran_dry(("grasp", ("box", "table")))
    steps = hook_steps(Step("place", ("box", "slope", "#p"), 0))
    search = Refinement(skeleton_of(steps), None, still_world(), None, OneValueSampler(), np.random.default_rng(0),
                        evidence=evidence)
    search.run(deadline=float("inf"), max_work=3)
    assert search.unblocked == {2}
    assert evidence.counts(search.skeleton.contexts[2]) == (1, 0)


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
    assert evidence.log_terms(apple)["groundings"] == pytest.approx(math.log(1e-2))
