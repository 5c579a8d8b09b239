"""Failures on untouched objects, learned once and shared between skeletons.

Symbolically, a box beyond the arm's reach is like any other box: every skeleton that grasps
it where it lies, or pushes it, or sets something on it, looks as good as the one that first
pulls it closer with a hook, and the FF-guided search yields thousands of them first (the
Hook-then-Place-on-Slope task: the composition that works was beyond rank 30 000). But a
step whose objects nothing earlier in its skeleton has touched (a *pristine* step) meets
those objects as the initial scene has them, whatever skeleton it is in. If such a step's
samplers keep running dry there (DEAD_AFTER visits without one feasible value, none ever
feasible), every skeleton that repeats it is deferred: kept aside, and refined only once the
others run out, so the planner stays complete. Other objects may have moved (an obstacle
cleared), which is why this defers rather than prunes.

Symbols cannot tell a step that moves an object from one that only touches it: a weight set
on a plate may tip it (the Lever mechanism) or leave it lying (a tool put down on the box out
of reach), so a dead step after such a step is not pristine and its skeleton is not deferred.
Refinement tells them apart in the scene (refine.py): a dead step met with its objects where
the scene began is not sampled again.
"""
from __future__ import annotations

import time
from collections import Counter
from typing import Dict, List, Optional, Sequence, Set, Tuple

from ..symbolic.optimistic import is_placeholder
from ..symbolic.task import StripsTask
from .refine import Step

DEAD_AFTER = 3      # dry visits of a pristine step, with no feasible value ever, before it is dead

StepKey = Tuple[str, Tuple[str, ...]]


def _objects(args: Sequence[str]) -> Tuple[str, ...]:
    return tuple(a for a in args if not is_placeholder(a))


def step_key(step: Step) -> StepKey:
    """The step as the same step in any skeleton: its operator and objects (placeholders name
    stream outputs, which differ between skeletons)."""
    return step.name, _objects(step.args)


def fixed_objects(task: StripsTask) -> Set[str]:
    """Objects the initial state calls (fixed X): never moved, so never 'touched'."""
    held = [fact for i, fact in enumerate(task.facts) if task.init >> i & 1] + list(task.static_facts)
    return {fact[1] for fact in held if fact[0] == "fixed"}


def touch_masks(task: StripsTask) -> Tuple[List[int], Dict[str, int]]:
    """Per operator, a bitmask of the movable objects it handles; and each object's bit."""
    fixed = fixed_objects(task)
    index: Dict[str, int] = {}
    masks = []
    for op in task.operators:
        mask = 0
        for name in _objects(op.args):
            if name not in fixed:
                mask |= 1 << index.setdefault(name, len(index))
        masks.append(mask)
    return masks, index


def pristine_keys(steps: Sequence[Step], fixed: Set[str]) -> List[Optional[StepKey]]:
    """For each step, (name, objects) if no earlier step touched any of its movable objects,
    else None."""
    touched: Set[str] = set()
    keys: List[Optional[StepKey]] = []
    for step in steps:
        objects = _objects(step.args)
        movable = {o for o in objects if o not in fixed}
        keys.append((step.name, objects) if not movable & touched else None)
        touched |= movable
    return keys


class PristineFailures:
    """Dry visits and feasible values of pristine steps, across all of a plan's skeletons."""

    def __init__(self, dead_after: int = DEAD_AFTER, start: Optional[float] = None):
        self.dead_after = dead_after
        self.bits: Dict[str, int] = {}    # object -> its bit in the symbolic search's masks
        self.masks: List[int] = []        # per operator: the bits of the objects it handles
        self.flagged = 0                  # bits of the objects some dead step is about
        self._steps: List[Tuple[Tuple[StepKey, int], ...]] = []  # per operator: (key, mask) per step
        self.start = time.perf_counter() if start is None else start
        self.dry: Counter = Counter()
        self.feasible: Set[StepKey] = set()
        self.dead: Dict[StepKey, float] = {}   # -> seconds from the start when it was found dead
        self.deaths = 0                         # steps found dead so far (grows only)

    def ran_dry(self, key: Optional[StepKey]) -> bool:
        """Note a visit of `key` that found no feasible value; True if that made it dead."""
        if key is None or key in self.feasible or key in self.dead:
            return False
        self.dry[key] += 1
        if self.dry[key] >= self.dead_after:
            self.dead[key] = round(time.perf_counter() - self.start, 3)
            self.deaths += 1
            for name in key[1]:
                if name in self.bits:
                    self.flagged |= 1 << self.bits[name]
            return True
        return False

    def found(self, key: Optional[StepKey]) -> None:
        """Note a feasible value of `key` (it simulated without error): never dead then."""
        if key is not None:
            self.feasible.add(key)
            self.dead.pop(key, None)

    def attach(self, task: StripsTask) -> List[int]:
        """Prepare to answer `blocks_operator` for `task`'s operators; returns touch_masks."""
        masks, self.bits = touch_masks(task)
        self.masks = masks
        keys = [(op.name, _objects(op.args)) for op in task.operators]
        self._steps = [tuple((keys[b], masks[b]) for b in (op.steps or (i,)))
                       for i, op in enumerate(task.operators)]
        return masks

    def blocks_operator(self, handled: int, op: int) -> bool:
        """Whether operator `op` (its steps, for a mechanism), after a path that handled the
        objects `handled`, has a dead pristine step."""
        if not self.dead:
            return False
        for key, mask in self._steps[op]:
            if not mask & handled and key in self.dead:
                return True
            handled |= mask
        return False

    def is_dead(self, name: str, args: Sequence[str]) -> bool:
        """Whether the step `name args`, met as the scene began, is dead."""
        return (name, _objects(args)) in self.dead

    def movable(self, args: Sequence[str]) -> List[str]:
        """The objects among `args` that steps may move (not fixed, not placeholders)."""
        return [a for a in args if a in self.bits]

    def blocks(self, keys: Sequence[Optional[StepKey]]) -> bool:
        """Whether a skeleton with these step keys repeats a dead pristine step."""
        return any(k in self.dead for k in keys if k is not None)

    def labels(self) -> Dict[str, float]:
        """Dead steps, as '(name objects...)', and when each was found dead (s)."""
        return {f"({name} {' '.join(objects)})": t for (name, objects), t in self.dead.items()}
