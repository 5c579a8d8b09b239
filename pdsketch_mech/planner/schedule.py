"""The one score by which the adaptive planner chooses what to work on next.

Every skeleton, created or upcoming, has

    score = (effort + SLICE) * rank / estimate

where rank is the order in which skeletons were created (the search's order, shorter and
cheaper skeletons first, unless the evidence passed one over), effort the work units it has
had, and estimate the evidence's chance that it is refined relative to one nothing is known
about (evidence.py, at least FLOOR). The lowest score gets the next SLICE units. The
upcoming skeletons compete as the next rank (effort 0): the one with the highest estimate is
created when its score is the lowest, the search's order deciding ties. The same score
chooses among the upcoming skeletons and shares the work, so skeleton k gets about
estimate_k / k of the work of the first, and the N-th is created after about SLICE * N ln N
units when nothing is known.

Completeness: an active skeleton's score grows by at least SLICE * rank / (max estimate) per
turn it gets, while another's is at most (effort + SLICE) * rank / FLOOR: no skeleton waits
for ever, and every upcoming one is created after finitely many turns. Work is counted in
units (a value drawn and simulated, a sampler running dry), never in seconds, so the same seed
gives the same plan whatever the machine's load.
"""
from __future__ import annotations

from typing import Iterable, Optional, Tuple

SLICE = 3   # work units per turn, values tried at a step before backtracking (refine.py), and
            # what a new skeleton is worth: a turn is one visit of a step


def score(rank: int, effort: int, estimate: float = 1.0) -> float:
    """Lower works first (module docstring)."""
    return (effort + SLICE) * rank / estimate


def lowest(candidates: Iterable[Tuple[float, tuple, object]]) -> Optional[object]:
    """The item of the (score, tie-break, item) candidates with the lowest score, the lowest
    tie-break on ties (a tuple: rank first); None if there is none."""
    best = min(candidates, key=lambda c: (c[0], c[1]), default=None)
    return None if best is None else best[2]
