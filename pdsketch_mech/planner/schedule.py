"""How the adaptive planner shares work between skeletons, old and new.

PDDLStream's adaptive algorithm balances creating new skeletons against refining the ones
it has. Here every skeleton k (in the order the symbolic search produces them: shorter
and cheaper first) has a priority score

    (effort_k + ENTRY) * k ** EXPONENT

where effort_k is the work it has had; the lowest score works next, for one SLICE. The next
skeleton not yet created competes too, with effort 0: it is created when its score, ENTRY *
k ** EXPONENT, is the lowest. So skeleton k gets about k ** EXPONENT times less work than
the first, and reaching the N-th skeleton costs about ENTRY * N * ln N units in all
(EXPONENT = 1): the Hook task's basis-only tool-use skeleton (the 26th) is refined after
some hundreds of units (below), while the first skeletons keep the larger share. Measured
on the Hook task: EXPONENT = 1/2 reaches deep skeletons sooner but starves the hook-use
mechanism's skeleton (167 s instead of 65 s, seed 0); 3/2 starves the deep ones (basis-only
unsolved in 90 s; 61 s with 1). ENTRY sets how fast new skeletons come: skeleton 1's share
of the work is about 1 / ln N whatever ENTRY is, but every new skeleton costs a first SLICE
of work when it comes, so the smaller ENTRY is against SLICE, the more of the work goes
into first slices. ENTRY = SLICE: a new skeleton is worth what its first turn costs.
Measured against ENTRY 1.5 on Table 1's Hook, Lever and Poking dev instances with learned
samplers (bench mechanisms, 10 trials each, same seeds; values simulated, which the
machine's load does not change): Hook's median 215 -> 96 values (skeletons created
40/25/171/62/103 -> 15/12/84/32/8 on the first five), Poking 64 -> 28, Lever 20 -> 20 (but
lever-dev-4 went from solved in 353 s to unsolved, in 1500 s too: its lever grounding got
823 units and never tipped the plate far enough to grasp it, and the old schedule had
reached the skeleton that solved it, after some 250 others, in time). The price: a skeleton
far down the order comes later (the 107th after ~2000 units instead of ~950, the Hook
task's basis-only tool-use skeleton, the 26th, after ~350 instead of ~180; tests). Earlier
measurements with ENTRY 4 / 2 / 1.5 and a first slice of 4: the 5-step two-poke skeleton
(#107 on a long-tunnel poking problem) created at 181 / 121 / 105 s. Work is counted in
units (samples drawn and simulated, samplers running dry), never in seconds: the same seed
gives the same plan whatever the machine's load.

A skeleton's score is divided by its weight: DETOUR_WEIGHT per detour no dead step explains
(detours.py), times, with learned samplers, how its mechanism groundings compare with the
best ones in the classifiers' eyes (promise.py), times UNBLOCK_GAIN per prefix it begins
with that got past a step found dead as the scene began (unblocked.py). A skeleton of weight
w gets about w times the share of work of its rank. The next few skeletons are looked at
before one is created (supply.py), and the first with the fewest detours comes next: its
weight delays its creation too, but one with detours does not hold back those behind it.
"""
from __future__ import annotations

from typing import Iterable, Optional, Sequence, Tuple

ENTRY = 4.0         # work units a new skeleton is worth before it starts: its first SLICE
EXPONENT = 1.0
SLICE = 4           # work units per turn


def score(rank: int, effort: int, weight: float = 1.0) -> float:
    return (effort + ENTRY) * rank ** EXPONENT / weight


def next_turn(active: Iterable[Tuple[int, ...]], next_rank: Optional[int], next_weight: float = 1.0) -> Optional[int]:
    """The rank of the skeleton to work on next among `active` (rank, effort[, weight])
    tuples, or `next_rank` if a new skeleton (of weight `next_weight`) should be created
    first (None: no more skeletons). Returns None when there is nothing left at all."""
    best: Optional[Tuple[float, int]] = None
    for rank, effort, *weight in active:
        candidate = (score(rank, effort, *weight), rank)
        if best is None or candidate < best:
            best = candidate
    if next_rank is not None and (best is None or score(next_rank, 0, next_weight) <= best[0]):
        return next_rank
    return None if best is None else best[1]


def heaviest(weights: Sequence[float]) -> int:
    """The index of the largest of `weights` (the upcoming skeletons' detour weights), the
    first (the search's order) on ties."""
    return max(range(len(weights)), key=lambda i: (weights[i], -i))
