"""Skeleton prefixes that got past a dead step: evidence from the scene, shared by every
skeleton that begins with them.

A step found dead where the scene began (pristine.py: the grasp of a box beyond reach) is what
holds every skeleton back. When one skeleton's earlier steps make it feasible (a hook pulls
the box within reach, and the grasp simulates), its prefix up to that step has done the hard
part, and every skeleton that begins with the same steps starts from the same scene, so can
do it too. Each such prefix multiplies the share of work of the skeletons that begin with it
by UNBLOCK_GAIN (schedule.py divides a skeleton's score by its weight), while their ranks
still reflect only how long they are.

The evidence is the prefix's, not the skeleton's: in Hook-then-Place-on-Slope the skeleton
that hooks the box and puts it straight on the slope (where it slides off) comes before the
composition with a blocker; weighting only the skeleton that first got past the grasp gave it
the work, sharing the weight between all skeletons that begin with the hook lets the one
with the blocker have its turn. Figures: results/HISTORY.md.
"""
from __future__ import annotations

from typing import Iterable, Sequence, Set, Tuple

from .pristine import StepKey, step_key
from .refine import Step

UNBLOCK_GAIN = 8.0   # share of work gained per prefix a skeleton begins with that got past a dead step

Prefix = Tuple[StepKey, ...]


def prefix(steps: Sequence[Step], length: int) -> Prefix:
    """The first `length` steps, as skeletons that begin alike share them."""
    return tuple(step_key(step) for step in steps[:length])


class UnblockedPrefixes:
    """The prefixes, over all of a plan's skeletons, that simulated a step found dead as the
    scene began; and the weight they give a skeleton."""

    def __init__(self, gain: float = UNBLOCK_GAIN):
        self.gain = gain
        self.prefixes: Set[Prefix] = set()

    def note(self, steps: Sequence[Step], indices: Iterable[int]) -> None:
        """Steps `indices` of the skeleton `steps` got past a dead step. Only the step's first
        occurrence in the skeleton counts: grasping the box again once it has been put down
        within reach is no new evidence."""
        keys = prefix(steps, len(steps))
        for i in indices:
            if keys[i] not in keys[:i]:
                self.prefixes.add(keys[:i + 1])

    def count(self, steps: Sequence[Step]) -> int:
        """How many of the prefixes the skeleton `steps` begins with."""
        # The planner asks about every active skeleton each turn: its keys once, then slices.
        keys = prefix(steps, len(steps)) if self.prefixes else ()
        return sum(keys[:len(p)] == p for p in self.prefixes)

    def weight(self, steps: Sequence[Step]) -> float:
        """UNBLOCK_GAIN per prefix the skeleton begins with (1: none)."""
        return self.gain ** self.count(steps) if self.prefixes else 1.0
