"""The sampler interface (issue 11, class 4): samplers propose cheaply and verify expensively,
are bound to streams by name from the domain, and are told the step they serve (operator,
mechanism, index in it, object poses, parent values). And the held-tool contact sampler's
pulls: a tool turned about the support normal reaches behind a box out of reach."""
import dataclasses
import os
from collections import Counter

import numpy as np
import pytest

from pdsketch_mech.envs.generate import sample
from pdsketch_mech.envs.tasks import TASKS
from pdsketch_mech.lang.loader import load_domain, load_problem
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.planner import bindings
from pdsketch_mech.planner.bilevel import prepare_task
from pdsketch_mech.planner.execute import run_step
from pdsketch_mech.planner.refine import Refinement
from pdsketch_mech.planner.skeleton import skeleton_steps

from pdsketch_mech.samplers.budget import SamplerBudget
from pdsketch_mech.samplers.contact import ContactSampler
from pdsketch_mech.samplers.grasp import sample_grasps
from pdsketch_mech.samplers.interface import Sampler, SampleRequest
from pdsketch_mech.samplers.trajectory import grasp_motion
from pdsketch_mech.world.values import Grasp
from pdsketch_mech.world.attachment import compose
from pdsketch_mech.world.build import build_world

from conftest import ROOT
from plan_fakes import skeleton_of

HOOK_USE = os.path.join(ROOT, "domains", "mechanisms", "hook-use.pddl")
HOOK_PROBLEM = os.path.join(ROOT, "problems", "hook-use.pddl")


class EvenNumbers(Sampler):
    """Proposes 0, 1, 2, ... and accepts the even ones."""

    def __init__(self):
        self.verified = []

    def propose(self, world, request, rng, budget):
        n = 0
        while True:
            yield n
            n += 1

    def verify(self, world, request, candidate, rng):
        self.verified.append(candidate)
        return candidate if candidate % 2 == 0 else None


def test_draw_verifies_proposals_in_order_within_the_budget():
    sampler = EvenNumbers()
    values = list(sampler.draw(None, SampleRequest("s", (), ()), np.random.default_rng(0), budget=5))
    assert values == [0, 2, 4]
    assert sampler.verified == [0, 1, 2, 3, 4], "no proposal beyond the budget is verified"


def test_draw_stops_at_the_deadline():
    sampler = EvenNumbers()
    assert list(sampler.draw(None, SampleRequest("s", (), (), deadline=0.0), np.random.default_rng(0))) == []


def test_an_unknown_sampler_name_is_refused_with_the_known_ones():
    domain = load_domain([HOOK_USE]).domain
    streams = {s.name: s for s in domain.streams}
    streams["sample-grasp"] = dataclasses.replace(streams["sample-grasp"], sampler="grip")
    with pytest.raises(ValueError, match="no sampler named grip; known: contact, free-motion, grasp"):
        bindings.StepSampler(streams, {}, Counter())


def test_the_step_sampler_gives_its_budget_to_every_sampler_it_builds():
    """One SamplerBudget reaches the generic samplers (their visit budgets and the rest)."""
    domain = load_domain([HOOK_USE]).domain
    budget = SamplerBudget(grasp_proposals=7, contact_proposals=5, proposals=9, free_motion_proposals=3)
    samplers = bindings.StepSampler({s.name: s for s in domain.streams}, {}, Counter(), budget=budget).samplers
    by_name = {s.sampler or s.name: samplers[s.name] for s in domain.streams}
    assert (by_name["grasp"].budget, by_name["contact"].budget, by_name["placement"].budget) == (7, 5, 9)
    assert all(sampler.sampler_budget is budget for sampler in samplers.values())
    assert bindings.StepSampler({s.name: s for s in domain.streams}, {}, Counter()).samplers["sample-grasp"].budget == \
        SamplerBudget().grasp_proposals


def test_a_sampler_budget_refuses_negative_counts_and_chances_above_one():
    for wrong in ({"grasp_batch": -1}, {"motion_checks": -8000}, {"learned_explore": 1.5}):
        with pytest.raises(ValueError, match="SamplerBudget"):
            SamplerBudget(**wrong)
    with pytest.raises(dataclasses.FrozenInstanceError):
        SamplerBudget().proposals = 1   # one declared object, never changed in place


class Recording(Sampler):
    """Wraps a generic sampler and keeps every request it is given."""

    def __init__(self, inner: Sampler, requests: list):
        self.inner, self.requests, self.budget = inner, requests, inner.budget

    def propose(self, world, request, rng, budget):
        self.requests.append(request)
        return self.inner.propose(world, request, rng, budget)

    def verify(self, world, request, candidate, rng):
        return self.inner.verify(world, request, candidate, rng)


def test_a_mechanism_step_is_told_its_mechanism_index_poses_and_parents(monkeypatch):
    """The hook-use mechanism's contact (its 2nd step) is sampled knowing the mechanism, its
    objects, the step's index, where the tool and box are, and the grasp step 1 drew."""
    requests: list = []
    registry = dict(bindings.GENERIC_SAMPLERS)
    registry["contact"] = lambda budget: Recording(ContactSampler(budget), requests)
    monkeypatch.setattr(bindings, "GENERIC_SAMPLERS", registry)
    domain, problem = load_problem(HOOK_PROBLEM, [load_domain([HOOK_USE])])
    task, placeholders = prepare_task(domain, problem)
    macro = next(i for i, op in enumerate(task.operators) if op.name == "hook-use" and op.args[:2] == ("hook", "box"))
    steps = skeleton_steps(task, [macro])
    assert [(s.name, s.mechanism, s.index) for s in steps] == [
        ("grasp", "hook-use", 0), ("move-cont", "hook-use", 1), ("place", "hook-use", 2), ("grasp", "hook-use", 3)]
    with build_world(problem) as world:
        world.settle()
        sampler = bindings.StepSampler({s.name: s for s in domain.domain.streams}, placeholders, Counter())
        refinement = Refinement(skeleton_of(steps), world.snapshot(), world, task, sampler, np.random.default_rng(0))
        for _ in range(40):
            refinement.run(deadline=float("inf"), max_work=2)
            if requests:
                break
    assert requests, "the contact sampler was asked for a contact"
    request = requests[0]
    assert request.stream == "sample-contact" and request.input_names == ("?x", "?y", "?s")
    assert request.inputs == ("hook", "box", "table")
    assert (request.step.operator, request.step.mechanism, request.step.index) == ("move-cont", "hook-use", 1)
    assert request.step.mechanism_args == ("hook", "box", "table")
    assert set(request.poses) == {"hook", "box", "table"}
    assert any(isinstance(v, Grasp) and v.object == "hook" for v in request.parents.values()), \
        "the tool's grasp from the mechanism's first step is a parent value"


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_held_straight_tool_pulls_a_box_out_of_reach(seed):
    """A soup ladle held by its handle gets contacts that pull the box towards the robot:
    the tool is turned about the table's normal so its far end is behind the box (the old
    sampler matched faces and proposed no reachable pull)."""
    from dataclasses import replace
    from pdsketch_mech.envs.spec import Assets
    task = TASKS["hook"]
    pinned = tuple(replace(o, assets=Assets(("soup-ladle/0",), ("soup-ladle/0",))) if o.name == "tool" else o
                   for o in task.objects)
    problem = parse_text(sample(replace(task, objects=pinned), "train", 1, vary_assets=False).problem_text())
    rng = np.random.default_rng(0)
    with build_world(problem) as world:
        world.settle()
        start = world.snapshot()
        # The grasp nearest the robot: the handle's end, as a user would hold a ladle.
        grasps = list(sample_grasps(world, "tool", rng, max_attempts=120))
        grasp = min(grasps, key=lambda g: np.linalg.norm(compose(world.pose("tool"), g.in_object)[0][:2]))
        trajectory = grasp_motion(world, "tool", grasp, rng)
        assert trajectory is not None
        world.restore(start)
        run_step(world, "grasp", ("tool", "table", "#g", "#t"), {"#g": grasp, "#t": trajectory})
        assert world.attachment is not None
        request = SampleRequest("sample-contact", ("tool", "target", "table"), ("?x", "?y", "?s"))
        pulls = [c for c in ContactSampler().draw(world, request, np.random.default_rng(seed), budget=600)
                 if c.direction[0] < -0.7]
    assert pulls, "some verified contact pulls the box towards the robot"
