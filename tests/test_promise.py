"""Learned samplers weigh skeletons (planner/promise.py): a grounding its classifiers score far
below a rival that promises the same gets a smaller share of the work, never none."""
from __future__ import annotations

import math
from collections import Counter
from types import SimpleNamespace

import numpy as np
import pytest

from pdsketch_mech.planner.bindings import StepSampler
from pdsketch_mech.planner.budget import DEFAULT_BUDGET

FLOOR = DEFAULT_BUDGET.floor
from pdsketch_mech.planner.promise import GroundingPromise
from pdsketch_mech.samplers.interface import SampleRequest, StepContext

from learned_data import AllVerify

TOOL, APPLE, TOOL_AS_TARGET = ("hook", ("tool", "box", "table")), ("hook", ("apple", "box", "table")), \
    ("hook", ("apple", "tool", "table"))
HOLD_BOX, HOLD_TOOL = ((1, 0),), ((2, 0),)   # what each grounding promises (certified masks)


def weight(promise, groundings):
    """The factor the groundings give a skeleton's estimate (evidence.py), once the planner
    has registered them as rivals."""
    promise.register(groundings)
    return max(FLOOR, math.exp(min(0.0, sum(promise.gap(g, p) for g, p in set(groundings)))))


def test_a_grounding_scored_below_its_rival_is_held_back_by_the_gap():
    promise = GroundingPromise()
    for best in (-1.0, -2.0):                    # two batches each: means -1.5 and -3.5
        promise.observe(*TOOL, "?g", best)
        promise.observe(*APPLE, "?g", best - 2.0)
    assert weight(promise, [(TOOL, HOLD_BOX)]) == 1.0
    assert weight(promise, [(APPLE, HOLD_BOX)]) == pytest.approx(math.exp(-2.0))
    promise.observe(*APPLE, "?c", -12.0)          # a variable only the apple reached: no rival yet
    assert weight(promise, [(APPLE, HOLD_BOX)]) == pytest.approx(math.exp(-2.0))
    promise.observe(*TOOL, "?c", -1.0)            # now there is, and the gap is large: the floor
    assert weight(promise, [(APPLE, HOLD_BOX)]) == FLOOR
    assert weight(promise, [(TOOL, HOLD_BOX)]) == 1.0


def test_rivals_are_compared_on_the_sum_over_the_variables_both_were_scored_on():
    """The apple's grasps score higher, the tool's contacts much higher: the tool is ahead."""
    promise = GroundingPromise()
    promise.observe(*TOOL, "?g", -2.0)
    promise.observe(*APPLE, "?g", -1.0)
    promise.observe(*TOOL, "?c", -1.0)
    promise.observe(*APPLE, "?c", -3.5)
    assert weight(promise, [(TOOL, HOLD_BOX)]) == 1.0
    assert weight(promise, [(APPLE, HOLD_BOX)]) == pytest.approx(math.exp(-1.5))


def test_groundings_that_promise_other_facts_are_not_rivals():
    """Pulling the tool with the apple serves another subgoal; its high scores say nothing
    about which object should pull the box."""
    promise = GroundingPromise()
    promise.observe(*TOOL, "?g", -3.0)
    promise.observe(*TOOL_AS_TARGET, "?g", -0.1)
    assert weight(promise, [(TOOL, HOLD_BOX)]) == 1.0
    assert weight(promise, [(TOOL_AS_TARGET, HOLD_TOOL)]) == 1.0
    promise.observe(*APPLE, "?g", -5.0)
    # A skeleton with two groundings pays for both gaps.
    assert weight(promise, [(TOOL_AS_TARGET, HOLD_TOOL), (APPLE, HOLD_BOX)]) == pytest.approx(math.exp(-2.0))


def test_unscored_groundings_and_non_finite_scores_change_nothing():
    promise = GroundingPromise()
    assert weight(promise, []) == 1.0 and weight(promise, [(APPLE, HOLD_BOX)]) == 1.0
    promise.observe(*APPLE, "?g", -math.inf)     # a batch of proposals with no encoding
    assert promise.mean(APPLE, "?g") is None


class ByValue:
    """A stand-in for a mechanism's classifiers: higher numbers score higher (as log odds)."""

    score_seconds: list = []
    model = SimpleNamespace(classifier=lambda variable: SimpleNamespace(spec=SimpleNamespace(kind="grasp")))

    def __contains__(self, variable):
        return variable == "?g"

    def ranks_proposals(self, variable):
        return True

    def extrapolates(self, world, request, variable, budget=None):
        return None   # no fixed object out of place

    def score(self, world, request, variable, proposals):
        offset = 0.0 if request.step.mechanism_args[0] == "tool" else -3.0
        return np.array(proposals, dtype=float) - 10.0 + offset


def test_the_step_sampler_tells_the_promise_what_its_learned_samplers_scored():
    steps = StepSampler({}, {}, Counter(), {"hook": ByValue()})
    steps.samplers["sample-grasp"] = AllVerify(4)
    for grounding in (TOOL, APPLE):
        context = StepContext("grasp", (grounding[1][0], "#g1"), "hook", grounding[1], 0, (("#g1", "?g"),))
        sampler = steps.sampler_for("sample-grasp", context, "#g1")
        request = SampleRequest("sample-grasp", (), (), context)
        assert list(sampler.draw(None, request, np.random.default_rng(0), budget=4))
    assert steps.promise.mean(TOOL, "?g") == pytest.approx(3.0 - 10.0)   # the batch's best
    # The planner registers every skeleton in view, which makes them rivals.
    assert weight(steps.promise, [(TOOL, HOLD_BOX)]) == 1.0
    assert weight(steps.promise, [(APPLE, HOLD_BOX)]) == pytest.approx(math.exp(-3.0))


class Counting(AllVerify):
    """AllVerify that counts the proposals it verifies."""

    verified = 0

    def verify(self, world, request, candidate, rng):
        Counting.verified += 1
        return super().verify(world, request, candidate, rng)


def test_a_probe_scores_a_grounding_before_its_skeleton_gets_work_and_verifies_nothing():
    """The planner probes an upcoming skeleton's first mechanism step (planner/bilevel.py):
    one batch proposed and scored, none verified, so that a rival grounding the classifiers
    prefer can be created first. A step no classifier ranks is not probed."""
    from pdsketch_mech.lang.nodes import Stream
    from pdsketch_mech.symbolic.optimistic import Placeholder
    streams = {"sample-grasp": Stream("sample-grasp", sampler="grasp")}
    holders = {f"#g{i}": Placeholder(f"#g{i}", "grasp", "sample-grasp", (obj,), 0)
               for i, obj in ((1, "tool"), (2, "apple"))}
    steps = StepSampler(streams, holders, Counter(), {"hook": ByValue()})
    steps.samplers["sample-grasp"] = Counting(4)
    rng, world = np.random.default_rng(0), SimpleNamespace(bodies={})
    for (mechanism, args), g in ((TOOL, "#g1"), (APPLE, "#g2")):
        assert steps.probe(world, StepContext("grasp", (args[0], g), mechanism, args, 0, ((g, "?g"),)), rng)
    assert Counting.verified == 0 and steps.proposals()["learned"] == {}
    assert weight(steps.promise, [(TOOL, HOLD_BOX)]) == 1.0
    assert weight(steps.promise, [(APPLE, HOLD_BOX)]) == pytest.approx(math.exp(-3.0))
    # A basis step (no mechanism) and a variable without a classifier are left alone.
    assert not steps.probe(world, StepContext("grasp", ("tool", "#g1")), rng)
    assert not steps.probe(world, StepContext("grasp", ("tool", "#g1"), "hook", TOOL[1], 0, (("#g1", "?p"),)), rng)


def test_only_groundings_with_a_rival_are_probed_and_each_skeleton_once():
    """A score compared with nothing changes no weight: a skeleton whose first mechanism step
    has no rival grounding (upcoming or scored before) is not probed; two rivals are, once."""
    from pdsketch_mech.planner.probes import GroundingProbes
    from pdsketch_mech.planner.skeleton import Skeleton, Step

    probed = []
    sampler = SimpleNamespace(promise=GroundingPromise(),
                              probe=lambda world, step, rng: probed.append(step.mechanism_args) or True)
    task = SimpleNamespace(operators=[SimpleNamespace(label=f"op{i}") for i in range(3)])
    world = SimpleNamespace(restore=lambda snapshot: None)
    probes = GroundingProbes(task, sampler, world, None, seed=0)

    def skeleton(op, grounding, promised=HOLD_BOX):
        first = Step("grasp", (grounding[1][0], "#g"), 0, grounding[0], (), 0, grounding[1])
        last = Step("place", (grounding[1][0], "#p"), 0, grounding[0], promised, 1, grounding[1])
        return Skeleton(op + 1, [op], [first, last], [None, None], [])

    def probe(window):
        sampler.promise.register(g for s in window for g in s.groundings())   # as the planner does
        probes.probe(window)

    probe([skeleton(0, TOOL), skeleton(2, TOOL_AS_TARGET, HOLD_TOOL)])
    assert probed == []                                   # no rivals: nothing to compare
    probe([skeleton(0, TOOL), skeleton(1, APPLE), skeleton(2, TOOL_AS_TARGET, HOLD_TOOL)])
    assert probed == [TOOL[1], APPLE[1]] and probes.count == 2
    probe([skeleton(0, TOOL), skeleton(1, APPLE)])
    assert probes.count == 2                              # each skeleton once
