"""Heuristic search over a `StripsTask`: lazy greedy best-first search with preferred
operators, and eager weighted A*. Ties break first-in-first-out, so runs are deterministic."""
from __future__ import annotations

import heapq
import time
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Tuple

from .heuristic import INFINITY, FFHeuristic
from .task import StripsTask, Timeout, bits

PREFERRED_BOOST = 1000  # as in Fast Downward: on progress, favour the preferred queue


@dataclass
class SearchResult:
    status: str                              # "solved" | "unsolvable" | "timeout"
    plan: Optional[List[int]] = None         # operator ids
    expansions: int = 0
    evaluations: int = 0
    generated: int = 0
    time_s: float = 0.0
    stats: Dict[str, float] = field(default_factory=dict)


class SuccessorGenerator:
    """Applicable operators of a state: each operator is indexed under one of its
    preconditions, so a state only looks at operators whose indexed fact it contains."""

    def __init__(self, task: StripsTask):
        self.task = task
        self.by_fact: List[List[int]] = [[] for _ in task.facts]
        self.always: List[int] = []
        for op_id, op in enumerate(task.operators):
            if op.pre:
                self.by_fact[(op.pre & -op.pre).bit_length() - 1].append(op_id)
            else:
                self.always.append(op_id)

    def __call__(self, state: int) -> List[int]:
        ops = self.task.operators
        out = [o for o in self.always if not state & ops[o].neg]
        for fact in bits(state):
            for o in self.by_fact[fact]:
                op = ops[o]
                if state & op.pre == op.pre and not state & op.neg:
                    out.append(o)
        return out


def _extract(parents: Dict[int, Optional[Tuple[int, int]]], state: int) -> List[int]:
    plan = []
    while parents[state] is not None:
        state, op = parents[state]
        plan.append(op)
    return plan[::-1]


def _check_time(deadline: Optional[float]) -> None:
    if deadline is not None and time.perf_counter() > deadline:
        raise Timeout


def greedy_search(task: StripsTask, heuristic: Optional[FFHeuristic] = None,
                  deadline: Optional[float] = None, preferred: bool = True) -> SearchResult:
    """Lazy GBFS: successors enter the open lists with their parent's h and are evaluated
    when popped; helpful actions also enter a preferred list that is boosted on progress."""
    start = time.perf_counter()
    heuristic = heuristic or FFHeuristic(task)
    successors = SuccessorGenerator(task)
    result = SearchResult("unsolvable")
    parents: Dict[int, Optional[Tuple[int, int]]] = {task.init: None}
    if task.is_goal(task.init):
        return SearchResult("solved", [], time_s=time.perf_counter() - start)
    queues: Tuple[list, list] = ([], [])  # regular, preferred
    priority = [0, 0]
    counter = 0
    best = INFINITY

    def expand(state: int, h: float, helpful: List[int]) -> None:
        nonlocal counter
        result.expansions += 1
        helpful_set = set(helpful) if preferred else ()
        for op in successors(state):
            counter += 1
            heapq.heappush(queues[0], (h, counter, state, op))
            if op in helpful_set:
                heapq.heappush(queues[1], (h, counter, state, op))

    try:
        h, helpful = heuristic(task.init)
        result.evaluations += 1
        if h == INFINITY:
            return _finish(result, start)
        best = h
        expand(task.init, h, helpful)
        while queues[0] or queues[1]:
            _check_time(deadline)
            which = 1 if queues[1] and (not queues[0] or priority[1] <= priority[0]) else 0
            priority[which] += 1
            _, _, parent, op = heapq.heappop(queues[which])
            child = task.successor(parent, task.operators[op])
            result.generated += 1
            if child in parents:
                continue
            parents[child] = (parent, op)
            if task.is_goal(child):
                result.status, result.plan = "solved", _extract(parents, child)
                return _finish(result, start)
            h, helpful = heuristic(child)
            result.evaluations += 1
            if h == INFINITY:
                continue
            if h < best:
                best = h
                priority[1] -= PREFERRED_BOOST
            expand(child, h, helpful)
    except Timeout:
        result.status = "timeout"
    return _finish(result, start)


def weighted_astar(task: StripsTask, heuristic: Optional[FFHeuristic] = None, weight: float = 2.0,
                   deadline: Optional[float] = None) -> SearchResult:
    """Eager best-first search on f = g + weight * h (unit costs), reopening on a cheaper path."""
    start = time.perf_counter()
    heuristic = heuristic or FFHeuristic(task)
    successors = SuccessorGenerator(task)
    result = SearchResult("unsolvable")
    parents: Dict[int, Optional[Tuple[int, int]]] = {task.init: None}
    g = {task.init: 0}
    h_cache: Dict[int, float] = {}
    counter = 0
    try:
        h_cache[task.init] = heuristic(task.init)[0]
        result.evaluations += 1
        if h_cache[task.init] == INFINITY:
            return _finish(result, start)
        open_list = [(weight * h_cache[task.init], h_cache[task.init], 0, task.init, 0)]
        while open_list:
            _, _, _, state, cost = heapq.heappop(open_list)
            if cost > g[state]:
                continue  # a stale entry: the state was reached more cheaply since
            if task.is_goal(state):
                result.status, result.plan = "solved", _extract(parents, state)
                return _finish(result, start)
            _check_time(deadline)
            result.expansions += 1
            for op in successors(state):
                child = task.successor(state, task.operators[op])
                result.generated += 1
                if child in g and g[child] <= cost + 1:
                    continue
                if child not in h_cache:
                    h_cache[child] = heuristic(child)[0]
                    result.evaluations += 1
                if h_cache[child] == INFINITY:
                    continue
                g[child] = cost + 1
                parents[child] = (state, op)
                counter += 1
                heapq.heappush(open_list, (cost + 1 + weight * h_cache[child], h_cache[child], counter,
                                           child, cost + 1))
    except Timeout:
        result.status = "timeout"
    return _finish(result, start)


def _finish(result: SearchResult, start: float) -> SearchResult:
    result.time_s = time.perf_counter() - start
    return result
