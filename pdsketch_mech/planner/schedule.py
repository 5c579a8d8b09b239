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

With mechanisms loaded, two such searches run side by side (side_by_side.py), and
`plain_owed` says whose turn it is: the mechanisms' search has a head start, then the basis
operators' own search is owed a fixed share of the work, so a mechanism never takes more
from a problem the basis operators solve than that share allows.
"""
from __future__ import annotations

from typing import Iterable, Optional, Tuple


def score(rank: int, effort: int, estimate: float, slice_units: int) -> float:
    """Lower works first (module docstring)."""
    return (effort + slice_units) * rank / estimate


def plain_owed(work: int, plain_work: int, head_start: int, plain_share: float) -> bool:
    """With mechanisms loaded, whether the basis operators' own search (`plain_work` of the
    `work` of both) is behind the share it is owed: `plain_share` of all done beyond the
    `head_start` the mechanisms' search has to itself. So a problem the basis operators solve in
    W units is solved within about head_start + W / plain_share, whatever is loaded."""
    beyond = work - plain_work - head_start
    return beyond > 0 and plain_work * (1.0 - plain_share) < plain_share * beyond


def lowest(candidates: Iterable[Tuple[float, tuple, object]]) -> Optional[object]:
    """The item of the (score, tie-break, item) candidates with the lowest score, the lowest
    tie-break on ties (a tuple: rank first); None if there is none."""
    best = min(candidates, key=lambda c: (c[0], c[1]), default=None)
    return None if best is None else best[2]
