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
from typing import TYPE_CHECKING, Callable, Dict, Iterator, List, Optional, Sequence, Set, Tuple

import numpy as np

from ..samplers.interface import StepContext
from ..symbolic.task import Operator, StripsTask
from ..world.snapshot import Snapshot
from ..world.world import World
from .bindings import StepSampler
from .execute import contact_mask, execute_step, observed_state

if TYPE_CHECKING:
    from .bottlenecks import SharedOutcomes
    from .pristine import PristineFailures, StepKey

TRIES_PER_VISIT = 3  # parameter samples tried at a step before backtracking to the one before

# Checks a refined skeleton must pass before it counts (the planner re-executes it in a
# fresh world): the values of every step in, an error message (or None) out.
Validator = Callable[[List["Step"], List[Dict[str, object]]], Optional[str]]


@dataclass(frozen=True)
class Step:
    name: str
    args: Tuple[str, ...]
    expected: int                 # symbolic state the step must produce
    mechanism: Optional[str] = None
    certified: Tuple[Tuple[int, int], ...] = ()  # the last step of a mechanism: what it promised
    index: int = 0                # position in its mechanism (0 for a basis step)
    mechanism_args: Tuple[str, ...] = ()
    roles: Tuple[Tuple[str, str], ...] = ()  # the mechanism's placeholders and their variables
    tolerated: int = 0            # support facts that may hold although `expected` lacks them

    def context(self) -> StepContext:
        """What the step's samplers are told about it."""
        return StepContext(self.name, self.args, self.mechanism, self.mechanism_args, self.index, self.roles)


def skeleton_groundings(steps: Sequence[Step]) -> List[Tuple[Tuple[str, Tuple[str, ...]], Tuple[Tuple[int, int], ...]]]:
    """A skeleton's mechanism groundings, (mechanism, its object arguments), each with what it
    promises (its last step's certified facts)."""
    return [((s.mechanism, s.mechanism_args), s.certified) for s in steps if s.certified]


@dataclass
class Refinement:
    """The continuous search of one skeleton, resumable across time slices."""

    steps: List[Step]
    start: Snapshot
    world: World
    task: StripsTask
    sampler: StepSampler
    rng: np.random.Generator
    validate: Optional[Validator] = None
    rank: int = 1                 # creation order among skeletons (1 = first)
    failures: Counter = field(default_factory=Counter)
    executions: int = 0
    effort: int = 0               # work units spent: sampler visits and simulated steps
    rejected: int = 0             # refinements the fresh-world re-execution refused
    exhausted: bool = False
    # Steps on untouched objects (pristine.py): keys per step, and the planner's shared record.
    pristine: Sequence[Optional["StepKey"]] = ()
    memo: Optional["PristineFailures"] = None
    # The planner's record of simulated outcomes per step and contact state (bottlenecks.py).
    outcomes: Optional["SharedOutcomes"] = None

    def __post_init__(self) -> None:
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
        self.outcome_keys = self.outcomes.keys(self.steps) if self.outcomes is not None else []

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
                    self.sampler.samples(world, step.context(), self.rng, parents), TRIES_PER_VISIT)
                self.visit_values[i] = 0
                self.visit_successes[i] = 0
            values = next(self.generators[i], None)
            if values is None:  # this step is out of samples: revise the step before it
                self.generators[i] = None
                why = "dead, its objects where they began" if self.skipped[i] else "no feasible parameters"
                self.failures[f"{step.name}: {why}"] += 1
                if self.visit_values[i] == 0 and self.memo is not None and self.pristine:
                    self.memo.ran_dry(self.pristine[i])
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
                # (pristine.py): one dry visit of a stochastic sampler (a spoon's grasps, 120
                # proposals) is bad luck as often as impossibility, and ending the skeleton
                # there lost the Lever mechanism's own skeleton a quarter second in.
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
                self._failed(i, values, f"{step.name}: {outcome.reason}")
                continue
            if self.memo is not None and self.pristine:
                self.memo.found(self.pristine[i])
            observed = observed_state(self.task, world)
            if mismatch(observed, step, self.observable):
                self._failed(i, values, f"{step.name}: simulated contacts differ from the skeleton")
                continue
            if step.certified and not self._certified(step, observed):
                self._failed(i, values, f"{step.mechanism}: its :certified facts do not hold after its steps")
                continue
            self._note(i, True)
            if self.memo is not None and self.memo.is_dead(step.name, step.args):
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

    def groundings(self) -> List[Tuple[Tuple[str, Tuple[str, ...]], Tuple[Tuple[int, int], ...]]]:
        return skeleton_groundings(self.steps)

    def _continues(self, i: int) -> bool:
        """Whether step i + 1 is the next step of step i's mechanism."""
        step, following = self.steps[i], self.steps[i + 1] if i + 1 < len(self.steps) else None
        return (step.mechanism is not None and following is not None and following.mechanism == step.mechanism
                and following.index == step.index + 1)

    def _failed(self, i: int, values: Dict[str, object], reason: str) -> None:
        """Simulated step i failed: count why, tell the samplers of its values, and share the
        outcome with the other skeletons."""
        self.failures[reason] += 1
        self.sampler.note_outcome(values, False)
        self._note(i, False)

    def _note(self, i: int, ok: bool) -> None:
        """Share step i's simulated outcome with the other skeletons (bottlenecks.py)."""
        if self.outcomes is not None:
            self.outcomes.note(self.outcome_keys[i], self.rank, ok)

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

    def _dead_where_it_began(self, i: int) -> bool:
        """Whether step i is a step found dead (pristine.py) that earlier steps touched but
        left where the scene began: a box out of reach with a tool put down on it, a plate a
        weight did not tip. Sampling it would be the dead step's dry visit again, so the
        visit is skipped (it still costs its unit of work); other values of the earlier steps
        that do move the objects get the step sampled."""
        memo, step = self.memo, self.steps[i]
        if memo is None or not memo.dead or not self.pristine or self.pristine[i] is not None:
            return False
        objects = memo.movable(step.args)
        if not objects or not memo.is_dead(step.name, step.args):
            return False
        return not any(self.world.moved_since(self.start, a) for a in objects)

    def _root_dead(self) -> bool:
        """Whether the first step's dry visit ends the skeleton: always without a shared
        record of pristine failures (self-play), else once the record calls the step dead."""
        if self.memo is None or not self.pristine or self.pristine[0] is None:
            return True
        return self.pristine[0] in self.memo.dead

    def _certified(self, step: Step, observed: int) -> bool:
        """Some alternative of the mechanism's promise holds: observable facts as simulated,
        the others as the skeleton has them."""
        state = (observed & self.observable) | (step.expected & ~self.observable)
        return any(state & pre == pre and not state & neg for pre, neg in step.certified)


def mismatch(observed: int, step: Step, observable: int) -> int:
    """The observable facts where the simulation and the skeleton disagree after `step`:
    a fact the skeleton expects that does not hold, or one that holds unexpected and is
    not tolerated."""
    diff = (observed ^ step.expected) & observable
    return diff & ~(observed & step.tolerated)


def goal_free_supports(task: StripsTask) -> int:
    """The task's `support` facts that the goal does not need false (nor any of a
    disjunctive goal's alternatives)."""
    supports = sum(1 << i for fact, i in task.fact_ids.items() if fact[0] == "support")
    needed_false = task.goal_neg
    for op in task.operators:
        if op.artificial:
            needed_false |= op.neg
    return supports & ~needed_false


def tolerated_supports(task: StripsTask, candidates: int, step: Operator, later: Sequence[int]) -> int:
    """Support facts (of `candidates`) that `step` may add beyond its effects: an object
    that ends up resting on one more body than the skeleton says still rests on the ones
    it says (a weight put on a plate's overhang, its handle on the wall beyond; the plate
    it levers into the pit, now touching the table below too). Not so the object a step
    moves without saying where it ends up (a push: an object pushed onto something else
    did not do what the skeleton says), nor a fact a later step needs false (a negative
    precondition, or a conditional effect's condition)."""
    needed_false = 0
    for op_id in later:
        op = task.operators[op_id]
        needed_false |= op.neg
        for cond in op.conditional:
            needed_false |= cond.pre | cond.neg
    moved = step.args[0] if step.args else None
    own = sum(1 << i for fact, i in task.fact_ids.items() if fact[0] == "support" and fact[1] == moved)
    if step.add & own:  # the step says where its object comes to rest
        own = 0
    return candidates & ~needed_false & ~own


def skeleton_steps(task: StripsTask, plan: Sequence[int]) -> List[Step]:
    """Basis steps of a skeleton with the state each must produce (macros expanded) and
    the support facts each may add unexpected (`tolerated_supports`). The artificial
    steps that reach a disjunctive goal have no physical content: the states the real
    steps must produce already satisfy one disjunct."""
    basis_ids = [b for op_id in plan if not task.operators[op_id].artificial
                 for b in (task.operators[op_id].steps or (op_id,))]
    steps, state, supports = [], task.init, goal_free_supports(task)
    for op_id in plan:
        op = task.operators[op_id]
        if op.artificial:
            continue
        expansion = op.steps or (op_id,)
        for k, basis_id in enumerate(expansion):
            basis = task.operators[basis_id]
            state = task.successor(state, basis)
            last = k == len(expansion) - 1
            macro = basis_id != op_id
            steps.append(Step(basis.name, basis.args, state, op.name if macro else None,
                              op.certified if last and op.steps else (), k if macro else 0,
                              tuple(a for a in op.args if not a.startswith("#")) if macro else (),
                              op.roles if macro else (),
                              tolerated_supports(task, supports, basis, basis_ids[len(steps) + 1:])))
    return steps
