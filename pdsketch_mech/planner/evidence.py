"""What refinement has learned about the scene, in one store, and the one estimate it gives a
skeleton.

Refinement reports every simulated outcome of a step (as the skeleton expects or not) and
every visit that found no value. What the store holds, and the factor each gives a skeleton:

- **failures**: the same step from the same contact state (skeleton.py, its *question*) is
  the same question in every skeleton, however the skeletons got there. Where a step has
  only failed from that state in the *other* skeletons (F times; a skeleton's own work is in
  its effort already), the factor is the chance that it is not dead there: if it works
  there as often as it does where it works (p, Laplace's rule over the states where it has
  worked; over every step's, for a step that has worked nowhere yet), F failures had chance
  q = (1 - p)^F, so P(works | F failures) = q / (1 + q) against the prior 1/2. Where it has
  worked, 1: one easy step says nothing of a skeleton's others. A sampler that ran dry
  says more about the scene's continuous state than about the step: it is not counted.
- **a way past a dead step**: a step found dead where the scene began (believed dead now,
  or being revisited: a revisit does not undo the way found past it) that has simulated
  after the same steps (skeleton.py, its *context*; the grasp of a box out of reach, once
  a hook pulled it closer), in any skeleton, this one included, whichever mechanism the
  step belonged to: `unblock_gain`. Those steps are the only way found past the scene as it
  began, and every skeleton that begins with them shares it.
- **dead steps**: a step whose objects nothing earlier touched (a *pristine* step) meets them
  as the scene began, whatever the skeleton; after `dead_after` dry visits with no feasible
  value ever, it is believed dead there (with the samplers that ran dry: a mechanism's own
  anchored proposals apart from the generic ones). The skeleton search defers paths
  that repeat it (supply.py), and refinement does not sample it again while its objects lie
  where they began. A belief, not a verdict: samplers are random, and a thin object's grasps may all
  miss three visits in a row. Found dead for the k-th time when the planner's total work is
  W, it is believed alive again once the total reaches W * revisit**k (`advance`): one
  skeleton that waits on it comes back to try it, `dead_after` more dry visits set it
  aside again, and a feasible value clears it for good (`cleared`), when everything that
  waits on it comes back. The share of work this costs shrinks geometrically, and no step
  is set aside for ever.
- **detours**: operators that return the symbolic state to one seen before, handling no
  object of a dead step, change nothing the planner knows needs changing: each counts as a
  step with the uninformed chance 1/2 of being needed.
- **promises**: per mechanism, whatever its grounding, how often its last step simulated as
  promised in the other skeletons: Laplace's rule against the uninformed 1/2, never above 1.
- **learned groundings**: with learned samplers, how far a mechanism grounding's classifier
  scores fall behind its best rival's (promise.py), as a log-probability ratio, never below
  `floor` on its own: a classifier wrong about a shape costs a bounded factor, which evidence
  from the scene (a prefix past a dead step) can still outweigh.

The estimate is the product of these ratios, never below `floor`: every skeleton keeps a
share of the work (docs/planner.md argues completeness from it).
"""
from __future__ import annotations

import math
import time
from collections import Counter, defaultdict
from typing import Collection, Dict, List, Optional, Sequence, Set, Tuple

from ..symbolic.task import StripsTask
from .budget import DEFAULT_BUDGET, SearchBudget
from .promise import GroundingPromise
from .skeleton import (Asked, Context, Question, Skeleton, StepKey, belief_owner, detour_steps, objects_of,
                       touch_masks)


class Evidence:
    """Outcomes by question, ways past dead steps, dead pristine steps, detours, learned
    groundings' scores: one store (module docstring)."""

    def __init__(self, task: StripsTask, promise: Optional[GroundingPromise] = None,
                 start: Optional[float] = None, budget: SearchBudget = DEFAULT_BUDGET,
                 own_samplers: Collection[str] = ()):
        self.task, self.budget = task, budget
        self.own_samplers = frozenset(own_samplers)   # mechanisms proposing values of their own (skeleton.py)
        self.dead_after, self.floor, self.gain = budget.dead_after, budget.floor, budget.unblock_gain
        self.promise = promise if promise is not None else GroundingPromise()
        self.start = time.perf_counter() if start is None else start
        self.masks, self.bits = touch_masks(task)   # per operator: the movable objects it handles
        ops = task.operators   # a mechanism's steps with proposals of their own are keyed by it
        owners = [belief_owner(op.name if op.steps else None, self.own_samplers) for op in ops]
        self._op_steps = [tuple(((ops[b].name, objects_of(ops[b].args), owners[i]), self.masks[b])
                                for b in (op.steps or (i,)))
                          for i, op in enumerate(ops)]
        self.flagged = 0                            # bits of the objects some dead step is about
        self.dry: Counter = Counter()
        self.feasible: Set[StepKey] = set()
        self.dead: Dict[StepKey, float] = {}        # -> seconds from the start when found dead
        self.deaths = 0                             # times a step was found dead so far (grows only)
        self.revivals = 0                           # times a dead step was believed alive again (grows only)
        self.revived: List[StepKey] = []            # those steps, in that order
        self.cleared = 0                            # times a step once found dead proved feasible (grows only)
        self.work = 0                               # the planner's work so far, in units
        self.verdicts: Counter = Counter()          # step -> times it was found dead
        self.first_dead: Dict[StepKey, float] = {}  # step ever found dead and not cleared -> when first
        self._dead_steps: Counter = Counter()      # those as (operator, objects), whichever samplers
        self.revisit_at: Dict[StepKey, float] = {}  # dead step -> total work at which it is revisited
        self._totals: Dict[Question, List[int]] = defaultdict(lambda: [0, 0])            # [successes, failures]
        self._by_owner: Dict[Tuple[Question, int], List[int]] = defaultdict(lambda: [0, 0])
        # Outcomes where a step has worked at least once: how often it works where it works,
        # per step and over every step (for a step that has worked nowhere yet).
        self._working: Dict[Asked, List[int]] = defaultdict(lambda: [0, 0])
        self._working_all = [0, 0]
        # (step, steps before) that have simulated, whichever mechanism the step belonged to:
        # past a dead step, what matters is that the steps before moved its objects.
        self._passed: Set[Tuple[StepKey, Tuple[Asked, ...]]] = set()
        self._detours: Dict[Tuple[int, ...], Tuple[int, int]] = {}   # plan -> (flagged, detour operators)
        # Per mechanism (and per skeleton): its last step simulated as promised, or not.
        self._promises: Dict[str, List[int]] = defaultdict(lambda: [0, 0])
        self._promises_by_owner: Dict[Tuple[str, int], List[int]] = defaultdict(lambda: [0, 0])

    # -- what refinement reports ------------------------------------------------------
    def simulated(self, skeleton: Skeleton, index: int, ok: bool) -> None:
        """Step `index` of `skeleton` simulated as the skeleton expects (ok) or not."""
        question, context = skeleton.questions[index], skeleton.contexts[index]
        total = self._totals[question]
        total[0 if ok else 1] += 1
        self._by_owner[(question, skeleton.number)][0 if ok else 1] += 1
        if ok:
            self._passed.add((context[0][:2], context[1]))
        step = skeleton.steps[index] if index < len(skeleton.steps) else None
        if step is not None and step.certified:   # a mechanism kept its promise, or not
            self._promises[step.mechanism][0 if ok else 1] += 1
            self._promises_by_owner[(step.mechanism, skeleton.number)][0 if ok else 1] += 1
        if total[0]:   # the step works here: its outcomes here say how often it works where it does
            added = total if ok and total[0] == 1 else ((1, 0) if ok else (0, 1))
            for counts in (self._working[question[0]], self._working_all):
                counts[0] += added[0]
                counts[1] += added[1]

    def ran_dry(self, key: Optional[StepKey]) -> bool:
        """A visit of a step found no feasible value; `key`: the step's pristine key (None:
        not pristine). True if that made the pristine step dead. (A sampler that ran dry says
        more about the scene's continuous state than about the step: no outcome is counted.)"""
        if key is None or key in self.feasible or key in self.dead:
            return False
        self.dry[key] += 1
        if self.dry[key] < self.dead_after:
            return False
        self.dead[key] = round(time.perf_counter() - self.start, 3)
        if key not in self.first_dead:
            self.first_dead[key] = self.dead[key]
            self._dead_steps[key[:2]] += 1
        self.deaths += 1
        self.verdicts[key] += 1
        self.revisit_at[key] = max(self.work, self.dead_after) * self.budget.revisit ** self.verdicts[key]
        for name in key[1]:
            if name in self.bits:
                self.flagged |= 1 << self.bits[name]
        return True

    def flagged_objects(self) -> List[str]:
        """The objects some step found dead is about (what explains a detour through them)."""
        return [name for name, bit in self.bits.items() if self.flagged >> bit & 1]

    def flag(self, objects: Sequence[str]) -> None:
        """Take `objects` as ones a dead step is about, as another search found them."""
        for name in objects:
            if name in self.bits:
                self.flagged |= 1 << self.bits[name]

    def advance(self, work: int) -> bool:
        """The planner has done `work` units in all: steps whose revisit is due are believed
        alive again (their dry visits start over). True if one was."""
        self.work = work
        due = [key for key, at in self.revisit_at.items() if at <= work and key in self.dead]
        for key in due:
            self._revive(key)
        return bool(due)

    def revive_earliest(self) -> bool:
        """Nothing else can be worked on (every path left repeats a step believed dead): the
        dead step whose revisit is due first is believed alive again now, as if the work had
        grown to it. False if no step is believed dead."""
        if not self.revisit_at:
            return False
        self._revive(min(self.revisit_at, key=lambda k: (self.revisit_at[k], str(k))))
        return True

    def _revive(self, key: StepKey) -> None:
        """Dead step `key` is believed alive again: its dry visits start over."""
        del self.dead[key], self.revisit_at[key]
        self.dry[key] = 0
        self.revivals += 1
        self.revived.append(key)

    def found(self, key: Optional[StepKey]) -> None:
        """Pristine step `key` had a feasible value (it simulated without error): never dead."""
        if key is not None and key not in self.feasible:
            self.feasible.add(key)
            self.dead.pop(key, None)
            self.revisit_at.pop(key, None)
            if self.first_dead.pop(key, None) is not None:
                self._dead_steps[key[:2]] -= 1
            self.cleared += key in self.verdicts

    # -- what the search and refinement ask -------------------------------------------
    def blocks(self, keys: Sequence[Optional[StepKey]]) -> bool:
        """Whether a skeleton with these pristine keys repeats a dead step."""
        return any(k in self.dead for k in keys if k is not None)

    def blocks_operator(self, handled: int, op: int) -> bool:
        """Whether operator `op` (its steps, for a mechanism), after a path that handled the
        objects `handled`, has a dead pristine step (the skeleton search's callback)."""
        if not self.dead:
            return False
        for key, mask in self._op_steps[op]:
            if not mask & handled and key in self.dead:
                return True
            handled |= mask
        return False

    def is_dead(self, name: str, args: Sequence[str], mechanism: Optional[str]) -> bool:
        """Whether the step `name args` of `mechanism` (None: a basis step), met as the scene
        began, is dead with the samplers it draws from."""
        return (name, objects_of(args), belief_owner(mechanism, self.own_samplers)) in self.dead

    def was_dead(self, name: str, args: Sequence[str]) -> bool:
        """Whether the step `name args`, met as the scene began, was found dead with any
        samplers and never found feasible since."""
        return self._dead_steps[(name, objects_of(args))] > 0

    def movable(self, args: Sequence[str]) -> List[str]:
        """The objects among `args` that steps may move (not fixed, not placeholders)."""
        return [a for a in args if a in self.bits]

    def labels(self) -> Dict[str, float]:
        """Steps found dead and never found feasible since (believed dead now, or being
        revisited), as '(name objects...)' (and the mechanism whose samplers ran dry), and
        when each was first found dead (s)."""
        return {f"({name} {' '.join(objects)})" + (f" in {mechanism}" if mechanism else ""): t
                for (name, objects, mechanism), t in self.first_dead.items()}

    # -- the estimate -----------------------------------------------------------------
    def counts(self, question: Question, owner: int = 0) -> Tuple[int, int]:
        """(successes, failures) of `question` in skeletons other than number `owner` (0: all)."""
        total = self._totals.get(question)
        if total is None:
            return 0, 0
        own = self._by_owner.get((question, owner), (0, 0))
        return total[0] - own[0], total[1] - own[1]

    def detours(self, plan: Sequence[int]) -> int:
        """The plan's operators in detours no dead step explains (skeleton.detour_steps)."""
        key = tuple(plan)
        known = self._detours.get(key)
        if known is None or known[0] != self.flagged:
            known = self._detours[key] = (self.flagged, detour_steps(self.task, plan, self.masks, self.flagged))
        return known[1]

    def log_lift(self, context: Context, question: Question, owner: int = 0) -> float:
        """What is known of a step, as a natural log (module docstring): `unblock_gain` where a
        step dead as the scene began has worked after the same steps, the chance that it is
        not dead where it has only failed from the same contact state, 1 otherwise."""
        if self._dead_steps[context[0][:2]] > 0 and (context[0][:2], context[1]) in self._passed:
            return math.log(self.gain)   # its own success too: getting past it is not in its effort
        successes, failures = self.counts(question, owner)
        if successes or not failures:
            return 0.0
        working = self._working.get(question[0]) or self._working_all
        rate = (working[0] + 1) / (working[0] + working[1] + 2)   # Laplace's rule where it works
        unlucky = failures * math.log1p(-rate)   # log P(those failures | it works here too)
        return math.log(2.0) + unlucky - math.log1p(math.exp(unlucky))   # P(works | failures) / (1/2)

    def log_terms(self, skeleton: Skeleton, owner: int = 0) -> Dict[str, float]:
        """The estimate's factors, as natural logs: outcomes elsewhere, detours, learned
        groundings (`owner`: the skeleton's number once it works, whose own outcomes are left
        out; 0: a skeleton not created yet, weighed by everything seen)."""
        outcomes = 0.0
        if self._totals:   # a step asked again the same way is one question
            for context, question in set(zip(skeleton.contexts, skeleton.questions)):
                outcomes += self.log_lift(context, question, owner)
        groundings = sum(self.promise.gap(g, promised) for g, promised in set(skeleton.groundings()))
        kept = sum(self.log_kept(mechanism, owner) for mechanism in {g[0] for g, _ in skeleton.groundings()})
        # A classifier wrong about a shape costs at most `floor`, whatever else is known.
        return {"outcomes": outcomes, "detours": -math.log(2.0) * self.detours(skeleton.plan),
                "groundings": min(0.0, max(math.log(self.floor), groundings)), "promises": kept}

    def log_kept(self, mechanism: str, owner: int = 0) -> float:
        """How often `mechanism` kept its promise in other skeletons, whatever its grounding,
        as a natural log: 2 (s + 1) / (s + f + 2) against the uninformed 1/2 (Laplace's rule),
        never above 1. A mechanism whose certified facts keep failing (a user's trick whose
        effect the generic samplers rarely reproduce) weighs on every skeleton that uses it,
        new groundings included; once it works, little."""
        total = self._promises.get(mechanism)
        if total is None:
            return 0.0
        own = self._promises_by_owner.get((mechanism, owner), (0, 0))
        kept, broken = total[0] - own[0], total[1] - own[1]
        return min(0.0, math.log(2.0 * (kept + 1) / (kept + broken + 2)))

    def estimate(self, skeleton: Skeleton, owner: int = 0) -> float:
        """The skeleton's chance of being refined, relative to one nothing is known about:
        the product of `log_terms`, at least `floor`."""
        return max(self.floor, math.exp(sum(self.log_terms(skeleton, owner).values())))
