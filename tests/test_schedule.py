"""The adaptive schedule (planner/schedule.py): deep skeletons are created within a bounded
amount of work while the first skeleton keeps a fair share of it."""
from __future__ import annotations

import math

from pdsketch_mech.planner import schedule


def simulate(until_rank: int):
    """Skeletons that never succeed, SLICE units per turn: (total units when `until_rank` is
    created, the first skeleton's effort then)."""
    efforts = {}
    total = 0
    while True:
        turn = schedule.next_turn(efforts.items(), len(efforts) + 1)
        if turn == len(efforts) + 1:
            efforts[turn] = 0
            if turn == until_rank:
                return total, efforts[1] if 1 in efforts else 0
            continue
        efforts[turn] += schedule.SLICE
        total += schedule.SLICE


def test_the_hundred_and_seventh_skeleton_comes_within_a_bounded_amount_of_work():
    total, first = simulate(107)
    # ~ ENTRY * N ln N units (module docstring); 107 skeletons of a poking problem at ~10 units/s,
    # about 3.5 minutes
    assert total <= 1.3 * schedule.ENTRY * 107 * math.log(107) + 107 * schedule.SLICE
    assert total < 2200
    # ... while the first skeleton has had about 1 / ln N of the work
    assert first >= 0.6 * total / math.log(107)


def test_new_skeletons_wait_for_their_turn():
    # With one active skeleton that has had no work yet, it works before a second is created.
    assert schedule.next_turn([(1, 0)], 2) == 1
    assert schedule.next_turn([], 1) == 1
    assert schedule.next_turn([], None) is None


def test_first_slices_of_new_skeletons_take_a_minority_of_the_work():
    """A mechanism skeleton (rank 2, the first one dead at once) that needs 80 units to
    refine: new skeletons enter at what their first slice costs, so they take less of the
    work than the one being refined, not five times as much (Hook, ENTRY 1.5: 103 skeletons
    by then)."""
    efforts, total, dead = {}, 0, {1}
    while efforts.get(2, 0) < 80:
        active = [(r, e) for r, e in efforts.items() if r not in dead or e == 0]
        turn = schedule.next_turn(active, len(efforts) + 1)
        efforts.setdefault(turn, 0)
        work = 1 if turn in dead else schedule.SLICE
        efforts[turn] += work
        total += work
    assert len(efforts) <= 45
    assert total <= 6 * efforts[2]
