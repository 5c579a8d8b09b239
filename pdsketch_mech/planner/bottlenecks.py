"""Steps that keep failing from the same contact state: evidence shared between skeletons.

The same step (operator and objects) taken from the same symbolic contact state is the same
problem in every skeleton that has it: in Hook-then-Place-on-Slope, putting the box straight
on the slope after the hook, laying it on the slope as the ladle's blocker, and the same after
poking instead of hooking all ask whether the held box, with the ladle on the table, stays on
the slope once let go. Each skeleton's own failures already cost it its share (its effort,
schedule.py); what the others learnt about its steps did not.

`SharedOutcomes` counts, per (step, contact state before it), the simulated outcomes of every
skeleton; a skeleton's weight is the product over its steps of

    (S + 1) / (S + 1 + F / FAILURES_PER_HALVING)

where S and F are the step's successes and failures in the *other* skeletons (its own are in
its effort), never below FLOOR: a step that failed FAILURES_PER_HALVING times elsewhere and
never worked halves the share of every skeleton that takes it from that state. A skeleton
not yet created is weighed by everything seen so far. Only simulated values count: a sampler
that ran dry says more about the scene's continuous state than about the symbolic one
(pristine.py). Figures: results/HISTORY.md.
"""
from __future__ import annotations

from collections import defaultdict
from typing import Dict, List, Sequence, Tuple

from .pristine import StepKey, step_key
from .refine import Step

FAILURES_PER_HALVING = 8.0   # failures elsewhere, with no success, that halve a skeleton's share
FLOOR = 1.0 / 32.0           # the least weight: every skeleton keeps a share (the planner stays complete)

OutcomeKey = Tuple[StepKey, int]   # (the step in any skeleton, the observable contact state before it)


def outcome_keys(steps: Sequence[Step], init: int, observable: int) -> List[OutcomeKey]:
    """Each step's key: the step, and the skeleton's symbolic contact state before it."""
    keys, before = [], init
    for step in steps:
        keys.append((step_key(step), before & observable))
        before = step.expected
    return keys


class SharedOutcomes:
    """Simulated successes and failures per (step, state before it), by skeleton rank."""

    def __init__(self, init: int, observable: int, per_halving: float = FAILURES_PER_HALVING,
                 floor: float = FLOOR):
        self.init, self.observable = init, observable
        self.per_halving, self.floor = per_halving, floor
        self._totals: Dict[OutcomeKey, List[int]] = defaultdict(lambda: [0, 0])        # [successes, failures]
        self._by_rank: Dict[Tuple[OutcomeKey, int], List[int]] = defaultdict(lambda: [0, 0])

    def keys(self, steps: Sequence[Step]) -> List[OutcomeKey]:
        """The skeleton `steps`' step keys (`outcome_keys` from this task's initial state)."""
        return outcome_keys(steps, self.init, self.observable)

    def note(self, key: OutcomeKey, rank: int, ok: bool) -> None:
        """Skeleton `rank` simulated the step `key` names: as the skeleton expects or not."""
        self._totals[key][0 if ok else 1] += 1
        self._by_rank[(key, rank)][0 if ok else 1] += 1

    def counts(self, key: OutcomeKey, rank: int = 0) -> Tuple[int, int]:
        """(successes, failures) of the step in skeletons other than `rank` (0: all)."""
        total = self._totals.get(key)
        if total is None:
            return 0, 0
        own = self._by_rank.get((key, rank), (0, 0))
        return total[0] - own[0], total[1] - own[1]

    def weight(self, keys: Sequence[OutcomeKey], rank: int = 0) -> float:
        """The share of work of a skeleton with step keys `keys` (rank 0: not created yet),
        relative to one whose steps never failed elsewhere."""
        if not self._totals:
            return 1.0
        weight = 1.0
        for key in set(keys):   # a step repeated from the same state is one question
            successes, failures = self.counts(key, rank)
            if failures:
                weight *= (successes + 1) / (successes + 1 + failures / self.per_halving)
        return max(self.floor, weight)
