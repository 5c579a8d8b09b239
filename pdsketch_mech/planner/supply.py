"""Where the adaptive planner's new skeletons come from.

Skeletons come from the FF-guided symbolic search in two orders that take turns (a
skeleton both find comes once, at the first place either gives it): the *unit* order, in
which a mechanism is one action (the paper's: a composition of three mechanisms is a plan of
three actions), and the *priced* order, in which a mechanism costs what its basis steps
cost and, at equal cost, the steps written out come first (symbolic/skeletons.py). In the
priced order a plan's place follows what it costs to do, not how many actions it names. With
no mechanism loaded the two orders are one. With mechanisms loaded the planner runs this
supply twice (side_by_side.py): one over the basis operators alone, one that hands out only
the skeletons that use a mechanism. The next `window` skeletons are
kept in view, so that the schedule can create a later one first when the evidence says it
is more promising (schedule.py): one skeleton with detours does not hold back the ones
behind it.

One that repeats a pristine step believed dead (evidence.py) is deferred: kept aside, in the
order it was found, and handed out again as soon as that step is believed alive again (the
evidence revisits its verdicts on a growing schedule), or once the search has no more; the
search itself puts paths through dead steps last, and gives them without end once only those
are left, so it is asked for at most `lookahead` in a row. Nothing is dropped and nothing is capped:
skeletons keep coming for as long as the planner asks.
"""
from __future__ import annotations

import time
from typing import Iterator, List, Optional, Set, Tuple

from ..operators.vocabulary import BASIS, Vocabulary
from ..symbolic.skeletons import iter_skeletons
from ..symbolic.task import StripsTask
from .budget import DEFAULT_BUDGET, SearchBudget
from .evidence import Evidence
from .execute import contact_mask
from .skeleton import Skeleton, fixed_objects, pristine_keys, skeleton_steps, step_contexts, step_questions


def skeleton_order(task: StripsTask, deadline: Optional[float] = None, evidence: Optional[Evidence] = None,
                   budget: SearchBudget = DEFAULT_BUDGET, priced: bool = False) -> Iterator[List[int]]:
    """Skeletons in the order the planner takes them from the symbolic search. With
    `evidence`, as refinement finds pristine steps dead: paths that would repeat one wait
    until the others run out or the step proves feasible after all, and paths are told apart
    by which of the objects of dead steps they have handled (a box out of reach hooked
    closer and put back is not the box where it lay). `priced`: the cost model."""
    bounds = dict(max_visits=budget.skeleton_visits, max_length=budget.skeleton_cost, deadline=deadline,
                  priced=priced)
    if evidence is None:
        return iter_skeletons(task, **bounds)
    return iter_skeletons(task, handles=evidence.masks, relevant=lambda: evidence.flagged,
                          blocked=evidence.blocks_operator, revived=lambda: evidence.cleared, **bounds)


def planner_order(task: StripsTask, deadline: Optional[float] = None,
                  budget: SearchBudget = DEFAULT_BUDGET) -> Iterator[List[int]]:
    """Plans in the order the planner creates skeletons while nothing is known of the scene:
    the two orders in turns, none twice (what `plan --skeletons` lists)."""
    supply = SkeletonSupply(task, Evidence(task), float("inf") if deadline is None else deadline, budget)
    while True:
        found = supply._next_plan()
        if found is None:
            return
        yield found[0]


class SkeletonSupply:
    """New skeletons for one plan, until `deadline`."""

    def __init__(self, task: StripsTask, evidence: Evidence, deadline: float, budget: SearchBudget = DEFAULT_BUDGET,
                 vocabulary: Vocabulary = BASIS, mechanisms_only: bool = False):
        """`mechanisms_only`: hand out only skeletons that use a mechanism (the basis
        operators' own search, beside this one, has the others: side_by_side.py)."""
        self.task, self.evidence, self.deadline, self.budget = task, evidence, deadline, budget
        self.mechanisms_only = mechanisms_only
        self.passed_plain = False   # the last ask passed over plain plans and found nothing else
        self.vocabulary = vocabulary
        # With mechanisms loaded the unit order goes first (a mechanism that does the job is
        # the first skeleton), the priced one second. (Priced first cost Table 1 on dev
        # a third more values simulated: results/HISTORY.md.)
        self._searches: List[Optional[Iterator[List[int]]]] = [skeleton_order(task, deadline, evidence, budget,
                                                                             priced=True)]
        if any(op.steps for op in task.operators):   # mechanisms loaded: the unit order too
            self._searches.append(skeleton_order(task, deadline, evidence, budget))
        self._yielded = [0] * len(self._searches)   # plans each search has yielded: their order
        self._turn = 0                              # the search that yielded last: the unit order goes first
        self._seen: Set[Tuple[int, ...]] = set()
        self._fixed = fixed_objects(task, vocabulary)
        self._observable = contact_mask(task, vocabulary)
        self._deferred: List[Skeleton] = []     # in the order they were found
        self._window: List[Skeleton] = []       # the next ones from the search
        self._revivals = 0                      # the evidence's revived steps looked at
        self._cleared = 0                       # the evidence's cleared steps looked at
        self._only_dead: Optional[Tuple[int, int]] = None   # the evidence's (revivals, cleared) when the
        # search last gave nothing but paths through dead steps: until a verdict changes, it still does
        self.found = 0                          # skeletons found so far (their numbers)
        self.taken = 0                          # skeletons handed out
        self.deferrals = 0                      # skeletons set aside (statistics)
        self.returned = 0                       # deferred skeletons handed back (statistics)
        self.search_s = 0.0                     # time in the symbolic search

    def upcoming(self) -> List[Skeleton]:
        """The skeletons `take` chooses from: those in the window (the next from the search,
        and deferred ones whose dead step is believed alive again) that repeat no dead
        pristine step; once the search has no more, the first deferred one."""
        t0 = time.perf_counter()
        for skeleton in [s for s in self._window if self.evidence.blocks(s.pristine)]:
            self._window.remove(skeleton)   # a step of it died since it was looked at
            self.defer(skeleton)
        self._return_deferred()
        # Those the evidence already holds well below an unknown skeleton (a step that keeps
        # failing from the same state, a mechanism that keeps breaking its promise) do not
        # count against the window: behind a run of them, the next plain plan is still in
        # view (up to `lookahead` in all).
        least = self.budget.contention
        in_contention = sum(self.evidence.estimate(s) >= least for s in self._window)
        asked = self._only_dead != (self.evidence.revivals, self.evidence.cleared)
        while asked and in_contention < self.budget.window and len(self._window) < self.budget.lookahead:
            skeleton = self._next()
            if skeleton is None:
                break
            self._window.append(skeleton)
            in_contention += self.evidence.estimate(skeleton) >= least
        self.search_s += time.perf_counter() - t0
        return list(self._window) if self._window else self._deferred[:1]

    def _return_deferred(self) -> None:
        """A step believed alive again: the first skeleton that waits on it comes back to try
        it. A step found feasible after all: every skeleton no dead step holds back comes back."""
        back: List[Skeleton] = []
        for key in self.evidence.revived[self._revivals:]:
            first = next((s for s in self._deferred if key in s.pristine and not self.evidence.blocks(s.pristine)
                          and s not in back), None)
            back += [first] if first is not None else []
        self._revivals = len(self.evidence.revived)
        if self.evidence.cleared != self._cleared:
            self._cleared = self.evidence.cleared
            back += [s for s in self._deferred if s not in back and not self.evidence.blocks(s.pristine)]
        if back:
            self._deferred = [s for s in self._deferred if s not in back]
            self._window.extend(back)
            self.returned += len(back)

    def take(self, skeleton: Skeleton) -> None:
        """Hand out `skeleton`, one of `upcoming()`."""
        self.taken += 1
        if skeleton in self._window:
            self._window.remove(skeleton)
        else:
            self._deferred.remove(skeleton)

    def defer(self, skeleton: Skeleton) -> None:
        """Set a skeleton aside until its dead step is believed alive again or the search has
        no more (an active one whose pristine step died is handed back this way)."""
        self._deferred.append(skeleton)
        self.deferrals += 1

    def _next_plan(self) -> Optional[Tuple[List[int], int]]:
        """The next plan from the searches in turn, none twice, with its place in the order
        of the search that found it (None: all are done)."""
        while any(search is not None for search in self._searches) and time.perf_counter() < self.deadline:
            self._turn = (self._turn + 1) % len(self._searches)
            search = self._searches[self._turn]
            plan = None if search is None else next(search, None)
            if plan is None:
                self._searches[self._turn] = None   # done (kept in place: the index names the search)
                continue
            self._yielded[self._turn] += 1
            if tuple(plan) not in self._seen:
                self._seen.add(tuple(plan))
                return plan, self._yielded[self._turn]
        return None

    def _next(self) -> Optional[Skeleton]:
        """The next skeleton from the searches that repeats no dead pristine step (None when
        they have no more, at the deadline, or after setting `lookahead` aside in a row: when
        every path left repeats a dead step, the search gives such paths without end)."""
        self.passed_plain = False
        for _ in range(self.budget.lookahead):
            found = self._next_plan()
            if found is None:
                return None
            plan, order = found
            if self.mechanisms_only and not any(self.task.operators[i].steps for i in plan):
                self.passed_plain = True   # basis steps alone: not this search's; the next call asks on
                continue
            self.found += 1
            steps = skeleton_steps(self.task, plan, self.vocabulary)
            skeleton = Skeleton(order, plan, steps, pristine_keys(steps, self._fixed, self.evidence.own_samplers),
                                step_contexts(steps),
                                self.found, step_questions(steps, self.task.init, self._observable))
            if not self.evidence.blocks(skeleton.pristine):
                return skeleton
            self.defer(skeleton)
        if not self.passed_plain:
            self._only_dead = (self.evidence.revivals, self.evidence.cleared)
        return None
