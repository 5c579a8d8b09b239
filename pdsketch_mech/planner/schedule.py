"""How the adaptive planner shares work between skeletons, old and new.

PDDLStream's adaptive algorithm balances creating new skeletons against refining the ones
it has. Here every skeleton k (in the order the symbolic search produces them: shorter
and cheaper first) has a priority score

    (effort_k + ENTRY) * k ** EXPONENT

where effort_k is the work it has had; the lowest score works next, for one SLICE. The next
skeleton not yet created competes too, with effort 0: it is created when its score, ENTRY *
k ** EXPONENT, is the lowest. So skeleton k gets about k ** EXPONENT times less work than
the first, and reaching the N-th skeleton costs about ENTRY * N * ln N units in all
(EXPONENT = 1). A smaller EXPONENT reaches deep skeletons sooner but starves a mechanism's
skeleton; a larger one starves the deep ones. ENTRY = SLICE: a new skeleton is worth what its
first turn costs, so first slices of new skeletons do not take most of the work. Work is
counted in units (samples drawn and simulated, samplers running dry), never in seconds: the
same seed gives the same plan whatever the machine's load.

A skeleton's score is divided by its weight: DETOUR_WEIGHT per detour no dead step explains
(detours.py), times, with learned samplers, how its mechanism groundings compare with the
best ones in the classifiers' eyes (promise.py), times UNBLOCK_GAIN per prefix it begins
with that got past a step found dead as the scene began (unblocked.py), times the failures
of its steps elsewhere (bottlenecks.py). A skeleton of weight w gets about w times the share
of work of its rank. results/HISTORY.md has the runs that chose the constants.
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
