"""Successive distinct plans (skeletons) for one task, cheapest first, without end.

The bilevel planner needs more than one plan: when continuous search fails on a skeleton
it asks for the next. This is a best-first search over *paths* (f = g + w·h_FF) in which a
state may be expanded up to a bound of times *at each cost*, a k-shortest-paths scheme:
each goal path popped is a new plan. Two cost models: *priced*, where an operator costs
`Operator.cost` (a mechanism its basis steps) and equal costs go to the plan of more
operators (the basis steps written out before a mechanism that takes them), so plain plans
come in the order a search over the basis operators alone would give them; and *unit*,
where every operator costs 1 (a mechanism is one action: the paper's order, in which
mechanisms make long plans short). Counting per cost matters because actions
with no symbolic effect (a push before a grasp, which the simulator may need) and
mechanisms like hook-use return to a state already seen; they must still be enumerated,
several in a row too (one push moves an object at most 25 cm). Plans are never extended
past the goal (a plan whose prefix reaches the goal is yielded first).

Nothing is pruned for good. The per-(state, cost) visit bound and the cost bound are a
*schedule*: paths beyond them are kept aside, and when the search has nothing else the
bounds double and those paths come back. So every path is eventually popped, and every
distinct plan is eventually yielded (the enumeration is complete), while the common case
pays for small bounds only.

With `handles` (per operator, the bitmask of the objects it handles) and `relevant` (the
bits that matter, asked as the search goes) paths are also told apart by which of those
objects they have handled: hooking a box that is out of reach closer and putting it back on
the table returns to the initial symbolic state, but not to the initial scene, and must not
compete with the many no-op pushes that reach that state too. `blocked(handled, op)` sets
paths aside that the caller wants last (through a step found dead); they come back when the
search has nothing else, or as soon as `revived()` changes (the caller withdrew a verdict).
"""
from __future__ import annotations

import heapq
import time
from collections import Counter
from dataclasses import replace
from typing import Callable, Iterator, List, Optional, Sequence, Set, Tuple

from .heuristic import INFINITY, FFHeuristic
from .search import SuccessorGenerator
from .task import StripsTask

# A path is a linked list (previous path, operator id); None is the empty path.
Path = Optional[Tuple["Path", int]]


def _unroll(path: Path) -> List[int]:
    ops = []
    while path is not None:
        path, op = path
        ops.append(op)
    return ops[::-1]


def priced_heuristic(task: StripsTask) -> Callable[[int], Tuple[float, List[int]]]:
    """h_FF in basis steps: the relaxed plan over the basis operators alone where it exists
    (with macros, FF's achievers are mechanisms, which reach facts a level earlier however
    many steps they take, and every plain path looks dear); over every operator, each at its
    cost, where only a mechanism's certified effect reaches the goal."""
    never = 1   # a macro that needs fact 0 both true and false never applies
    basis = replace(task, operators=[replace(op, pre=op.pre | never, neg=op.neg | never, add=0, conditional=())
                                     if op.steps else op for op in task.operators])
    plain, every = FFHeuristic(basis, priced=True), FFHeuristic(task, priced=True)

    def h(state: int) -> Tuple[float, List[int]]:
        value = plain(state)
        return value if value[0] != INFINITY else every(state)
    return h


def iter_skeletons(task: StripsTask, max_visits: int = 50, weight: float = 1.0, max_length: int = 40,
                   deadline: Optional[float] = None, heuristic: Optional[FFHeuristic] = None,
                   handles: Optional[Sequence[int]] = None, relevant: Optional[Callable[[], int]] = None,
                   blocked: Optional[Callable[[int, int], bool]] = None,
                   revived: Optional[Callable[[], int]] = None, priced: bool = True) -> Iterator[List[int]]:
    """Yield operator-id plans, cheapest (by g + weight·h) first, no two with the same labels.

    `priced`: the cost model (module docstring). `max_visits` and `max_length` (a cost) are
    where the schedule starts; each doubles whenever the search runs out of paths within them
    (module docstring). `handles`, `relevant`, `blocked` and `revived` are asked as the search
    goes, so the caller may learn more on the way. Stops when every path has been searched (a
    task with finitely many acyclic paths and nothing set aside) or at `deadline`
    (time.perf_counter() value).
    """
    search = _PathSearch(task, heuristic or (priced_heuristic(task) if priced else FFHeuristic(task)), weight,
                         priced, handles, relevant, blocked, revived, max_visits, max_length)
    seen_plans: Set[Tuple[str, ...]] = set()
    while search.refill():
        if deadline is not None and time.perf_counter() > deadline:
            return
        plan = search.step()
        if plan is not None:
            labels = tuple(task.operators[o].label for o in plan)
            if labels not in seen_plans:
                seen_plans.add(labels)
                yield plan


# A node: (order key, tie-break, operators, state, cost, objects handled, handled before the last op, path)
Node = Tuple[tuple, int, int, int, int, int, int, Path]


class _PathSearch:
    """The best-first search over paths behind `iter_skeletons`: an open list, the paths
    set aside through blocked operators (`waiting`) and past the bounds (`beyond`)."""

    def __init__(self, task: StripsTask, heuristic, weight: float, priced: bool,
                 handles: Optional[Sequence[int]], relevant: Optional[Callable[[], int]],
                 blocked: Optional[Callable[[int, int], bool]], revived: Optional[Callable[[], int]],
                 max_visits: int, max_length: int):
        self.task, self.heuristic, self.weight, self.priced = task, heuristic, weight, priced
        self.handles, self.relevant, self.blocked, self.revived = handles, relevant, blocked, revived
        self.successors = SuccessorGenerator(task)
        self.h_cache = {task.init: heuristic(task.init)[0]}
        self.visits: Counter = Counter()
        self.counter = 0
        self.bound, self.length = max_visits, max_length
        self.revivals = revived() if revived is not None else 0
        self.honoured = blocked is not None   # set aside what `blocked` says, until only such paths are left
        h0 = self.h_cache[task.init]
        self.open: List[Node] = [] if h0 == INFINITY else [(self.order(weight * h0, h0, 0), 0, 0, task.init, 0, 0, 0,
                                                             None)]
        self.waiting: List[Node] = []   # paths through a blocked operator
        self.beyond: List[Node] = []    # paths past the visit or cost bound: the schedule's next round

    def order(self, f: float, h: float, n_ops: int) -> tuple:
        """Priced: equal costs go to more operators, counting the relaxed plan's steps as
        operators still to come (the steps written out before a mechanism that takes them).
        Unit: lower h first (the goal nearer), as a plain best-first."""
        return (f, -(n_ops + h), h) if self.priced else (f, h, n_ops)

    def visit_key(self, state: int, cost: int, handled: int) -> tuple:
        return state, cost, handled & self.relevant() if self.relevant is not None else 0

    def refill(self) -> bool:
        """Make the open list non-empty if any path is left: waiting paths come back when a
        verdict is withdrawn or nothing else is left; then the bounds double. False: done."""
        if not (self.open or self.waiting or self.beyond):
            return False
        if self.revived is not None and self.revived() != self.revivals:   # a verdict withdrawn: re-ask the waiting
            self.revivals, self.honoured = self.revived(), self.blocked is not None
            self.open.extend(self.waiting)
            self.waiting = []
            heapq.heapify(self.open)
        if not self.open:
            if self.waiting:   # only paths through blocked operators are left: search them
                self.open, self.waiting, self.honoured = self.waiting, [], False
            else:   # every path within the bounds is searched: widen them
                self.bound, self.length = 2 * self.bound, 2 * self.length
                self.open, self.beyond = self.beyond, []
            heapq.heapify(self.open)
        return True

    def step(self) -> Optional[List[int]]:
        """Pop one path: a goal path is returned as a plan; any other is expanded (or set aside)."""
        node = heapq.heappop(self.open)
        _, _, n_ops, state, cost, handled, before, path = node
        if self.honoured and path is not None and self.blocked(before, path[1]):
            self.waiting.append(node)  # found out since it was generated
            return None
        if self.task.is_goal(state):  # a leaf: the bound on paths into a state is for expansions
            return _unroll(path)
        key = self.visit_key(state, cost, handled)
        if self.visits[key] >= self.bound or cost >= self.length:
            self.beyond.append(node)
            return None
        self.visits[key] += 1
        self.expand(n_ops, state, cost, handled, path)
        return None

    def expand(self, n_ops: int, state: int, cost: int, handled: int, path: Path) -> None:
        task = self.task
        for op in self.successors(state):
            operator = task.operators[op]
            child = task.successor(state, operator)
            h = self.h_cache.get(child)
            if h is None:
                h = self.h_cache[child] = self.heuristic(child)[0]
            if h == INFINITY:
                continue
            self.counter += 1
            child_cost = cost + (operator.cost if self.priced else 1)
            child_handled = handled | self.handles[op] if self.handles is not None else 0
            item = (self.order(child_cost + self.weight * h, h, n_ops + 1), self.counter, n_ops + 1, child, child_cost,
                    child_handled, handled, (path, op))
            if self.honoured and self.blocked(handled, op):
                self.waiting.append(item)
            elif not task.is_goal(child) and self.visits[self.visit_key(child, child_cost, child_handled)] >= self.bound:
                self.beyond.append(item)   # its state is searched enough at that cost for this round
            else:
                heapq.heappush(self.open, item)
