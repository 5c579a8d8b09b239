"""How promising a skeleton's mechanism groundings look to their learned samplers.

A learned classifier scores every batch of proposals by log P(the proposal verifies and a
successful plan uses it) in the step's context (samplers/learned/ranked.py). Its best score
in a batch therefore also says how likely the *grounding* is to work: a tool that is a tool
scores far above an apple in the tool's role. The generic samplers have no such opinion.

`GroundingPromise` keeps, per mechanism grounding and learned variable, the mean of the
batches' best scores; a grounding's `gap` is how far (log probability, <= 0) it falls behind
its best rival, and enters the evidence's estimate of a skeleton (evidence.py) as one more
factor, bounded below by the estimate's floor: a classifier wrong about a shape costs at most
a constant factor. Rivals are the groundings of the same mechanism that promise the same
facts (its :certified, grounded): the ways to reach the same subgoal. Groundings become
rivals when the planner registers the skeletons they are in (`register`); the probes score
upcoming ones before they get work (probes.py).
"""
from __future__ import annotations

import math
from collections import defaultdict
from typing import Dict, Hashable, Iterable, List, Optional, Sequence, Tuple

Grounding = Tuple[str, Tuple[str, ...]]   # (mechanism, its object arguments)
Promised = Hashable                        # what a grounding promises (its grounded :certified)


class GroundingPromise:
    """Mean best batch score per (grounding, variable), and the gaps between rivals."""

    def __init__(self) -> None:
        # grounding -> variable -> [sum of the batches' best scores, batches]
        self._stats: Dict[Grounding, Dict[str, List[float]]] = defaultdict(dict)
        self._rivals: Dict[Tuple[str, Promised], set] = defaultdict(set)  # groundings by what they promise

    def observe(self, mechanism: str, args: Sequence[str], variable: str, best_log_score: float) -> None:
        """A batch of proposals for `variable` of `mechanism` grounded on `args` was scored,
        its best at `best_log_score`."""
        if math.isfinite(best_log_score):
            total = self._stats[(mechanism, tuple(args))].setdefault(variable, [0.0, 0])
            total[0] += best_log_score
            total[1] += 1

    def rivals(self, mechanism: str, promised: Promised) -> List[Grounding]:
        """The registered groundings of `mechanism` promising `promised`."""
        return sorted(self._rivals.get((mechanism, promised), ()))

    def mean(self, grounding: Grounding, variable: str) -> Optional[float]:
        """The mean best score of the grounding's batches for `variable` (None: none yet)."""
        return self._means(grounding).get(variable)

    def gap(self, grounding: Grounding, promised: Promised) -> float:
        """How far (in log probability, <= 0) the grounding's scores fall behind its best
        rival (a grounding of its mechanism that promises the same), each pair compared on
        the variables both have been scored on (summed): one grounding's grasps may score
        higher and another's contacts, and only the sum says which is ahead."""
        rivals = self._rivals.get((grounding[0], promised), ())
        own = self._means(grounding)
        gap = 0.0
        for rival in rivals:
            if rival != grounding:
                theirs = self._means(rival)
                shared = own.keys() & theirs.keys()
                gap = min(gap, sum(own[v] - theirs[v] for v in shared))
        return gap

    def _means(self, grounding: Grounding) -> Dict[str, float]:
        return {variable: total / n for variable, (total, n) in self._stats.get(grounding, {}).items()}

    def register(self, groundings: Iterable[Tuple[Grounding, Promised]]) -> None:
        """Make each grounding a rival of the others of its mechanism promising the same."""
        for grounding, promised in groundings:
            self._rivals[(grounding[0], promised)].add(grounding)
