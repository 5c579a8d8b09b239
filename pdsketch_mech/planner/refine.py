"""ContinuousSearch (paper Alg. 1) for one skeleton: sample a step's parameters, simulate it,
check the contact graph it produced against the skeleton, and backtrack: step by step, or
past a step that cannot have caused the dead end (backjumping, `Refinement._irrelevant`).

A `Refinement` keeps its search state (snapshots, per-step sample generators), so the
adaptive planner can give it a time slice, move to another skeleton, and come back.
"""
from __future__ import annotations

import itertools
import time
from collections import Counter
from dataclasses import dataclass, field
from typing import Callable, Dict, Iterator, List, Optional, Set

import numpy as np

from ..symbolic.task import StripsTask, bits
from ..world.snapshot import Snapshot
from ..world.world import World
from .bindings import StepSampler
from .evidence import Evidence
from .execute import contact_mask, execute_step, observed_state
from .schedule import SLICE
from .skeleton import Skeleton, Step, mismatch, step_label


# Checks a refined skeleton must pass before it counts (the planner re-executes it in a
# fresh world): the values of every step in, an error message (or None) out.
Validator = Callable[[List[Step], List[Dict[str, object]]], Optional[str]]


@dataclass
class Refinement:
    """The continuous search of one skeleton, resumable across time slices. With `evidence`
    (the planner's shared store), it reports every step's outcome under the step's context
    and skips a step found dead where it began; without (self-play), it searches alone."""

    skeleton: Skeleton
    start: Snapshot
    world: World
    task: StripsTask
    sampler: StepSampler
    rng: np.random.Generator
    validate: Optional[Validator] = None
    evidence: Optional[Evidence] = None
    rank: int = 1                 # creation order among the plan's skeletons (1 = first)
    failures: Counter = field(default_factory=Counter)
    # (step label, why) -> how often: the step with its objects, so that the planner can say
    # which step of the scene failed most (failure_hint.py); shared between skeletons.
    step_failures: Counter = field(default_factory=Counter)
    executions: int = 0
    effort: int = 0               # work units spent: sampler visits and simulated steps
    rejected: int = 0             # refinements the fresh-world re-execution refused
    exhausted: bool = False

    def __post_init__(self) -> None:
        self.steps, self.number = self.skeleton.steps, self.skeleton.number
        self.pristine = self.skeleton.pristine if self.evidence is not None else [None] * len(self.steps)
        n = len(self.steps)
        self.snapshots: List[Optional[Snapshot]] = [self.start] + [None] * n
        self.generators: List[Optional[Iterator[Dict[str, object]]]] = [None] * n
        self.visit_values = [0] * n   # values the current visit of each step has drawn
        self.visit_successes = [0] * n  # ... and how many of them simulated as expected
        self.values: List[Optional[Dict[str, object]]] = [None] * n
        self.skipped = [False] * n    # the current visit of each step was known dead (not sampled)
        self.depth = 0
        self.deepest = 0              # most steps simulated in a row so far (statistics)
        self.root_yields = 0
        self.unblocked: Set[int] = set()  # steps found dead where the scene began that simulated here
        self.observable = contact_mask(self.task)

    def run(self, deadline: float, max_work: int) -> Optional[List[Dict[str, object]]]:
        """Search for `max_work` more units of work (a parameter sample drawn and simulated,
        or a step's sampler running dry: counted, not timed, so that how skeletons interleave
        does not depend on the machine's speed) or until `deadline`; the values of every
        step if the skeleton is refined."""
        world = self.world
        budget = self.effort + max_work
        if not self.steps:  # the goal holds symbolically already: it must hold in the scene too
            world.restore(self.start)
            self.exhausted = bool((observed_state(self.task, world) ^ self.task.init) & self.observable)
            return None if self.exhausted else []
        while not self.exhausted and self.effort < budget and time.perf_counter() < deadline:
            self.effort += 1
            i = self.depth
            step = self.steps[i]
            world.restore(self.snapshots[i])
            if self.generators[i] is None:
                # A mechanism's later steps are told what its earlier steps drew.
                parents = {k: v for values in self.values[i - step.index:i] for k, v in (values or {}).items()}
                self.skipped[i] = self._dead_where_it_began(i)
                self.generators[i] = iter(()) if self.skipped[i] else itertools.islice(
                    self.sampler.samples(world, step.context(self.pristine[i] is not None), self.rng, parents),
                    SLICE)   # a visit tries SLICE values
                self.visit_values[i] = 0
                self.visit_successes[i] = 0
            values = next(self.generators[i], None)
            if values is None:  # this step is out of samples: revise the step before it
                self.generators[i] = None
                why = "dead, its objects where they began" if self.skipped[i] else "no feasible parameters"
                self.failures[f"{step.name}: {why}"] += 1
                if not self.skipped[i]:  # a skipped visit tried nothing
                    self.step_failures[(step_label(step.name, step.args), why)] += 1
                if self.visit_values[i] == 0 and self.evidence is not None and not self.skipped[i]:
                    self.evidence.ran_dry(self.pristine[i])
                if i > 0:
                    if self._continues(i - 1) and self.visit_successes[i] == 0:
                        # the step before led nowhere in this visit: its values failed
                        self.sampler.note_outcome(self.values[i - 1], False)
                    self.depth -= 1
                    if i > 1 and self.visit_successes[i] == 0 and self._irrelevant(i - 1, i):
                        # Backjump: the step before neither names nor moved what this step
                        # acts on, so its other values would meet the same dead end.
                        self.generators[i - 1] = None
                        self.failures[f"{self.steps[i - 1].name}: skipped back over, step {i + 1} dead after it"] += 1
                        self.depth -= 1
                    continue
                # The first step's visit is over; the next slice draws fresh values. A visit
                # that yielded nothing ends the skeleton only once the step is known dead
                # (evidence.py): one dry visit of a stochastic sampler (a thin object's grasps)
                # is bad luck as often as impossibility.
                self.exhausted = self.root_yields == 0 and self._root_dead()
                self.root_yields = 0
                return None
            if i == 0:
                self.root_yields += 1
            self.visit_values[i] += 1
            outcome = execute_step(world, self.snapshots[i], step.name, step.args, values)
            self.executions += 1
            self.sampler.note_simulated(values)
            if not outcome.ok:
                self._failed(i, values, outcome.reason)
                continue
            if self.evidence is not None:
                self.evidence.found(self.pristine[i])
            observed = observed_state(self.task, world)
            # A mechanism's promise first: its last step expects the certified facts too.
            if step.certified and not self._certified(step, observed):
                self._failed(i, values, "its :certified facts do not hold after its steps", mechanism=True)
                self._end_visit_if_decided_before(i, observed)
                continue
            if mismatch(observed, step, self.observable):
                self._failed(i, values, "simulated contacts differ from the skeleton")
                continue
            self._note(i, True)
            if self.evidence is not None and self.evidence.is_dead(step.name, step.args):
                self.unblocked.add(i)  # done what the scene as it began did not allow
            # A value of a mechanism step is worth what it leads to: it succeeds once the
            # mechanism's next step simulates after it too (a grasp of a blocker that lets no
            # placement hold fails), or with the mechanism's last step (trust.py).
            if not self._continues(i):
                self.sampler.note_outcome(values, True)
            if i > 0 and self._continues(i - 1):
                self.sampler.note_outcome(self.values[i - 1], True)
            self.visit_successes[i] += 1
            self.values[i] = values
            self.snapshots[i + 1] = world.snapshot()
            self.generators[i + 1:] = [None] * (len(self.steps) - i - 1)
            self.depth += 1
            self.deepest = max(self.deepest, self.depth)
            if self.depth == len(self.steps):
                error = self.validate(self.steps, list(self.values)) if self.validate else None
                if error is None:
                    return list(self.values)
                # Not a plan after all: count it and look for other values of the last step.
                self.rejected += 1
                self.failures[f"rejected: {error}"] += 1
                self.depth -= 1
        return None

    def _continues(self, i: int) -> bool:
        """Whether step i + 1 is the next step of step i's mechanism."""
        step, following = self.steps[i], self.steps[i + 1] if i + 1 < len(self.steps) else None
        return (step.mechanism is not None and following is not None and following.mechanism == step.mechanism
                and following.index == step.index + 1)

    def _failed(self, i: int, values: Dict[str, object], why: str, mechanism: bool = False) -> None:
        """Simulated step i failed: count why (against the step, or the `mechanism` it ends),
        tell the samplers of its values, and share the outcome with the other skeletons."""
        step = self.steps[i]
        if mechanism:
            self.failures[f"{step.mechanism}: {why}"] += 1
            self.step_failures[(step_label(step.mechanism, step.mechanism_args), why)] += 1
        else:
            self.failures[f"{step.name}: {why}"] += 1
            self.step_failures[(step_label(step.name, step.args), why)] += 1
        self.sampler.note_outcome(values, False)
        self._note(i, False)

    def _note(self, i: int, ok: bool) -> None:
        """Share step i's simulated outcome with the other skeletons (evidence.py)."""
        if self.evidence is not None:
            self.evidence.simulated(self.skeleton, i, ok)

    def _irrelevant(self, j: int, i: int) -> bool:
        """Whether step j (before step i) is irrelevant to step i's failure: it names none of
        the movable objects step i acts on and left them where they were (a tool put down
        after a poke, then no grasp of the box the poke left in the tunnel: another place
        for the tool leaves the box where it is; another poke may not). Objects step j
        moved may still have been in step i's way; the next values of the steps before
        move them again."""
        world = self.world
        acted_on = [a for a in self.steps[i].args if a in world.bodies and not world.bodies[a].fixed]
        if not acted_on or set(acted_on) & set(self.steps[j].args):
            return False
        world.restore(self.snapshots[i])
        return not any(world.moved_since(self.snapshots[j], a) for a in acted_on)

    def _end_visit_if_decided_before(self, i: int, observed: int) -> None:
        """A mechanism's last step that failed on certified facts about objects it neither
        names nor moved (the box a held stick did not push onto the platform, found wrong once
        the stick is put down) cannot succeed with other values: the steps before decided it,
        so the search goes back to them now instead of drawing the rest of this visit. (The
        paper's mechanisms certify facts about what their last step handles: never so.)"""
        step, world = self.steps[i], self.world
        if not step.certified:
            return
        promised = 0
        for true, false in step.certified:
            promised |= true | false
        wrong = (observed ^ step.expected) & self.observable & promised
        named = {arg for fact in bits(wrong) for arg in self.task.facts[fact][1:]}
        movable = [n for n in named if n in world.bodies and not world.bodies[n].fixed]
        if not movable or set(movable) & set(step.args):
            return
        if not any(world.moved_since(self.snapshots[i], n) for n in movable):
            self.generators[i] = iter(())

    def _dead_where_it_began(self, i: int) -> bool:
        """Whether step i is a step found dead (evidence.py) that earlier steps touched but
        left where the scene began: a box out of reach with a tool put down on it, a plate a
        weight did not tip. Sampling it would be the dead step's dry visit again, so the
        visit is skipped (it still costs its unit of work); other values of the earlier steps
        that do move the objects get the step sampled."""
        evidence, step = self.evidence, self.steps[i]
        if evidence is None or not evidence.dead or self.pristine[i] is not None:
            return False
        objects = evidence.movable(step.args)
        if not objects or not evidence.is_dead(step.name, step.args):
            return False
        return not any(self.world.moved_since(self.start, a) for a in objects)

    def _root_dead(self) -> bool:
        """Whether the first step's dry visit ends the skeleton: always without shared
        evidence (self-play), else once the evidence calls the step dead."""
        if self.evidence is None or self.pristine[0] is None:
            return True
        return self.pristine[0] in self.evidence.dead

    def _certified(self, step: Step, observed: int) -> bool:
        """Some alternative of the mechanism's promise holds: observable facts as simulated,
        the others as the skeleton has them."""
        state = (observed & self.observable) | (step.expected & ~self.observable)
        return any(state & pre == pre and not state & neg for pre, neg in step.certified)

