"""Steps that keep failing from the same contact state (planner/bottlenecks.py): what one
skeleton learns by simulating a step weighs down the other skeletons that take the same step
from the same symbolic contact state, not the skeleton itself and not the same step taken
from another state."""
from types import SimpleNamespace

import numpy as np

from pdsketch_mech.planner import refine
from pdsketch_mech.planner.bottlenecks import FAILURES_PER_HALVING, FLOOR, SharedOutcomes
from pdsketch_mech.planner.refine import Refinement, Step

HELD, TOOL_ON_TABLE, TOOL_ON_SLOPE = 0b001, 0b010, 0b100
INIT = TOOL_ON_TABLE


def _straight_on():
    """Hold the box, put it on the slope with the tool on the table (it slides off)."""
    return [Step("grasp", ("box", "table", "#g1"), HELD | TOOL_ON_TABLE),
            Step("place", ("box", "slope", "#p1"), TOOL_ON_TABLE)]


def _box_as_blocker():
    """Another skeleton asking the same: the box on the slope, the tool still on the table."""
    return [Step("grasp", ("box", "table", "#g2"), HELD | TOOL_ON_TABLE),
            Step("place", ("box", "slope", "#p2"), TOOL_ON_TABLE),
            Step("grasp", ("tool", "table", "#g3"), HELD)]


def _tool_first():
    """The box put on the slope once the tool lies across it: another state before the place."""
    return [Step("place", ("tool", "slope", "#p3"), TOOL_ON_SLOPE),
            Step("grasp", ("box", "table", "#g4"), HELD | TOOL_ON_SLOPE),
            Step("place", ("box", "slope", "#p4"), TOOL_ON_SLOPE)]


def _fail(outcomes, steps, index, rank, times):
    key = outcomes.keys(steps)[index]
    for _ in range(times):
        outcomes.note(key, rank, False)


def test_failures_in_one_skeleton_halve_the_share_of_another_taking_the_step_from_that_state():
    outcomes = SharedOutcomes(INIT, observable=0b111)
    _fail(outcomes, _straight_on(), 1, rank=17, times=int(FAILURES_PER_HALVING))
    assert outcomes.weight(outcomes.keys(_box_as_blocker()), rank=19) == 0.5
    assert outcomes.weight(outcomes.keys(_box_as_blocker())) == 0.5   # not created yet: the same


def test_a_skeletons_own_failures_do_not_weigh_it_down_twice():
    outcomes = SharedOutcomes(INIT, observable=0b111)
    _fail(outcomes, _straight_on(), 1, rank=17, times=40)
    assert outcomes.weight(outcomes.keys(_straight_on()), rank=17) == 1.0


def test_the_same_step_from_another_contact_state_is_another_question():
    outcomes = SharedOutcomes(INIT, observable=0b111)
    _fail(outcomes, _straight_on(), 1, rank=17, times=40)
    assert outcomes.weight(outcomes.keys(_tool_first()), rank=18) == 1.0


def test_successes_elsewhere_soften_the_failures_and_the_weight_has_a_floor():
    outcomes = SharedOutcomes(INIT, observable=0b111)
    key = outcomes.keys(_straight_on())[1]
    _fail(outcomes, _straight_on(), 1, rank=17, times=16)
    for _ in range(3):
        outcomes.note(key, 17, True)
    assert outcomes.weight([key], rank=19) == 4 / (4 + 16 / FAILURES_PER_HALVING)
    _fail(outcomes, _straight_on(), 1, rank=17, times=10_000)
    assert outcomes.weight([key], rank=19) == FLOOR


def test_refinement_shares_each_simulated_outcome_under_its_steps_state(monkeypatch):
    monkeypatch.setattr(refine, "execute_step",
                        lambda world, snapshot, name, args, values: SimpleNamespace(ok=name == "grasp", reason="slid"))
    monkeypatch.setattr(refine, "observed_state", lambda task, world: HELD | TOOL_ON_TABLE)
    monkeypatch.setattr(refine, "contact_mask", lambda task: 0b111)
    sampler = SimpleNamespace(samples=lambda world, context, rng, parents: iter([{"#v": 1}]),
                              note_simulated=lambda values: None, note_outcome=lambda values, ok: None)
    world = SimpleNamespace(bodies={}, restore=lambda snapshot: None, snapshot=object,
                            moved_since=lambda snapshot, name: True)
    outcomes = SharedOutcomes(INIT, observable=0b111)
    search = Refinement(_straight_on(), start=None, world=world, task=None, sampler=sampler,
                        rng=np.random.default_rng(0), rank=17, outcomes=outcomes)
    search.run(deadline=float("inf"), max_work=2)   # the grasp simulates, the place fails
    grasp, place = outcomes.keys(_straight_on())
    assert outcomes.counts(grasp) == (1, 0) and outcomes.counts(place) == (0, 1)
    assert outcomes.counts(place, rank=17) == (0, 0)
