"""Every number that changes the planner's search order or its budgets, in one declared
object (docs/planner.md lists each with how it was chosen).

Work is counted in *units*: a value drawn and simulated, or a step's samplers running dry
on a visit. Counting work rather than seconds makes the same seed give the same plan on any
machine under any load.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..samplers.budget import SamplerBudget


@dataclass(frozen=True)
class SearchBudget:
    """The adaptive bilevel planner's knobs, with their units (docs/planner.md)."""

    slice: int = 3              # units: work a skeleton gets per turn, values a visit of a step
                                # tries before going back, and what a new skeleton is worth
    dead_after: int = 3         # visits: dry visits of a pristine step, none feasible, before it is believed dead
    revisit: float = 2.0        # factor: a step believed dead for the k-th time at total work W is
                                # believed alive again once the total reaches W * revisit**k
    floor: float = 1.0 / 32.0   # ratio: the least estimate evidence can give a skeleton
    unblock_gain: float = 8.0   # ratio: the estimate a prefix past a step dead where the scene began gets, per step
    window: int = 8             # skeletons: upcoming ones from the symbolic search the schedule chooses among,
                                # counting only those whose estimate is at least `contention` ...
    contention: float = 0.25    # ratio: ... (two halvings below an unknown skeleton's) ...
    lookahead: int = 64         # skeletons: ... up to this many in view in all (and set aside in a row)
    skeleton_visits: int = 50   # paths: the symbolic enumeration's first bound on expansions of a state
                                # at one cost (doubles each time it runs out: symbolic/skeletons.py)
    skeleton_cost: int = 40     # basis steps: the enumeration's first bound on a plan's cost (doubles likewise)
    plain_share: float = 2 / 3  # ratio: with mechanisms loaded, the share of the work beyond
                                # `head_start` owed to the basis operators' own search
    head_start: int = 20        # units: work the mechanisms' search has before the basis operators' own is owed its share
    samplers: SamplerBudget = field(default_factory=SamplerBudget)   # proposals, IK, motion checks, ranking


DEFAULT_BUDGET = SearchBudget()
