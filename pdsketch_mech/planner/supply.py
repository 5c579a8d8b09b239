"""Where the adaptive planner's new skeletons come from.

Skeletons come from the FF-guided symbolic search, in its order. To that search a mechanism
is one operator, so with every mechanism loaded, combinations of mechanisms come before the
plain plan of a problem that needs none (a tower of blocks). So with mechanisms loaded, a
second search over the basis operators alone runs beside it, the two taking turns (a
skeleton both find comes once): the plain plan comes as early as it does without
mechanisms. The basis-only search stops once a step is found dead where the scene began
(evidence.py), and what it found but was not handed out is forgotten: the problem needs
the scene changed first, which is what mechanisms are for, and the full search, which has
the basis operators too, goes on alone and finds those plans in its own order.

One that repeats a pristine step found dead (evidence.py) is deferred: kept aside and handed
out only once the searches have no more (or the planner's cap is reached); the searches
themselves put paths through dead steps last. The next WINDOW skeletons are kept in view, so
that the schedule can create a later one first when the evidence says it is more promising
(schedule.py): one skeleton with detours does not hold back the ones behind it.
"""
from __future__ import annotations

import time
from dataclasses import replace
from typing import Iterator, List, Optional, Set, Tuple

from ..symbolic.skeletons import iter_skeletons
from ..symbolic.task import StripsTask
from .evidence import Evidence
from .execute import contact_mask
from .skeleton import Skeleton, fixed_objects, pristine_keys, skeleton_steps, step_contexts, step_questions

WINDOW = 8   # upcoming skeletons in view for the schedule to choose from


def skeleton_order(task: StripsTask, deadline: Optional[float] = None,
                   evidence: Optional[Evidence] = None) -> Iterator[List[int]]:
    """Skeletons in the order the planner takes them from the symbolic search. With
    `evidence`, as refinement finds pristine steps dead: paths that would repeat one wait
    until the others run out, and paths are told apart by which of the objects of dead
    steps they have handled (a box out of reach hooked closer and put back is not the box
    where it lay)."""
    if evidence is None:
        return iter_skeletons(task, deadline=deadline)
    return iter_skeletons(task, deadline=deadline, handles=evidence.masks, relevant=lambda: evidence.flagged,
                          blocked=evidence.blocks_operator)


def without_mechanisms(task: StripsTask) -> StripsTask:
    """The task with its mechanism macros never applicable (operator ids kept): a macro that
    needs fact 0 both true and false."""
    never = 1
    return replace(task, operators=[replace(op, pre=op.pre | never, neg=op.neg | never, add=0, conditional=())
                                    if op.steps else op for op in task.operators])


class SkeletonSupply:
    """New skeletons for one plan, at most `max_skeletons` handed out, until `deadline`."""

    def __init__(self, task: StripsTask, evidence: Evidence, deadline: float, max_skeletons: int):
        self.task, self.evidence = task, evidence
        self.deadline, self.max_skeletons = deadline, max_skeletons
        self._searches = [skeleton_order(task, deadline, evidence)]
        if task.facts and any(op.steps for op in task.operators):
            self._searches.append(skeleton_order(without_mechanisms(task), deadline, evidence))
        self._yielded = [0] * len(self._searches)   # plans each search has yielded: their order
        self._turn = 0                          # which search yields next
        self._seen: Set[Tuple[int, ...]] = set()
        self._fixed = fixed_objects(task)
        self._observable = contact_mask(task)
        self._more = True                       # the search may have more
        self._deferred: List[Skeleton] = []     # in the order they were found
        self._window: List[Skeleton] = []       # the next ones from the search
        self.found = 0                          # skeletons found so far (their numbers)
        self.taken = 0                          # skeletons handed out
        self.deferrals = 0                      # skeletons set aside (statistics)
        self.search_s = 0.0                     # time in the symbolic search

    def upcoming(self) -> List[Skeleton]:
        """The skeletons `take` chooses from: the next WINDOW from the search (fewer near the
        cap) that repeat no dead pristine step; once the search has no more (or the cap is
        reached), the first deferred one."""
        t0 = time.perf_counter()
        if len(self._searches) > 1 and self._searches[1] is not None and self.evidence.deaths:
            self._stop_basis_only()   # a step is dead where the scene began (module docstring)
        if self._searching():  # a step of one may have died since it was looked at
            for skeleton in [s for s in self._window if self.evidence.blocks(s.pristine)]:
                self._window.remove(skeleton)
                self.defer(skeleton)
        del self._window[max(0, self.max_skeletons - self.taken):]   # the cap counts what is handed out
        while len(self._window) < min(WINDOW, self.max_skeletons - self.taken):
            skeleton = self._next()
            if skeleton is None:
                break
            self._window.append(skeleton)
        self.search_s += time.perf_counter() - t0
        return list(self._window) if self._window else self._deferred[:1]

    def take(self, skeleton: Skeleton) -> None:
        """Hand out `skeleton`, one of `upcoming()`."""
        self.taken += 1
        if skeleton in self._window:
            self._window.remove(skeleton)
        else:
            self._deferred.remove(skeleton)

    def defer(self, skeleton: Skeleton) -> None:
        """Set a skeleton aside until the search has no more (an active one whose pristine
        step died is handed back this way)."""
        self._deferred.append(skeleton)
        self.deferrals += 1

    def _next_plan(self) -> Optional[Tuple[List[int], int, int]]:
        """The next plan from the searches in turn, none twice, with its place in the order
        of the search that found it and which search that was (None: all are done)."""
        while any(search is not None for search in self._searches):
            self._turn %= len(self._searches)
            turn = self._turn
            self._turn += 1
            plan = None if self._searches[turn] is None else next(self._searches[turn], None)
            if plan is None:
                self._searches[turn] = None   # done (kept in place: the index names the search)
                continue
            self._yielded[turn] += 1
            if tuple(plan) not in self._seen:
                self._seen.add(tuple(plan))
                return plan, self._yielded[turn], turn
        return None

    def _stop_basis_only(self) -> None:
        self._searches[1] = None
        self._seen -= {tuple(s.plan) for s in self._window + self._deferred if s.source}
        self._window = [s for s in self._window if not s.source]
        self._deferred = [s for s in self._deferred if not s.source]

    def _searching(self) -> bool:
        return self._more and self.taken < self.max_skeletons and time.perf_counter() < self.deadline

    def _next(self) -> Optional[Skeleton]:
        """The next skeleton from the search that repeats no dead pristine step (None when
        the search has no more or the cap is reached)."""
        while self._searching():
            found = self._next_plan()
            if found is None:
                self._more = False
                break
            plan, order, source = found
            self.found += 1
            steps = skeleton_steps(self.task, plan)
            skeleton = Skeleton(order, plan, steps, pristine_keys(steps, self._fixed), step_contexts(steps), self.found,
                                source, step_questions(steps, self.task.init, self._observable))
            if not self.evidence.blocks(skeleton.pristine):
                return skeleton
            self.defer(skeleton)
        return None
