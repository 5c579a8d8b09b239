"""The one score by which the adaptive planner chooses what to work on next.

Every skeleton, created or upcoming, has

    score = (effort + slice) * rank / estimate

where rank is the order in which the planner created skeletons (1, 2, ...: the symbolic
search's order, cheapest first, unless the evidence had one created earlier), effort the
work units it has had, and estimate the evidence's chance that it is refined relative to
one nothing is known about (evidence.py). The lowest score gets the next `slice` units.
The upcoming skeletons compete as the next rank (effort 0): the one with the highest
estimate is created when its score is the lowest, the search's order deciding ties. The
same score chooses among the upcoming skeletons and shares the work, so skeleton k gets
about estimate_k / k of the work of the first, and the N-th is created after about
slice * N ln N units when nothing is known. docs/planner.md argues completeness from it.
"""
from __future__ import annotations

from typing import Iterable, Optional, Tuple


def score(rank: int, effort: int, estimate: float, slice_units: int) -> float:
    """Lower works first (module docstring)."""
    return (effort + slice_units) * rank / estimate


def lowest(candidates: Iterable[Tuple[float, tuple, object]]) -> Optional[object]:
    """The item of the (score, tie-break, item) candidates with the lowest score, the lowest
    tie-break on ties (a tuple: rank first); None if there is none."""
    best = min(candidates, key=lambda c: (c[0], c[1]), default=None)
    return None if best is None else best[2]
