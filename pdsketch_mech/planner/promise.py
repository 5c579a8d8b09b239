"""How promising a skeleton's mechanism groundings look to their learned samplers.

A learned classifier scores every batch of proposals by log P(the proposal verifies and a
successful plan uses it) in the step's context (samplers/learned/ranked.py). Its best score
in a batch therefore also says how likely the *grounding* is to work: on a Hook instance the
contact scores peak around log 0.004 when the tool is the tool and log 4e-6 when an apple
is (medians of the batches' best), and the grasps that start the two groundings already
differ tenfold.
The generic samplers have no such opinion, so without learned samplers the planner gives
every skeleton of a given rank the same share of work (schedule.py), and most of a Hook
plan's work went into skeletons that use a distractor as the tool.

`GroundingPromise` keeps, per mechanism grounding and learned variable, the mean of the
batches' best scores, and weighs a skeleton by how far its groundings fall behind their best
rivals: exp(sum of the gaps), never below FLOOR, so every skeleton still gets its share in
the end (the planner stays complete) and a classifier wrong about a shape costs at most a
constant factor. Rivals are the groundings of the same mechanism that promise the same facts
(its :certified, grounded): the ways to reach the same subgoal. A Hook grounding that pulls
the tool within reach with the apple serves another subgoal and scores high for it; it says
nothing about which object should pull the box. Two rivals are compared on the sum over the
variables both were scored on. A grounding no batch has scored yet is not held back; so that
rivals are scored before any gets work, the planner probes upcoming skeletons that begin
with a mechanism's first step (probes.py).

An earlier weighting by a grounding's own best score, against no rival, helped where the
classifier was right and hurt where it was not, and was dropped (README).
"""
from __future__ import annotations

import math
from collections import defaultdict
from typing import Dict, Hashable, Iterable, List, Optional, Sequence, Tuple

FLOOR = 1.0 / 32.0   # the least share a skeleton keeps, relative to the most promising one

Grounding = Tuple[str, Tuple[str, ...]]   # (mechanism, its object arguments)
Promised = Hashable                        # what a grounding promises (its grounded :certified)


class GroundingPromise:
    """Mean best batch score per (grounding, variable), and the weights they give skeletons."""

    def __init__(self, floor: float = FLOOR):
        self.floor = floor
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
        """The groundings of `mechanism` promising `promised` that weights were asked about."""
        return sorted(self._rivals.get((mechanism, promised), ()))

    def mean(self, grounding: Grounding, variable: str) -> Optional[float]:
        """The mean best score of the grounding's batches for `variable` (None: none yet)."""
        return self._means(grounding).get(variable)

    def gap(self, grounding: Grounding, promised: Promised) -> float:
        """How far (in log probability, <= 0) the grounding's scores fall behind its best
        rival (a grounding of its mechanism that promises the same), each pair compared on
        the variables both have been scored on (summed): one grounding's grasps may score
        higher and another's contacts, and only the sum says which is ahead."""
        rivals = self._rivals[(grounding[0], promised)]
        rivals.add(grounding)
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

    def weight(self, groundings: Iterable[Tuple[Grounding, Promised]]) -> float:
        """A skeleton's share of work relative to one whose groundings are the best ones:
        the product over its mechanism groundings (each with what it promises), in
        [FLOOR, 1]. A grounding asked about becomes a rival of those promising the same (the
        planner asks about every active skeleton each turn)."""
        log_weight = sum(self.gap(g, promised) for g, promised in set(groundings))
        return max(self.floor, math.exp(min(0.0, log_weight)))
