"""ContinuousSearch (paper Alg. 1) for one skeleton: sample a step's parameters, simulate it,
check the contact graph it produced against the skeleton, and backtrack, with one rule for
where to: conflict-directed backjumping.

Each visit of a step gathers its *conflict*: the movable objects its failures were about
(the objects the step acts on, when no value worked; the objects of the facts that came out
wrong, when a simulated outcome differed from the skeleton). A failure whose wrong facts are
about objects the step neither names nor moved was decided before it: no other value of the
step can change it, so its visit ends at once. When a visit ends with nothing simulated as
expected, the search goes back to the latest earlier step that names an object of the
conflict or moved one (a tool put down after a poke does not free the box the poke left in
its tunnel: the next poke may), and the steps in between draw afresh after it. Nothing is
excluded for good: every step's values are drawn anew each time the search passes it.

A `Refinement` keeps its search state (snapshots, per-step sample generators), so the
adaptive planner can give it a slice of work, move to another skeleton, and come back.
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
from .budget import DEFAULT_BUDGET, SearchBudget
from .evidence import Evidence
from ..operators.vocabulary import BASIS, Vocabulary
from .execute import contact_mask, execute_step, observed_state
from .skeleton import Skeleton, Step, mismatch, step_label


# Checks a refined skeleton must pass before it counts (the planner re-executes it in a
# fresh world): the values of every step in, an error message (or None) out.
Validator = Callable[[List[Step], List[Dict[str, object]]], Optional[str]]


@dataclass
class Refinement:
    """The continuous search of one skeleton, resumable across slices of work. With
    `evidence` (the planner's shared store), it reports every step's outcome and skips a step
    believed dead where it began; without (self-play), it searches alone."""

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
    budget: SearchBudget = DEFAULT_BUDGET
    vocabulary: Vocabulary = BASIS
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
        self.conflicts: List[Set[str]] = [set() for _ in range(n)]   # the current visit's conflict
        self.values: List[Optional[Dict[str, object]]] = [None] * n
        self.skipped = [False] * n    # the current visit of each step was believed dead (not sampled)
        self.depth = 0
        self.deepest = 0              # most steps simulated in a row so far (statistics)
        self.root_yields = 0
        self.unblocked: Set[int] = set()  # steps found dead where the scene began that simulated here
        self.observable = contact_mask(self.task, self.vocabulary)

    def run(self, deadline: float, max_work: int) -> Optional[List[Dict[str, object]]]:
        """Search for `max_work` more units of work (a parameter sample drawn and simulated,
        or a step's sampler running dry: counted, not timed, so that how skeletons interleave
        does not depend on the machine's speed) or until `deadline`; the values of every
        step if the skeleton is refined."""
        budget = self.effort + max_work
        if not self.steps:  # the goal holds symbolically already: it must hold in the scene too
            self.world.restore(self.start)
            self.exhausted = bool((observed_state(self.task, self.world, self.vocabulary) ^ self.task.init)
                                  & self.observable)
            return None if self.exhausted else []
        while not self.exhausted and self.effort < budget and time.perf_counter() < deadline:
            self.effort += 1
            i = self.depth
            self.world.restore(self.snapshots[i])
            if self.generators[i] is None:
                self._begin_visit(i)
            values = next(self.generators[i], None)
            if values is None:
                if self._end_visit(i):
                    return None   # the first step's visit is over: the next slice draws afresh
                continue
            if i == 0:
                self.root_yields += 1
            self.visit_values[i] += 1
            if self._simulate(i, values) and self._advance(i, values):
                return list(self.values)
        return None

    # -- one visit of a step ----------------------------------------------------------
    def _begin_visit(self, i: int) -> None:
        """Start drawing values for step i (none, if it is believed dead where it began)."""
        step = self.steps[i]
        # A mechanism's later steps are told what its earlier steps drew.
        parents = {k: v for values in self.values[i - step.index:i] for k, v in (values or {}).items()}
        self.skipped[i] = self._dead_where_it_began(i)
        self.generators[i] = iter(()) if self.skipped[i] else itertools.islice(
            self.sampler.samples(self.world, step.context(self.pristine[i] is not None), self.rng, parents),
            self.budget.slice)   # a visit tries `slice` values
        self.visit_values[i] = 0
        self.visit_successes[i] = 0
        self.conflicts[i] = set()

    def _end_visit(self, i: int) -> bool:
        """Step i is out of values for this visit: record why, and go back (module
        docstring). True if that ends the first step's visit."""
        step = self.steps[i]
        self.generators[i] = None
        why = "dead, its objects where they began" if self.skipped[i] else "no feasible parameters"
        if self.visit_successes[i] == 0:
            self.failures[f"{step.name}: {why}"] += 1
            if not self.skipped[i]:  # a skipped visit tried nothing
                self.step_failures[(step_label(step.name, step.args), why)] += 1
            if self.visit_values[i] == 0:
                self.conflicts[i] |= set(self._movable(step.args))
                if self.evidence is not None and not self.skipped[i]:
                    self.evidence.ran_dry(self.pristine[i])
        if i == 0:
            # A visit that yielded nothing ends the skeleton only once the step is believed
            # dead (evidence.py): one dry visit of a stochastic sampler (a thin object's
            # grasps) is bad luck as often as impossibility.
            self.exhausted = self.root_yields == 0 and self._root_dead()
            self.root_yields = 0
            return True
        if self._continues(i - 1) and self.visit_successes[i] == 0:
            self.sampler.note_outcome(self.values[i - 1], False)   # the step before led nowhere
        target = i - 1 if self.visit_successes[i] else self._culprit(i)
        for k in range(target + 1, i):
            self.generators[k] = None
        if target < i - 1:
            self.failures[f"{self.steps[target + 1].name}: skipped back over, step {i + 1} failed after it"] += 1
        self.conflicts[target] |= self.conflicts[i]
        self.depth = target
        return False

    def _culprit(self, i: int) -> int:
        """The latest step before i that names an object of step i's conflict or moved one;
        the first step if none did (then only its fresh values can change the scene)."""
        conflict = self.conflicts[i]
        for j in range(i - 1, 0, -1):
            if conflict & set(self.steps[j].args) or self._moved(j, conflict):
                return j
        return 0

    def _moved(self, j: int, objects: Set[str]) -> bool:
        """Whether step j moved any of `objects`."""
        self.world.restore(self.snapshots[j + 1])
        return any(self.world.moved_since(self.snapshots[j], name) for name in objects)

    def _movable(self, names) -> List[str]:
        """The movable bodies among `names`."""
        bodies = self.world.bodies
        return [n for n in names if n in bodies and not bodies[n].fixed]

    # -- a value simulated --------------------------------------------------------------
    def _simulate(self, i: int, values: Dict[str, object]) -> bool:
        """Execute step i with `values` and check what the simulation did against the
        skeleton; True if it did what the skeleton says."""
        step = self.steps[i]
        outcome = execute_step(self.world, self.snapshots[i], step.name, step.args, values,
                               vocabulary=self.vocabulary)
        self.executions += 1
        self.sampler.note_simulated(values)
        if not outcome.ok:
            self.conflicts[i] |= set(self._movable(step.args))
            self._failed(i, values, outcome.reason)
            return False
        if self.evidence is not None:
            self.evidence.found(self.pristine[i])
        observed = observed_state(self.task, self.world, self.vocabulary)
        # A mechanism's promise first: its last step expects the certified facts too.
        if step.certified and not self._certified(step, observed):
            self._failed(i, values, "its :certified facts do not hold after its steps", mechanism=True)
            self._blame(i, observed, self._promised(step))
            return False
        if mismatch(observed, step, self.observable):
            self._failed(i, values, "simulated contacts differ from the skeleton")
            self._blame(i, observed, -1)
            return False
        return True

    def _blame(self, i: int, observed: int, facts: int) -> None:
        """Add the objects of the wrong `facts` to step i's conflict; if step i neither names
        nor moved any of them, the steps before decided the failure: end the visit."""
        step = self.steps[i]
        wrong = (observed ^ step.expected) & self.observable & facts
        named = self._movable({arg for fact in bits(wrong) for arg in self.task.facts[fact][1:]})
        self.conflicts[i] |= set(named)
        if named and not set(named) & set(step.args) and not any(
                self.world.moved_since(self.snapshots[i], n) for n in named):
            self.generators[i] = iter(())
        else:
            self.conflicts[i] |= set(self._movable(step.args))

    def _advance(self, i: int, values: Dict[str, object]) -> bool:
        """Step i simulated as expected: go deeper. True if that refines the skeleton."""
        step = self.steps[i]
        self._note(i, True)
        if self.evidence is not None and self.evidence.was_dead(step.name, step.args):
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
        self.snapshots[i + 1] = self.world.snapshot()
        self.generators[i + 1:] = [None] * (len(self.steps) - i - 1)
        self.depth += 1
        self.deepest = max(self.deepest, self.depth)
        if self.depth < len(self.steps):
            return False
        error = self.validate(self.steps, list(self.values)) if self.validate else None
        if error is None:
            return True
        # Not a plan after all: count it and look for other values of the last step.
        self.rejected += 1
        self.failures[f"rejected: {error}"] += 1
        self.depth -= 1
        return False

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

    def _dead_where_it_began(self, i: int) -> bool:
        """Whether step i is a step believed dead (evidence.py) that earlier steps touched but
        left where the scene began: a box out of reach with a tool put down on it, a plate a
        weight did not tip. Sampling it would be the dead step's dry visit again, so the
        visit is skipped (it still costs its unit of work); other values of the earlier steps
        that do move the objects get the step sampled."""
        evidence, step = self.evidence, self.steps[i]
        if evidence is None or not evidence.dead or self.pristine[i] is not None:
            return False
        objects = evidence.movable(step.args)
        if not objects or not evidence.is_dead(step.name, step.args, step.mechanism):
            return False
        return not any(self.world.moved_since(self.start, a) for a in objects)

    def _root_dead(self) -> bool:
        """Whether the first step's dry visit ends the skeleton's refinement: always without
        shared evidence (self-play), else while the evidence believes the step dead (the
        planner then sets the skeleton aside until it does not: bilevel.py)."""
        if self.evidence is None:
            return True
        return self.pristine[0] is not None and self.pristine[0] in self.evidence.dead

    @staticmethod
    def _promised(step: Step) -> int:
        """The facts a mechanism's last step certifies (any alternative)."""
        promised = 0
        for true, false in step.certified:
            promised |= true | false
        return promised

    def _certified(self, step: Step, observed: int) -> bool:
        """Some alternative of the mechanism's promise holds: observable facts as simulated,
        the others as the skeleton has them."""
        state = (observed & self.observable) | (step.expected & ~self.observable)
        return any(state & pre == pre and not state & neg for pre, neg in step.certified)
