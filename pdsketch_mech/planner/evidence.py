"""What refinement has learned about the scene, in one store, and the one estimate it gives a
skeleton.

Refinement reports every outcome of a step (simulated as the skeleton expects, simulated
otherwise, or its sampler ran dry) under the step's *context* (skeleton.py: the step and the
steps before it). Skeletons that begin alike ask the scene the same questions, so each
outcome is evidence for all of them:

- **outcomes**: how much better or worse a step does in its context than the same step does
  anywhere (its *lift*). Anywhere: its successes and failures (dry visits count as failures)
  in every context and skeleton, p = (S + 1) / (S + F + 2), Laplace's rule. In its context:
  the successes and failures of the *other* skeletons (a skeleton's own work is in its effort
  already), p_c = (S_c + 2 p) / (S_c + F_c + 2), the same rule with p as its prior. The lift
  p_c / p is 1 where nothing is known and below 1 where the step keeps failing. It rises above
  1 only for a step found dead where the scene began that works in this context (the grasp
  of a box out of reach, once a hook pulled it closer): that is what gets a skeleton past the
  scene as it began, while a step that is merely easier here than elsewhere says nothing
  about the skeleton's other steps.
- **dead steps**: a step whose objects nothing earlier touched (a *pristine* step) meets them
  as the scene began, whatever the skeleton; after DEAD_AFTER dry visits with no feasible
  value ever, it is dead there. The skeleton search defers paths that repeat it (supply.py),
  and refinement does not sample it again while its objects lie where they began.
- **detours**: operators that return the symbolic state to one seen before, handling no
  object of a dead step, change nothing the planner knows needs changing: each counts as a
  step with the uninformed chance 1/2 of being needed.
- **learned groundings**: with learned samplers, how far a mechanism grounding's classifier
  scores fall behind its best rival's (promise.py), as a log-probability ratio.

The estimate is the product of these ratios, never below FLOOR: every skeleton keeps a
share of the work (schedule.py argues completeness from it).
"""
from __future__ import annotations

import math
import time
from collections import Counter, defaultdict
from typing import Dict, List, Optional, Sequence, Set, Tuple

from ..symbolic.task import StripsTask
from .promise import GroundingPromise
from .skeleton import Asked, Context, Skeleton, StepKey, detour_steps, objects_of, touch_masks

DEAD_AFTER = 3        # dry visits of a pristine step, never feasible, before it is dead where it lies
FLOOR = 1.0 / 32.0    # the least estimate: the smallest share of work a skeleton keeps against the best


class Evidence:
    """Outcomes by context, dead pristine steps, learned groundings' scores: one store."""

    def __init__(self, task: StripsTask, promise: Optional[GroundingPromise] = None,
                 start: Optional[float] = None, dead_after: int = DEAD_AFTER, floor: float = FLOOR):
        self.task, self.dead_after, self.floor = task, dead_after, floor
        self.promise = promise if promise is not None else GroundingPromise()
        self.start = time.perf_counter() if start is None else start
        self.masks, self.bits = touch_masks(task)   # per operator: the movable objects it handles
        keys = [(op.name, objects_of(op.args)) for op in task.operators]
        self._op_steps = [tuple((keys[b], self.masks[b]) for b in (op.steps or (i,)))
                          for i, op in enumerate(task.operators)]
        self.flagged = 0                            # bits of the objects some dead step is about
        self.dry: Counter = Counter()
        self.feasible: Set[StepKey] = set()
        self.dead: Dict[StepKey, float] = {}        # -> seconds from the start when found dead
        self.deaths = 0                             # steps found dead so far (grows only)
        self._totals: Dict[Context, List[int]] = defaultdict(lambda: [0, 0])            # [successes, failures]
        self._by_owner: Dict[Tuple[Context, int], List[int]] = defaultdict(lambda: [0, 0])
        self._anywhere: Dict[Asked, List[int]] = defaultdict(lambda: [0, 0])            # per step, dry visits too
        self._detours: Dict[Tuple[int, ...], Tuple[int, int]] = {}   # plan -> (flagged, detour operators)

    # -- what refinement reports ------------------------------------------------------
    def simulated(self, context: Context, owner: int, ok: bool) -> None:
        """Skeleton number `owner` tried the step of `context`: it simulated as the skeleton expects,
        or not (or its samplers ran dry)."""
        self._totals[context][0 if ok else 1] += 1
        self._by_owner[(context, owner)][0 if ok else 1] += 1
        self._anywhere[context[0]][0 if ok else 1] += 1

    def ran_dry(self, key: Optional[StepKey], context: Optional[Context] = None, owner: int = 0) -> bool:
        """A visit of the step of `context` in skeleton number `owner` found no feasible value (a
        failure there); `key`: the step's pristine key (None: not pristine). True if that
        made the pristine step dead."""
        if context is not None:
            self.simulated(context, owner, False)   # the steps before were the same: the same question
        if key is None or key in self.feasible or key in self.dead:
            return False
        self.dry[key] += 1
        if self.dry[key] < self.dead_after:
            return False
        self.dead[key] = round(time.perf_counter() - self.start, 3)
        self.deaths += 1
        for name in key[1]:
            if name in self.bits:
                self.flagged |= 1 << self.bits[name]
        return True

    def found(self, key: Optional[StepKey]) -> None:
        """Pristine step `key` had a feasible value (it simulated without error): never dead."""
        if key is not None:
            self.feasible.add(key)
            self.dead.pop(key, None)

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

    def is_dead(self, name: str, args: Sequence[str]) -> bool:
        """Whether the step `name args`, met as the scene began, is dead."""
        return (name, objects_of(args)) in self.dead

    def movable(self, args: Sequence[str]) -> List[str]:
        """The objects among `args` that steps may move (not fixed, not placeholders)."""
        return [a for a in args if a in self.bits]

    def labels(self) -> Dict[str, float]:
        """Dead steps, as '(name objects...)', and when each was found dead (s)."""
        return {f"({name} {' '.join(objects)})": t for (name, objects), t in self.dead.items()}

    # -- the estimate -----------------------------------------------------------------
    def counts(self, context: Context, owner: int = 0) -> Tuple[int, int]:
        """(successes, failures) at `context` in skeletons other than number `owner` (0: all)."""
        total = self._totals.get(context)
        if total is None:
            return 0, 0
        own = self._by_owner.get((context, owner), (0, 0))
        return total[0] - own[0], total[1] - own[1]

    def detours(self, plan: Sequence[int]) -> int:
        """The plan's operators in detours no dead step explains (skeleton.detour_steps)."""
        key = tuple(plan)
        known = self._detours.get(key)
        if known is None or known[0] != self.flagged:
            known = self._detours[key] = (self.flagged, detour_steps(self.task, plan, self.masks, self.flagged))
        return known[1]

    def lift(self, context: Context, owner: int = 0) -> float:
        """How much more likely the step of `context` is to work there, in the other
        skeletons' experience, than anywhere (module docstring); 1 when nothing is known."""
        anywhere = self._anywhere.get(context[0])
        if anywhere is None:
            return 1.0
        prior = (anywhere[0] + 1) / (anywhere[0] + anywhere[1] + 2)
        successes, failures = self.counts(context, owner)
        lift = (successes + 2 * prior) / (successes + failures + 2) / prior
        return lift if lift < 1.0 or context[0][:2] in self.dead else 1.0

    def log_terms(self, skeleton: Skeleton, owner: int = 0) -> Dict[str, float]:
        """The estimate's factors, as natural logs: outcomes elsewhere, detours, learned
        groundings (`owner`: the skeleton's number once it works, whose own outcomes are left
        out; 0: a skeleton not created yet, weighed by everything seen)."""
        outcomes = 0.0
        if self._anywhere:
            for context in set(skeleton.contexts):   # a step repeated in the same context is one question
                outcomes += math.log(self.lift(context, owner))
        groundings = sum(self.promise.gap(g, promised) for g, promised in set(skeleton.groundings()))
        return {"outcomes": outcomes, "detours": -math.log(2.0) * self.detours(skeleton.plan),
                "groundings": min(0.0, groundings)}

    def estimate(self, skeleton: Skeleton, owner: int = 0) -> float:
        """The skeleton's chance of being refined, relative to one nothing is known about:
        the product of `log_terms`, at least FLOOR."""
        return max(self.floor, math.exp(sum(self.log_terms(skeleton, owner).values())))
