"""Skeletons that get past a dead step (planner/unblocked.py): a step found dead as the scene
began (the grasp of a box out of reach) that simulates in a skeleton, after its earlier steps
changed the scene (a hook pulled the box closer), earns every skeleton that begins with the
same steps a larger share of the work than its rank gives it (schedule.py)."""
from types import SimpleNamespace

import numpy as np

from pdsketch_mech.planner import refine, schedule
from pdsketch_mech.planner.pristine import PristineFailures, pristine_keys
from pdsketch_mech.planner.refine import Refinement, Step
from pdsketch_mech.planner.unblocked import UNBLOCK_GAIN, UnblockedPrefixes


class _Sampler:
    """One value a visit for every step; counts nothing."""

    def samples(self, world, context, rng, parents):
        return iter([{"#v": context.operator}])

    def note_simulated(self, values):
        pass

    def note_outcome(self, values, ok):
        pass


def _refine(monkeypatch, steps, memo):
    monkeypatch.setattr(refine, "execute_step", lambda *args: SimpleNamespace(ok=True))
    monkeypatch.setattr(refine, "observed_state", lambda task, world: 0)
    monkeypatch.setattr(refine, "contact_mask", lambda task: 0)
    world = SimpleNamespace(bodies={}, restore=lambda snapshot: None, snapshot=object,
                            moved_since=lambda snapshot, name: True)
    search = Refinement(steps, start=None, world=world, task=None, sampler=_Sampler(),
                        rng=np.random.default_rng(0), pristine=pristine_keys(steps, {"table"}), memo=memo)
    search.run(deadline=float("inf"), max_work=len(steps) - 1)  # stops before the last step
    return search


def _dead_grasp_of_the_box() -> PristineFailures:
    memo = PristineFailures()
    for _ in range(memo.dead_after):
        memo.ran_dry(("grasp", ("box", "table")))
    assert memo.is_dead("grasp", ("box", "table", "#g2"))
    return memo


def _hook(*after):
    return [Step("grasp", ("tool", "table", "#g1"), 0), Step("move-cont", ("tool", "box", "table", "#c"), 0),
            Step("grasp", ("box", "table", "#g2"), 0)] + list(after)


def test_a_dead_grasp_that_simulates_after_a_hook_counts_as_unblocked(monkeypatch):
    search = _refine(monkeypatch, _hook(Step("place", ("box", "slope", "#p"), 0)), _dead_grasp_of_the_box())
    assert search.unblocked == {2}


def test_every_skeleton_that_begins_with_the_unblocking_steps_shares_the_evidence():
    straight_on = _hook(Step("place", ("box", "slope", "#p1"), 0))
    with_blocker = _hook(Step("place", ("box", "table", "#p2"), 0), Step("grasp", ("tool", "table", "#g3"), 0))
    poke = [Step("grasp", ("tool", "table", "#g1"), 0), Step("move-cont", ("tool", "box", "table", "#c9"), 0),
            Step("place", ("tool", "table", "#p3"), 0), Step("grasp", ("box", "table", "#g2"), 0)]
    prefixes = UnblockedPrefixes()
    assert prefixes.weight(with_blocker) == 1.0
    prefixes.note(straight_on, {2})
    # the same first three steps (their stream outputs named apart): the same scene
    with_blocker[1] = Step("move-cont", ("tool", "box", "table", "#c7"), 0)
    assert prefixes.weight(straight_on) == prefixes.weight(with_blocker) == UNBLOCK_GAIN
    assert prefixes.weight(poke) == 1.0 and prefixes.weight(with_blocker[:2]) == 1.0
    # the box grasped again after it was put down within reach: no new evidence
    regrasp = with_blocker + [Step("grasp", ("box", "table", "#g4"), 0)]
    prefixes.note(regrasp, {2, len(regrasp) - 1})
    assert prefixes.weight(regrasp) == UNBLOCK_GAIN


def test_steps_that_were_never_dead_unblock_nothing(monkeypatch):
    steps = [Step("grasp", ("tool", "table", "#g1"), 0), Step("move-cont", ("tool", "box", "table"), 0),
             Step("grasp", ("tool", "table", "#g2"), 0), Step("place", ("tool", "slope", "#p"), 0)]
    search = _refine(monkeypatch, steps, _dead_grasp_of_the_box())
    assert search.unblocked == set()


def _shares(weights, units=4000):
    """Effort per rank after `units` of work among skeletons that never succeed."""
    efforts = {rank: 0 for rank in weights}
    for _ in range(units // schedule.SLICE):
        turn = schedule.next_turn([(r, e, weights[r]) for r, e in efforts.items()], None)
        efforts[turn] += schedule.SLICE
    return efforts


def test_a_skeleton_past_a_dead_step_gets_more_work_than_its_rank_gives_it():
    plain = _shares({rank: 1.0 for rank in range(1, 21)})
    boosted = _shares({rank: UNBLOCK_GAIN if rank == 18 else 1.0 for rank in range(1, 21)})
    assert plain[18] < plain[3] / 4                      # rank alone: 1/18 of the first's share
    assert boosted[18] > boosted[3] and boosted[18] > 4 * plain[18]
