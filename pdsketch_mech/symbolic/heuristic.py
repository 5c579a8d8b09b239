"""The FF heuristic (Hoffmann & Nebel 2001): relaxed planning graph, relaxed plan, helpful actions.

Data-oriented: the relaxed task is flat lists of ints built once; an evaluation walks the
graph layer by layer with precondition counters, so its cost is linear in the part of the
graph it explores and it stops as soon as every goal fact is reached.
"""
from __future__ import annotations

from collections import defaultdict
from typing import Dict, List, Set, Tuple

from .task import StripsTask, bits

INFINITY = float("inf")


class FFHeuristic:
    """`h(state) -> (h value, helpful operator ids)`. Negative conditions are relaxed away;
    each conditional effect is its own relaxed operator with the operator's preconditions.
    `priced`: a relaxed plan costs what its operators cost (`Operator.cost`), else 1 each;
    and its achievers are chosen level by level to cover most of what that level needs (an
    operator that achieves two needed facts is chosen once), rather than first found: the
    first achiever found of `handempty` after a grasp is any place, not the one the goal
    needs, which costs a plain plan a step a mechanism's plan does not pay."""

    def __init__(self, task: StripsTask, priced: bool = False):
        self.task = task
        n_facts = len(task.facts)
        self.pre: List[List[int]] = []      # relaxed op -> precondition facts
        self.add: List[List[int]] = []      # relaxed op -> added facts
        self.origin: List[int] = []         # relaxed op -> operator id
        for op_id, op in enumerate(task.operators):
            parts = [(op.pre, op.add)] + [(op.pre | c.pre, c.add) for c in op.conditional]
            for pre, add in parts:
                if add:
                    self.pre.append(bits(pre))
                    self.add.append(bits(add))
                    self.origin.append(op_id)
        self.pre_count = [len(p) for p in self.pre]
        self.consumers: List[List[int]] = [[] for _ in range(n_facts)]
        for r, pre in enumerate(self.pre):
            for fact in pre:
                self.consumers[fact].append(r)
        self.no_pre = [r for r, count in enumerate(self.pre_count) if count == 0]
        self.goal = bits(task.goal)
        self.n_facts = n_facts
        self.cost = [op.cost if priced else 1 for op in task.operators]
        self.priced = priced

    def __call__(self, state: int) -> Tuple[float, List[int]]:
        level: List[int] = [-1] * self.n_facts
        achiever: List[int] = [-1] * self.n_facts
        adders: Dict[int, List[int]] = defaultdict(list)   # fact -> relaxed ops adding it first (priced)
        current = bits(state)
        for fact in current:
            level[fact] = 0
        unsat = self.pre_count[:]
        consumers, adds, goal = self.consumers, self.add, self.goal
        fired: List[int] = list(self.no_pre)
        depth = 0
        while any(level[g] < 0 for g in goal):
            for fact in current:
                for r in consumers[fact]:
                    unsat[r] -= 1
                    if not unsat[r]:
                        fired.append(r)
            depth += 1
            current = []
            for r in fired:
                for fact in adds[r]:
                    if level[fact] < 0:
                        level[fact] = depth
                        achiever[fact] = r
                        current.append(fact)
                    if self.priced and level[fact] == depth:
                        adders[fact].append(r)
            fired = []
            if not current:
                return INFINITY, []
        if self.priced:
            return self._covering_plan(level, adders)
        return self._relaxed_plan(level, achiever)

    def _covering_plan(self, level: List[int], adders: Dict[int, List[int]]) -> Tuple[float, List[int]]:
        """The relaxed plan chosen level by level, top down: at each level the achiever that
        covers most of the facts still needed there, until none is left."""
        needed: Dict[int, Set[int]] = defaultdict(set)
        for g in self.goal:
            if level[g] > 0:
                needed[level[g]].add(g)
        chosen: Set[int] = set()
        helpful: List[int] = []
        for depth in range(max(needed, default=0), 0, -1):
            need = needed.get(depth, set())
            while need:
                r = max(sorted({r for fact in need for r in adders[fact]}),
                        key=lambda r: len(need.intersection(self.add[r])))
                need.difference_update(self.add[r])
                op = self.origin[r]
                if op not in chosen:
                    chosen.add(op)
                    if depth == 1:
                        helpful.append(op)
                for p in self.pre[r]:
                    if level[p] > 0:
                        needed[level[p]].add(p)
        return float(sum(self.cost[op] for op in chosen)), sorted(helpful)

    def _relaxed_plan(self, level: List[int], achiever: List[int]) -> Tuple[float, List[int]]:
        chosen: Set[int] = set()
        helpful: List[int] = []
        marked: Set[int] = set()
        stack = [g for g in self.goal if level[g] > 0]
        while stack:
            fact = stack.pop()
            if fact in marked:
                continue
            marked.add(fact)
            r = achiever[fact]
            op = self.origin[r]
            if op not in chosen:
                chosen.add(op)
                if level[fact] == 1:
                    helpful.append(op)
            for p in self.pre[r]:
                if level[p] > 0 and p not in marked:
                    stack.append(p)
        # A relaxed plan costs what its operators cost (a mechanism its steps: Operator.cost).
        cost = self.cost
        return float(sum(cost[op] for op in chosen)), sorted(helpful)
