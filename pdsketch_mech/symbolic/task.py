"""A grounded STRIPS task: facts are integer ids, a state is an int bitset of true facts.

Static facts (predicates no action changes) are not part of the state; grounding has
already evaluated them.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Sequence, Tuple

Fact = Tuple[str, ...]  # ("on", "a", "b")


class Timeout(Exception):
    """Raised by grounding or search when their deadline passes."""


@dataclass(frozen=True)
class ConditionalEffect:
    pre: int
    neg: int
    add: int
    delete: int


@dataclass(frozen=True)
class Operator:
    """A ground operator. `pre`/`neg` are the facts that must be true/false; the effect
    deletes before it adds (an atom both deleted and added ends up true)."""

    name: str
    args: Tuple[str, ...]
    pre: int
    neg: int
    add: int
    delete: int
    conditional: Tuple[ConditionalEffect, ...] = ()
    artificial: bool = False  # compiled goal disjunctions; never shown in plans
    steps: Tuple[int, ...] = ()  # a mechanism (macro): the ids of its basis operators, in order
    certified: Tuple[Tuple[int, int], ...] = ()  # a mechanism's promise: alternatives of (true, false) masks
    roles: Tuple[Tuple[str, str], ...] = ()  # a mechanism: (placeholder, the variable it stands for)
    settles: Tuple[int, int] = (0, 0)  # a mechanism: (add, delete) its certified facts impose after its steps
    then: Tuple[Tuple[int, int], ...] = ()  # a mechanism: (add, delete) physics makes so after each step, if any

    @property
    def label(self) -> str:
        return f"({' '.join((self.name,) + self.args)})"

    @property
    def cost(self) -> int:
        """What the operator costs a plan: a mechanism what its basis steps cost, so that a
        plan with mechanisms is never cheaper than the same steps written out."""
        return len(self.steps) or 1


def bits(mask: int) -> List[int]:
    """The ids of the set bits of `mask`, ascending."""
    out = []
    while mask:
        low = mask & -mask
        out.append(low.bit_length() - 1)
        mask ^= low
    return out


@dataclass
class StripsTask:
    facts: List[Fact]
    operators: List[Operator]
    init: int
    goal: int
    goal_neg: int = 0
    static_facts: frozenset = frozenset()
    fact_ids: Dict[Fact, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not self.fact_ids:
            self.fact_ids = {f: i for i, f in enumerate(self.facts)}

    @staticmethod
    def applicable(state: int, op: Operator) -> bool:
        return state & op.pre == op.pre and not state & op.neg

    @staticmethod
    def successor(state: int, op: Operator) -> int:
        add, delete = op.add, op.delete
        for cond in op.conditional:
            if state & cond.pre == cond.pre and not state & cond.neg:
                add |= cond.add
                delete |= cond.delete
        return (state & ~delete) | add

    def is_goal(self, state: int) -> bool:
        return state & self.goal == self.goal and not state & self.goal_neg

    def atoms(self, state: int) -> List[Fact]:
        return [self.facts[i] for i in bits(state)]

    def mask(self, facts: Sequence[Fact]) -> int:
        out = 0
        for fact in facts:
            out |= 1 << self.fact_ids[fact]
        return out
