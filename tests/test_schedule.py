"""The one score (planner/schedule.py): deep skeletons are created within a bounded amount of
work, the first skeleton keeps a fair share, and a skeleton's estimate multiplies its share."""
from __future__ import annotations

import math

from pdsketch_mech.planner import schedule
from pdsketch_mech.planner.budget import DEFAULT_BUDGET

SLICE = DEFAULT_BUDGET.slice


def simulate(until_rank: int, estimates=lambda rank: 1.0):
    """Skeletons that never succeed, SLICE units per turn, the next one from the search in
    view: (total units when `until_rank` is created, the first skeleton's effort then)."""
    efforts = {}
    total = 0
    while True:
        upcoming = len(efforts) + 1
        candidates = [(schedule.score(r, e, estimates(r), SLICE), (r,), r) for r, e in efforts.items()]
        candidates.append((schedule.score(upcoming, 0, estimates(upcoming), SLICE), (upcoming,), upcoming))
        turn = schedule.lowest(candidates)
        if turn == upcoming:
            efforts[turn] = 0
            if turn == until_rank:
                return total, efforts.get(1, 0)
            continue
        efforts[turn] += SLICE
        total += SLICE


def shares(estimates, units=4000):
    """Effort per rank after `units` of work among skeletons that never succeed."""
    efforts = {rank: 0 for rank in estimates}
    for _ in range(units // SLICE):
        turn = schedule.lowest([(schedule.score(r, e, estimates[r], SLICE), (r,), r) for r, e in efforts.items()])
        efforts[turn] += SLICE
    return efforts


def test_the_hundred_and_seventh_skeleton_comes_within_a_bounded_amount_of_work():
    total, first = simulate(107)
    # about SLICE * N ln N units (module docstring)
    assert total <= 1.3 * SLICE * 107 * math.log(107) + 107 * SLICE
    # ... while the first skeleton has had about 1 / ln N of the work
    assert first >= 0.6 * total / math.log(107)


def test_a_skeleton_at_the_floor_still_comes_and_gets_work():
    """Completeness: a low estimate delays a skeleton by a bounded factor, never for ever."""
    total, _ = simulate(30, estimates=lambda rank: 1 / 32 if rank == 30 else 1.0)
    assert total < 32 * 1.3 * SLICE * 30 * math.log(30)
    efforts = shares({rank: (1 / 32 if rank == 2 else 1.0) for rank in range(1, 6)}, units=20000)
    assert efforts[2] > 0


def test_new_skeletons_wait_for_their_turn():
    assert schedule.lowest([(schedule.score(1, 0, 1.0, SLICE), (1,), "first"), (schedule.score(2, 0, 1.0, SLICE), (2,), "new")]) == "first"
    assert schedule.lowest([]) is None
    assert schedule.lowest([(1.0, (3,), "later"), (1.0, (2,), "earlier")]) == "earlier"   # ties: the earlier rank


def test_a_skeleton_gets_about_its_estimate_times_the_work_of_its_rank():
    plain = shares({rank: 1.0 for rank in range(1, 21)})
    boosted = shares({rank: 8.0 if rank == 18 else 1.0 for rank in range(1, 21)})
    assert plain[18] < plain[3] / 4                      # rank alone: 1/18 of the first's share
    assert boosted[18] > boosted[3] and boosted[18] > 4 * plain[18]


def test_mechanisms_have_the_head_start_then_plain_skeletons_their_share():
    """The contract's schedule (schedule.plain_owed): while both groups have work, the
    mechanisms' skeletons take the first `head_start` units, and after that the plain ones
    get `plain_share` of every unit, so a plain plan that needs W units comes within
    head_start + W / plain_share in all, whatever the mechanisms' skeletons cost."""
    budget = DEFAULT_BUDGET
    work = plain = 0
    first_plain_at = None
    while plain < 300:
        turn_plain = schedule.plain_owed(work, plain, budget.head_start, budget.plain_share)
        if turn_plain and first_plain_at is None:
            first_plain_at = work
        work += SLICE
        plain += SLICE if turn_plain else 0
    assert first_plain_at is not None and budget.head_start <= first_plain_at <= budget.head_start + SLICE
    assert work <= budget.head_start + 300 / budget.plain_share + 2 * SLICE
    assert abs(plain / (work - budget.head_start) - budget.plain_share) < 0.02


def test_plain_skeletons_are_owed_nothing_while_they_keep_their_share():
    budget = DEFAULT_BUDGET
    assert not schedule.plain_owed(budget.head_start, 0, budget.head_start, budget.plain_share)
    assert schedule.plain_owed(budget.head_start + 10, 0, budget.head_start, budget.plain_share)
    assert not schedule.plain_owed(budget.head_start + 1000, 1000, budget.head_start, budget.plain_share)
