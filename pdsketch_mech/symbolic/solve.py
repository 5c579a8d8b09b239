"""Parse-free entry point: a checked domain + problem -> grounded task -> searched plan."""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Tuple

from ..lang.nodes import Domain, Problem
from ..lang.typecheck import TypeTable
from .grounding import ground
from .heuristic import FFHeuristic
from .search import SearchResult, greedy_search, weighted_astar
from .task import Timeout

SEARCHES = ("gbfs", "wastar")
Step = Tuple[str, Tuple[str, ...]]


@dataclass
class ClassicalResult:
    status: str                      # "solved" | "unsolvable" | "timeout"
    plan: List[Step] = field(default_factory=list)
    time_s: float = 0.0
    stats: Dict[str, float] = field(default_factory=dict)


def solve(domain: Domain, problem: Problem, types: TypeTable, search: str = "gbfs", weight: float = 2.0,
          timeout: Optional[float] = None) -> ClassicalResult:
    """Ground and search; `timeout` (seconds) bounds grounding and search together."""
    if search not in SEARCHES:
        raise ValueError(f"unknown search '{search}'; expected one of {', '.join(SEARCHES)}")
    start = time.perf_counter()
    deadline = None if timeout is None else start + timeout
    try:
        task = ground(domain, problem, types, deadline=deadline)
    except Timeout:
        return ClassicalResult("timeout", [], time.perf_counter() - start,
                               {"facts": 0, "operators": 0, "expansions": 0, "evaluations": 0, "generated": 0,
                                "ground_s": round(time.perf_counter() - start, 6), "search_s": 0.0})
    grounded = time.perf_counter()
    heuristic = FFHeuristic(task)
    if search == "gbfs":
        result: SearchResult = greedy_search(task, heuristic, deadline=deadline)
    else:
        result = weighted_astar(task, heuristic, weight=weight, deadline=deadline)
    plan = [(task.operators[o].name, task.operators[o].args) for o in result.plan or ()
            if not task.operators[o].artificial]
    stats = {"facts": len(task.facts), "operators": len(task.operators), "expansions": result.expansions,
             "evaluations": result.evaluations, "generated": result.generated,
             "ground_s": round(grounded - start, 6), "search_s": round(result.time_s, 6)}
    return ClassicalResult(result.status, plan, time.perf_counter() - start, stats)
