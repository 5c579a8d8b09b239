"""Context objects (samplers/learned/context.py): the bodies nearest a mechanism's movable
objects, chosen by geometry alone, the same in self-play and at planning time."""
from __future__ import annotations

import os

import numpy as np

from pdsketch_mech.envs.generate import sample
from pdsketch_mech.envs.tasks import TASKS
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.planner.execute import settle_start
from pdsketch_mech.samplers.interface import SampleRequest, StepContext
from pdsketch_mech.samplers.learned.context import box_gap, context_objects
from pdsketch_mech.samplers.learned.ranked import LearnedMechanism
from pdsketch_mech.world.build import build_world


def test_box_gap():
    unit = (np.zeros(3), np.ones(3))
    assert box_gap(unit, (np.full(3, 0.5), np.full(3, 2.0))) == 0.0            # overlapping
    assert box_gap(unit, (np.array([3.0, 0, 0]), np.array([4.0, 1, 1]))) == 2.0
    assert np.isclose(box_gap(unit, (np.array([2.0, 2, 0]), np.array([3.0, 3, 1]))), np.sqrt(2))


def test_the_tunnel_around_a_poked_block_is_its_context_and_the_planner_sees_it_too():
    instance = sample(TASKS["poking"], "dev", 6)
    problem = parse_text(instance.problem_text(), file="<poking>")
    grounding = ("tool", "target", "table")
    with build_world(problem) as world:
        settle_start(world)
        assert world.bodies["tunnel"].fixed
        assert context_objects(world, grounding, 1) == ["tunnel"]   # the block sits inside it
        three = context_objects(world, grounding, 3)
        assert three[0] == "tunnel" and set(three[1:]) <= {"d0", "d1"} and len(set(three)) == 3
        assert len(context_objects(world, grounding, 6)) == 6     # fewer bodies: the last repeats
        assert context_objects(world, grounding, 0) == []
        assert context_objects(world, ("table",), 2) == ["table", "table"]   # nothing moves
        # A checkpoint trained with one context object scores with the same bodies.
        request = SampleRequest("s", (), (), StepContext("grasp", (), "poking", grounding))
        assert LearnedMechanism(None, {"selfplay": {"context": 1}}).objects(world, request) == grounding + ("tunnel",)
        assert LearnedMechanism(None, {}).objects(world, request) == grounding   # older checkpoints
