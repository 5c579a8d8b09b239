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

    `priced`: the cost model (module docstring). `max_visits` and `max_length` (a cost) are where the schedule starts; each doubles
    whenever the search runs out of paths within them (module docstring). `handles`,
    `relevant`, `blocked` and `revived` are asked as the search goes, so the caller may
    learn more on the way. Stops when every path has been searched (a task with finitely
    many acyclic paths and nothing set aside) or at `deadline` (time.perf_counter() value).
    """
    heuristic = heuristic or (priced_heuristic(task) if priced else FFHeuristic(task))

    def order(f: float, h: float, n_ops: int) -> tuple:
        """Priced: equal costs go to more operators, counting the relaxed plan's steps as
        operators still to come (the steps written out before a mechanism that takes them).
        Unit: lower h first (the goal nearer), as a plain best-first."""
        return (f, -(n_ops + h), h) if priced else (f, h, n_ops)
    successors = SuccessorGenerator(task)
    h_cache = {task.init: heuristic(task.init)[0]}
    if h_cache[task.init] == INFINITY:
        return
    visits: Counter = Counter()
    seen_plans: Set[Tuple[str, ...]] = set()
    counter = 0
    bound, length = max_visits, max_length
    revivals = revived() if revived is not None else 0
    honoured = blocked is not None   # set aside what `blocked` says, until only such paths are left

    def visit_key(state, cost: int, handled: int) -> tuple:
        return state, cost, handled & relevant() if relevant is not None else 0

    # (order(f, h, operators), tie-break, operators, state, cost, objects handled, handled before the last op, path)
    h0 = h_cache[task.init]
    open_list = [(order(weight * h0, h0, 0), counter, 0, task.init, 0, 0, 0, None)]
    waiting: list = []    # paths through a blocked operator
    beyond: list = []     # paths past the visit or cost bound: the schedule's next round
    while open_list or waiting or beyond:
        if revived is not None and revived() != revivals:   # a verdict withdrawn: re-ask the waiting
            revivals, honoured = revived(), blocked is not None
            open_list.extend(waiting)
            waiting = []
            heapq.heapify(open_list)
        if not open_list:
            if waiting:   # only paths through blocked operators are left: search them
                open_list, waiting, honoured = waiting, [], False
            else:   # every path within the bounds is searched: widen them
                bound, length = 2 * bound, 2 * length
                open_list, beyond = beyond, []
            heapq.heapify(open_list)
        if deadline is not None and time.perf_counter() > deadline:
            return
        node = heapq.heappop(open_list)
        _, _, n_ops, state, cost, handled, before, path = node
        if honoured and path is not None and blocked(before, path[1]):
            waiting.append(node)  # found out since it was generated
            continue
        if task.is_goal(state):  # a leaf: the bound on paths into a state is for expansions
            plan = _unroll(path)
            labels = tuple(task.operators[o].label for o in plan)
            if labels not in seen_plans:
                seen_plans.add(labels)
                yield plan
            continue
        key = visit_key(state, cost, handled)
        if visits[key] >= bound or cost >= length:
            beyond.append(node)
            continue
        visits[key] += 1
        for op in successors(state):
            operator = task.operators[op]
            child = task.successor(state, operator)
            h = h_cache.get(child)
            if h is None:
                h = h_cache[child] = heuristic(child)[0]
            if h == INFINITY:
                continue
            counter += 1
            child_cost = cost + (operator.cost if priced else 1)
            child_handled = handled | handles[op] if handles is not None else 0
            item = (order(child_cost + weight * h, h, n_ops + 1), counter, n_ops + 1, child, child_cost, child_handled,
                    handled, (path, op))
            if honoured and blocked(handled, op):
                waiting.append(item)
            elif not task.is_goal(child) and visits[visit_key(child, child_cost, child_handled)] >= bound:
                beyond.append(item)   # its state is searched enough at that cost for this round
            else:
                heapq.heappush(open_list, item)
