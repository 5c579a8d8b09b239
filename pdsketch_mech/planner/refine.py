"""ContinuousSearch (paper Alg. 1) for one skeleton: sample a step's parameters, simulate it,
check the contact graph it produced against the skeleton, and backtrack step by step.

A `Refinement` keeps its search state (snapshots, per-step sample generators), so the
adaptive planner can give it a time slice, move to another skeleton, and come back.
"""
from __future__ import annotations

import itertools
import time
from collections import Counter
from dataclasses import dataclass, field
from typing import Dict, Iterator, List, Optional, Sequence, Tuple

import numpy as np

from ..symbolic.task import StripsTask
from ..world.contacts import read_contacts
from ..world.snapshot import Snapshot
from ..world.world import World
from .bindings import StepSampler, run_step

CONTACT_PREDICATES = ("holding", "support", "handempty")
TRIES_PER_VISIT = 3  # parameter samples tried at a step before backtracking to the one before


@dataclass(frozen=True)
class Step:
    name: str
    args: Tuple[str, ...]
    expected: int                 # symbolic state the step must produce
    mechanism: Optional[str] = None


def contact_mask(task: StripsTask) -> int:
    """The task facts the simulation can observe (the contact-mode graph)."""
    mask = 0
    for fact, i in task.fact_ids.items():
        if fact[0] in CONTACT_PREDICATES:
            mask |= 1 << i
    return mask


def observed_state(task: StripsTask, world: World) -> int:
    """The contact-graph facts true in the world, as task bits."""
    state = 0
    for fact in read_contacts(world).facts():
        i = task.fact_ids.get(tuple(fact))
        if i is not None:
            state |= 1 << i
    return state


@dataclass
class Refinement:
    """The continuous search of one skeleton, resumable across time slices."""

    steps: List[Step]
    start: Snapshot
    world: World
    task: StripsTask
    sampler: StepSampler
    rng: np.random.Generator
    failures: Counter = field(default_factory=Counter)
    executions: int = 0
    exhausted: bool = False

    def __post_init__(self) -> None:
        n = len(self.steps)
        self.snapshots: List[Optional[Snapshot]] = [self.start] + [None] * n
        self.generators: List[Optional[Iterator[Dict[str, object]]]] = [None] * n
        self.values: List[Optional[Dict[str, object]]] = [None] * n
        self.depth = 0
        self.root_yields = 0
        self.observable = contact_mask(self.task)

    def run(self, deadline: float, max_executions: int) -> Optional[List[Dict[str, object]]]:
        """Search until `max_executions` more steps have been simulated (a unit of work, so
        that how skeletons interleave does not depend on the machine's speed) or until
        `deadline`; the values of every step if the skeleton is refined."""
        world = self.world
        budget = self.executions + max_executions
        if not self.steps:  # the goal holds symbolically already: it must hold in the scene too
            world.restore(self.start)
            self.exhausted = bool((observed_state(self.task, world) ^ self.task.init) & self.observable)
            return None if self.exhausted else []
        while not self.exhausted and self.executions < budget and time.perf_counter() < deadline:
            i = self.depth
            step = self.steps[i]
            world.restore(self.snapshots[i])
            if self.generators[i] is None:
                self.generators[i] = itertools.islice(
                    self.sampler.samples(world, step.args, self.rng), TRIES_PER_VISIT)
            values = next(self.generators[i], None)
            if values is None:  # this step is out of samples: revise the step before it
                self.generators[i] = None
                self.failures[f"{step.name}: no feasible parameters"] += 1
                if i > 0:
                    self.depth -= 1
                    continue
                # The first step's visit is over. If it yielded nothing its sampler found no
                # feasible values at all; otherwise pause: the next slice draws fresh ones.
                self.exhausted = self.root_yields == 0
                self.root_yields = 0
                return None
            if i == 0:
                self.root_yields += 1
            world.restore(self.snapshots[i])
            outcome = run_step(world, step.name, step.args, values, self.rng)
            self.executions += 1
            if not outcome.ok:
                self.failures[f"{step.name}: {outcome.reason}"] += 1
                continue
            observed = observed_state(self.task, world)
            if (observed ^ step.expected) & self.observable:
                self.failures[f"{step.name}: simulated contacts differ from the skeleton"] += 1
                continue
            self.values[i] = values
            self.snapshots[i + 1] = world.snapshot()
            self.generators[i + 1:] = [None] * (len(self.steps) - i - 1)
            self.depth += 1
            if self.depth == len(self.steps):
                return list(self.values)
        return None


def skeleton_steps(task: StripsTask, plan: Sequence[int]) -> List[Step]:
    """Basis steps of a skeleton with the state each must produce (macros expanded)."""
    steps, state = [], task.init
    for op_id in plan:
        op = task.operators[op_id]
        for basis_id in op.steps or (op_id,):
            basis = task.operators[basis_id]
            state = task.successor(state, basis)
            steps.append(Step(basis.name, basis.args, state, op.name if basis_id != op_id else None))
    return steps
