"""Probes: what the learned samplers think of a skeleton's mechanism grounding before it works.

The planner weighs skeletons by how their mechanism groundings score against their rivals
(promise.py), but a grounding is scored only once its skeleton samples, so the first skeleton
created with a mechanism got work before any rival was looked at. Each upcoming skeleton that
begins with a mechanism's first step, where that grounding has a rival (another grounding of
the mechanism promising the same facts, upcoming or scored before), is therefore probed: one
batch of the step's proposals scored in the scene as it begins, none verified or simulated.
A grounding without rivals is not probed: a score compared with nothing changes no weight.
A first variable's scores say little about some groundings (mass is in no classifier's
context: a light fork can outscore a heavy dipper as a Lever's weight). Figures:
results/HISTORY.md.
"""
from __future__ import annotations

import zlib
from typing import TYPE_CHECKING, Dict, Hashable, List, Sequence, Set, Tuple

import numpy as np

from .refine import Step, skeleton_groundings

if TYPE_CHECKING:
    from ..symbolic.task import StripsTask
    from ..world.snapshot import Snapshot
    from ..world.world import World
    from .bindings import StepSampler

PROBE_STREAM = 1   # a probe's random stream, apart from its skeleton's (seeded by the same labels)


class GroundingProbes:
    """Probes upcoming skeletons' first mechanism steps, each skeleton at most once."""

    def __init__(self, task: "StripsTask", sampler: "StepSampler", world: "World", initial: "Snapshot", seed: int):
        self.task, self.sampler, self.world, self.initial, self.seed = task, sampler, world, initial, seed
        self.probed: Set[Tuple[int, ...]] = set()
        self.count = 0   # batches scored (statistics)

    def probe(self, window: Sequence[Tuple[List[int], List[Step], object]]) -> None:
        """Probe the skeletons of `window` (the supply's upcoming ones) whose first step begins
        a mechanism grounding that has a rival."""
        candidates = []
        for plan, steps, _ in window:
            first = steps[0] if steps else None
            if first is None or first.mechanism is None or first.index or tuple(plan) in self.probed:
                continue
            grounding = (first.mechanism, tuple(first.mechanism_args))
            promised = next((c for g, c in skeleton_groundings(steps) if g == grounding), None)
            candidates.append((plan, first, grounding, promised))
        groundings: Dict[Tuple[str, Hashable], Set[Tuple[str, Tuple[str, ...]]]] = {}
        for _, _, grounding, promised in candidates:
            key = (grounding[0], promised)
            if key not in groundings:
                groundings[key] = set(self.sampler.promise.rivals(grounding[0], promised))
            groundings[key].add(grounding)
        for plan, first, grounding, promised in candidates:
            if len(groundings[(grounding[0], promised)]) < 2:
                continue
            self.probed.add(tuple(plan))
            self.world.restore(self.initial)
            label = " ".join(self.task.operators[o].label for o in plan)
            rng = np.random.default_rng([self.seed, zlib.crc32(label.encode()), PROBE_STREAM])
            self.count += self.sampler.probe(self.world, first.context(), rng)
