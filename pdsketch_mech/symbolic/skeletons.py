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
one length into one state, longer alternatives are dropped. Two things keep it from
dropping the plans that matter. Goal paths are leaves and never count against it. And
with `touches` (per operator, a bitmask of the objects it handles) a state is told apart by
which objects the path has handled: hooking a box within reach and putting it back on the
table returns to the initial symbolic state, but not to the initial scene, and must not
compete with the many no-op pushes that reach that state too.
"""
from __future__ import annotations

import heapq
import time
from collections import Counter
from typing import Iterator, List, Optional, Sequence, Set, Tuple

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
                   touches: Optional[Sequence[int]] = None) -> Iterator[List[int]]:
    """Yield operator-id plans, cheapest (by g + weight·h) first, no two with the same labels.

    `touches[op]`: the objects operator `op` handles, as a bitmask (see the module's doc).
    Stops when the open list is exhausted or at `deadline` (time.perf_counter() value).
    """
    heuristic = heuristic or FFHeuristic(task)
    successors = SuccessorGenerator(task)
    h_cache = {task.init: heuristic(task.init)[0]}
    if h_cache[task.init] == INFINITY:
        return
    visits: Counter = Counter()
    seen_plans: Set[Tuple[str, ...]] = set()
    counter = 0
    # (f, h, tie-break, state, cost, objects handled, path)
    open_list = [(weight * h_cache[task.init], h_cache[task.init], counter, task.init, 0, 0, None)]
    while open_list:
        if deadline is not None and time.perf_counter() > deadline:
            return
        _, _, _, state, cost, handled, path = heapq.heappop(open_list)
        if task.is_goal(state):
            plan = _unroll(path)
            labels = tuple(task.operators[o].label for o in plan)
            if labels not in seen_plans:
                seen_plans.add(labels)
                yield plan
            continue
        if visits[state, cost, handled] >= max_visits:
            continue
        visits[state, cost, handled] += 1
        if cost >= max_length:
            continue
        for op in successors(state):
            child = task.successor(state, task.operators[op])
            child_handled = handled | touches[op] if touches is not None else 0
            if visits[child, cost + 1, child_handled] >= max_visits and not task.is_goal(child):
                continue
            h = h_cache.get(child)
            if h is None:
                h = h_cache[child] = heuristic(child)[0]
            if h == INFINITY:
                continue
            counter += 1
            heapq.heappush(open_list, (cost + 1 + weight * h, h, counter, child, cost + 1, child_handled, (path, op)))
