"""Where the adaptive planner's new skeletons come from, and how much each is worth.

Skeletons come from the FF-guided symbolic search, in its order. One that repeats a pristine
step found dead (pristine.py) is deferred: kept aside and handed out only once the search
has no more (or the planner's cap is reached). The next WINDOW skeletons are looked at before
the planner creates one, and it creates the first of those with the fewest unexplained
detours (detours.py): a skeleton's detours delay its own creation as they lower its share of
work afterwards, but not the creation of the skeletons behind it (with only the next one
looked at, one with three detours held back every later skeleton). The choice reads the
detours and, with learned samplers, the promise of the skeleton's mechanism groundings
(promise.py; probed before the skeleton is created, probes.py), not the prefixes: skeletons
that begin with a prefix past a dead step (unblocked.py) jumping the queue too took the work
from the one that solved a Lever instance. Figures: results/HISTORY.md.
"""
from __future__ import annotations

import time
from typing import Dict, Iterator, List, Optional, Tuple

from ..symbolic.skeletons import iter_skeletons
from ..symbolic.task import StripsTask
from .detours import detour_weight, unexplained_detours
from .pristine import PristineFailures, StepKey, fixed_objects, pristine_keys
from .refine import Step, skeleton_steps

# A skeleton as the planner takes it: operator ids, its steps, and their pristine keys.
Taken = Tuple[List[int], List[Step], List[Optional[StepKey]]]

WINDOW = 8   # skeletons looked at ahead of creating one


def skeleton_order(task: StripsTask, deadline: Optional[float] = None,
                   memo: Optional[PristineFailures] = None) -> Iterator[List[int]]:
    """Skeletons in the order the planner takes them from the symbolic search. With `memo`,
    as refinement finds pristine steps dead (pristine.py): paths that would repeat one wait
    until the others run out, and paths are told apart by which of the objects of dead
    steps they have handled (a box out of reach hooked closer and put back is not the box
    where it lay)."""
    if memo is None:
        return iter_skeletons(task, deadline=deadline)
    masks = memo.attach(task)
    return iter_skeletons(task, deadline=deadline, handles=masks, relevant=lambda: memo.flagged,
                          blocked=memo.blocks_operator)


class SkeletonSupply:
    """New skeletons for one plan, at most `max_skeletons` from the search, until `deadline`."""

    def __init__(self, task: StripsTask, memo: PristineFailures, deadline: float, max_skeletons: int):
        self.task, self.memo = task, memo
        self.deadline, self.max_skeletons = deadline, max_skeletons
        self._search = skeleton_order(task, deadline, memo)
        self._fixed = fixed_objects(task)
        self._more = True                       # the search may have more
        self._deferred: List[Taken] = []        # in the order they were found
        self._window: List[Taken] = []          # the next ones, looked at (upcoming)
        self._detours: Dict[Tuple[int, ...], Tuple[int, int]] = {}  # plan -> (flagged, detours)
        self.taken = 0                          # skeletons handed out
        self.deferrals = 0                      # skeletons set aside (statistics)
        self.search_s = 0.0                     # time in the symbolic search

    def upcoming(self) -> List[Taken]:
        """The skeletons `take` chooses from: the next WINDOW from the search (fewer near the
        cap) that repeat no dead pristine step, in its order; once the search has no more
        (or the cap is reached), the first deferred one."""
        t0 = time.perf_counter()
        if self._searching():  # a step of one may have died since it was looked at
            blocked = [self.memo.blocks(t[2]) for t in self._window]
            for taken in (t for t, dead in zip(self._window, blocked) if dead):
                self.defer(taken)
            self._window = [t for t, dead in zip(self._window, blocked) if not dead]
        del self._window[max(0, self.max_skeletons - self.taken):]   # the cap counts what is handed out
        while len(self._window) < min(WINDOW, self.max_skeletons - self.taken):
            taken = self._next()
            if taken is None:
                break
            self._window.append(taken)
        self.search_s += time.perf_counter() - t0
        return list(self._window) if self._window else self._deferred[:1]

    def peek(self) -> Optional[Taken]:
        """The first of the upcoming skeletons, None if there is none."""
        window = self.upcoming()
        return window[0] if window else None

    def take(self, index: int = 0) -> Optional[Taken]:
        """Hand out the `index`-th upcoming skeleton (None if there is none)."""
        window = self.upcoming()
        if index >= len(window):
            return None
        self.taken += 1
        return self._window.pop(index) if self._window else self._deferred.pop(0)

    def defer(self, taken: Taken) -> None:
        """Set a skeleton aside until the search has no more (an active one whose pristine
        step died is handed back this way)."""
        self._deferred.append(taken)
        self.deferrals += 1

    def detours(self, plan: List[int]) -> int:
        """The plan's unexplained detours given the steps dead so far (detours.py)."""
        key = tuple(plan)
        known = self._detours.get(key)
        if known is None or known[0] != self.memo.flagged:
            count = unexplained_detours(self.task, plan, self.memo.masks, self.memo.flagged)
            known = self._detours[key] = (self.memo.flagged, count)
        return known[1]

    def weight(self, plan: List[int]) -> float:
        return detour_weight(self.detours(plan))

    def _searching(self) -> bool:
        return self._more and self.taken < self.max_skeletons and time.perf_counter() < self.deadline

    def _next(self) -> Optional[Taken]:
        """The next skeleton from the search that repeats no dead pristine step (None when
        the search has no more or the cap is reached)."""
        while self._searching():
            plan = next(self._search, None)
            if plan is None:
                self._more = False
                break
            steps = skeleton_steps(self.task, plan)
            keys = pristine_keys(steps, self._fixed)
            if not self.memo.blocks(keys):
                return plan, steps, keys
            self.defer((plan, steps, keys))
        return None
