"""Backjumping in the continuous search (planner/refine.py): when a step's visit finds
nothing, the step before it is revised only if it could have mattered: it names one of
the objects the failed step acts on, or it moved one."""
from types import SimpleNamespace

import numpy as np
import pytest

from pdsketch_mech.planner import refine
from pdsketch_mech.planner.refine import Refinement
from pdsketch_mech.planner.skeleton import Step

from plan_fakes import skeleton_of


class _Sampler:
    """Three values a visit for every step but the last, whose visits always run dry (a
    box the poke left deep in its tunnel); counts the values simulated per step."""

    def __init__(self, steps):
        self.steps, self.simulated = steps, [0] * len(steps)

    def samples(self, world, context, rng, parents):
        if context.operator == self.steps[-1].name:
            return iter(())
        index = next(k for k, s in enumerate(self.steps) if s.name == context.operator)
        return iter([{"#v": (index, n)} for n in range(3)])

    def note_simulated(self, values):
        self.simulated[values["#v"][0]] += 1

    def note_outcome(self, values, ok):
        pass


def _search(monkeypatch, place_args, moved):
    """A poke, a put-down of the tool and a grasp of the box that never succeeds: the
    values each step simulated in 60 units of work."""
    monkeypatch.setattr(refine, "execute_step", lambda *args, **kwargs: SimpleNamespace(ok=True))
    monkeypatch.setattr(refine, "observed_state", lambda task, world, vocabulary=None: 0)
    monkeypatch.setattr(refine, "contact_mask", lambda task, vocabulary=None: 0)
    steps = [Step("move-cont", ("tool", "box", "table"), 0), Step("place", place_args, 0),
             Step("grasp", ("box", "table"), 0)]
    bodies = {"tool": SimpleNamespace(fixed=False), "box": SimpleNamespace(fixed=False),
              "table": SimpleNamespace(fixed=True)}
    world = SimpleNamespace(bodies=bodies, restore=lambda snapshot: None, snapshot=object,
                            moved_since=lambda snapshot, name: name in moved)
    sampler = _Sampler(steps)
    search = Refinement(skeleton_of(steps), start=None, world=world, task=None, sampler=sampler, rng=np.random.default_rng(0))
    search.run(deadline=float("inf"), max_work=60)
    return sampler.simulated


def test_a_put_down_that_left_the_box_alone_is_skipped_back_over_to_the_next_poke(monkeypatch):
    pokes, places, _ = _search(monkeypatch, ("tool", "table"), moved=set())
    assert places == pokes       # one put-down per poke: the grasp's dead end is the poke's


@pytest.mark.parametrize("place_args, moved", [(("tool", "table"), {"box"}),   # the put-down moved the box
                                               (("tool", "box"), set())])      # or is put on it
def test_a_step_that_may_have_mattered_is_revised_before_the_one_before_it(monkeypatch, place_args, moved):
    pokes, places, _ = _search(monkeypatch, place_args, moved)
    assert places >= 2 * pokes   # up to three put-downs per poke, as chronological backtracking
