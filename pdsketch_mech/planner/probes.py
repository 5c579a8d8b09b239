"""Probes: what the learned samplers think of a skeleton's mechanism grounding before it works.

The evidence weighs a skeleton by how its mechanism groundings' classifier scores compare
with their rivals' (promise.py), but a grounding is scored only once its skeleton samples:
the first skeleton created with a mechanism would get work before any rival was looked at.
So each upcoming skeleton that begins with a mechanism's first step, where that grounding
has a rival (another grounding of the mechanism promising the same facts), is probed: one
batch of the step's proposals scored in the scene as it begins, none verified or simulated.
A grounding without rivals is not probed: a score compared with nothing changes no estimate.
"""
from __future__ import annotations

import zlib
from typing import TYPE_CHECKING, Sequence, Set, Tuple

import numpy as np

from .skeleton import Skeleton

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

    def probe(self, window: Sequence[Skeleton]) -> None:
        """Probe the skeletons of `window` (registered with the promise: supply's upcoming
        ones) whose first step begins a mechanism grounding that has a rival."""
        promise = self.sampler.promise
        for skeleton in window:
            first = skeleton.steps[0] if skeleton.steps else None
            if first is None or first.mechanism is None or first.index or tuple(skeleton.plan) in self.probed:
                continue
            grounding = (first.mechanism, tuple(first.mechanism_args))
            promised = next((c for g, c in skeleton.groundings() if g == grounding), None)
            if len(promise.rivals(grounding[0], promised)) < 2:
                continue
            self.probed.add(tuple(skeleton.plan))
            self.world.restore(self.initial)
            rng = np.random.default_rng([self.seed, zlib.crc32(skeleton.label(self.task).encode()), PROBE_STREAM])
            self.count += self.sampler.probe(self.world, first.context(), rng)
