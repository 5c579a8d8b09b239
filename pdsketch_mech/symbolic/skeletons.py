"""Successive distinct plans (skeletons) for one task, best first.

The bilevel planner needs more than one plan: when continuous search fails on a skeleton
it asks for the next. This is a best-first search over *paths* (f = g + w·h_FF) in which a
state may be expanded up to `max_visits` times *at each depth*, a k-shortest-paths scheme:
each goal path popped is a new plan. Counting per depth matters because actions with no
symbolic effect (a push before a grasp, which the simulator may need) and mechanisms like
hook-use return to a state already seen; they must still be enumerated, several in a row
too (one push moves an object at most 25 cm). Plans are never extended past the goal
(sound: a plan whose prefix reaches the goal is yielded first). The per-(state, depth)
visit bound is the one pruning that is not sound in general: beyond `max_visits` paths of
one length into one state, longer alternatives are dropped (goal paths are leaves and never
count against it). With `handles` (per operator, the bitmask of the objects it handles)
and `relevant` (the bits that matter, asked as the search goes) paths are also told apart
by which of those objects they have handled: hooking a box that is out of reach closer and
putting it back on the table returns to the initial symbolic state, but not to the initial
scene, and must not compete with the many no-op pushes that reach that state too.
"""
from __future__ import annotations

import heapq
import time
from collections import Counter
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


def iter_skeletons(task: StripsTask, max_visits: int = 50, weight: float = 1.0, max_length: int = 40,
                   deadline: Optional[float] = None, heuristic: Optional[FFHeuristic] = None,
                   handles: Optional[Sequence[int]] = None, relevant: Optional[Callable[[], int]] = None,
                   blocked: Optional[Callable[[int, int], bool]] = None) -> Iterator[List[int]]:
    """Yield operator-id plans, cheapest (by g + weight·h) first, no two with the same labels.

    `handles[op]`: the objects operator `op` handles, as a bitmask; paths are told apart by
    which of the `relevant()` ones they have handled (see the module's doc). `blocked(handled,
    op)`: whether `op` after a path that handled `handled` should wait; such paths are
    searched only once the others run out. Both callbacks are asked as the search goes, so the
    caller may learn more on the way. Stops when both lists are exhausted or at `deadline`
    (time.perf_counter() value).
    """
    heuristic = heuristic or FFHeuristic(task)
    successors = SuccessorGenerator(task)
    h_cache = {task.init: heuristic(task.init)[0]}
    if h_cache[task.init] == INFINITY:
        return
    visits: Counter = Counter()
    seen_plans: Set[Tuple[str, ...]] = set()
    counter = 0

    def visit_key(state, cost: int, handled: int) -> tuple:
        return state, cost, handled & relevant() if relevant is not None else 0

    # (f, h, tie-break, state, cost, objects handled, objects handled before the last op, path)
    open_list = [(weight * h_cache[task.init], h_cache[task.init], counter, task.init, 0, 0, 0, None)]
    waiting: list = []
    while open_list or waiting:
        if not open_list:
            open_list, waiting, blocked = waiting, [], None
            heapq.heapify(open_list)
        if deadline is not None and time.perf_counter() > deadline:
            return
        node = heapq.heappop(open_list)
        _, _, _, state, cost, handled, before, path = node
        if blocked is not None and path is not None and blocked(before, path[1]):
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
        if visits[key] >= max_visits:
            continue
        visits[key] += 1
        if cost >= max_length:
            continue
        for op in successors(state):
            child = task.successor(state, task.operators[op])
            child_handled = handled | handles[op] if handles is not None else 0
            waits = blocked is not None and blocked(handled, op)
            if not waits and visits[visit_key(child, cost + 1, child_handled)] >= max_visits and not task.is_goal(child):
                continue
            h = h_cache.get(child)
            if h is None:
                h = h_cache[child] = heuristic(child)[0]
            if h == INFINITY:
                continue
            counter += 1
            item = (cost + 1 + weight * h, h, counter, child, cost + 1, child_handled, handled, (path, op))
            if waits:
                waiting.append(item)
            else:
                heapq.heappush(open_list, item)
