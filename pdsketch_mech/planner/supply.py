"""Where the adaptive planner's new skeletons come from, and how much each is worth.

Skeletons come from the FF-guided symbolic search, in its order. One that repeats a pristine
step found dead (pristine.py) is deferred: kept aside and handed out only once the search
has no more (or the planner's cap is reached). The next skeleton is looked at before the
planner decides to create it, so that its weight (detours.py) delays its creation as it
lowers its share of work afterwards.
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
        self._upcoming: Optional[Taken] = None  # the next one, looked at
        self._detours: Dict[Tuple[int, ...], Tuple[int, int]] = {}  # plan -> (flagged, detours)
        self.taken = 0                          # skeletons handed out
        self.deferrals = 0                      # skeletons set aside (statistics)
        self.search_s = 0.0                     # time in the symbolic search

    def peek(self) -> Optional[Taken]:
        """The skeleton `take` would hand out next, None if there is none."""
        t0 = time.perf_counter()
        if self._upcoming is None:
            self._upcoming = self._next()
        while self._upcoming is not None and self._searching() and self.memo.blocks(self._upcoming[2]):
            self.defer(self._upcoming)          # a step of it died since it was looked at
            self._upcoming = self._next()
        self.search_s += time.perf_counter() - t0
        return self._upcoming

    def take(self) -> Optional[Taken]:
        taken = self.peek()
        self._upcoming = None
        self.taken += taken is not None
        return taken

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
        """The next skeleton from the search that repeats no dead pristine step; a deferred
        one once the search has no more (or the cap is reached)."""
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
        return self._deferred.pop(0) if self._deferred else None
