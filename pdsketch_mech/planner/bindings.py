"""Streams -> samplers, and the joint values of a step's placeholders.

A step such as `(grasp box table #grasp3 #traj4)` gets its placeholder values from the
streams that created them (`sample-grasp` for #grasp3, `plan-grasp-motion` for #traj4),
sampled in dependency order in the world as it is before the step. Each stream's sampler is
the one its `:sampler` names (samplers/registry.py), told the step's context: the operator,
the mechanism and the step's index in it, the objects' poses and the parent values.
"""
from __future__ import annotations

import time
from collections import Counter
from typing import Callable, Dict, Iterator, List, Mapping, Optional

import numpy as np

from ..lang.nodes import Stream
from ..samplers.interface import Sampler, SampleRequest, StepContext
from ..samplers.registry import GENERIC_SAMPLERS
from ..symbolic.optimistic import Placeholder, is_placeholder
from ..world.world import World

# Told of every value a stream's sampler yields, with the request it answered (self-play
# records them); the world is in the state the value was drawn in.
SampleObserver = Callable[[SampleRequest, object], None]


class StepSampler:
    """Joint samples of a step's placeholder arguments, drawn stream by stream."""

    def __init__(self, streams: Mapping[str, Stream], placeholders: Mapping[str, Placeholder], counts: Counter):
        self.streams, self.placeholders, self.counts = streams, placeholders, counts
        self.deadline = float("inf")  # (time.perf_counter()) no value is drawn after it
        unknown = sorted({s.sampler or s.name for s in streams.values()} - set(GENERIC_SAMPLERS))
        if unknown:
            known = ", ".join(sorted(GENERIC_SAMPLERS))
            raise ValueError(f"no sampler named {', '.join(unknown)}; known: {known}")
        self.samplers: Dict[str, Sampler] = {s.name: GENERIC_SAMPLERS[s.sampler or s.name]() for s in streams.values()}
        self.observers: List[SampleObserver] = []

    def samples(self, world: World, step: StepContext, rng: np.random.Generator,
                parents: Optional[Mapping[str, object]] = None, per_value: int = 1) -> Iterator[Dict[str, object]]:
        """Assignments {placeholder: value} for the placeholders among the step's arguments;
        `parents` are values earlier steps of the step's mechanism drew."""
        needed = sorted({a for a in step.args if is_placeholder(a)}, key=lambda a: (self.placeholders[a].level, a))
        objects = [a for a in step.args if not is_placeholder(a) and a in world.bodies]
        poses = {name: world.pose(name) for name in objects}
        yield from self._assign(world, step, dict(parents or {}), poses, needed, {}, rng, per_value, root=True)

    def _assign(self, world, step: StepContext, parents: Dict[str, object], poses, needed: List[str],
                values: Dict[str, object], rng, per_value: int, root: bool):
        """Values for `needed` in order; a value that depends on earlier ones (a trajectory
        for a grasp) is drawn at most `per_value` times per combination of those."""
        if not needed:
            yield dict(values)
            return
        name, rest = needed[0], needed[1:]
        holder = self.placeholders[name]
        stream = self.streams[holder.stream]
        request = SampleRequest(stream.name, tuple(values.get(v, v) for v in holder.inputs),
                                tuple(q.name for q in stream.inputs), step, poses, {**parents, **values}, self.deadline)
        key = stream.sampler or stream.name
        drawn = 0
        for value in self.samplers[stream.name].draw(world, request, rng):
            if time.perf_counter() > self.deadline:
                break
            self.counts[key] += 1
            for observe in self.observers:
                observe(request, value)
            values[name] = value
            yield from self._assign(world, step, parents, poses, rest, values, rng, per_value, root=False)
            drawn += 1
            if not root and drawn >= per_value:
                break
        values.pop(name, None)
