"""Streams -> Python samplers (by their `:sampler` name).

A step such as `(grasp box table #grasp3 #traj4)` gets its placeholder values from the
streams that created them (`sample-grasp` for #grasp3, `plan-grasp-motion` for #traj4),
sampled in dependency order in the world as it is before the step.
"""
from __future__ import annotations

import time
from collections import Counter
from typing import Callable, Dict, Iterator, List, Mapping, Sequence

import numpy as np

from ..lang.nodes import Atom, Stream
from ..samplers.contact import sample_contacts
from ..samplers.grasp import sample_grasps
from ..samplers.placement import sample_placements
from ..samplers.trajectory import free_motion, grasp_motion, place_motion, push_motion
from ..symbolic.optimistic import Placeholder, is_placeholder
from ..world.world import World

# (world, stream, input values, generator, deadline as time.perf_counter()) -> values
Sampler = Callable[[World, Stream, List[object], np.random.Generator, float], Iterator[object]]


# Candidates a sampler examines per visit of a step: the adaptive planner revisits steps,
# so a modest budget that fails fast beats an exhaustive one.
ATTEMPTS = 120
GRASP_ATTEMPTS = 60  # grasp proposals already passed cheap geometric tests (samplers/grasp.py)


def _grasp(world: World, stream: Stream, inputs: List[object], rng, deadline: float) -> Iterator[object]:
    return sample_grasps(world, inputs[0], rng, max_attempts=GRASP_ATTEMPTS, deadline=deadline)


def _placement(world: World, stream: Stream, inputs: List[object], rng, deadline: float) -> Iterator[object]:
    return sample_placements(world, inputs[0], inputs[1], rng, max_attempts=ATTEMPTS, deadline=deadline)


def _contact(world: World, stream: Stream, inputs: List[object], rng, deadline: float) -> Iterator[object]:
    target, support = inputs[-2], inputs[-1]  # (?y ?s) or (?x ?y ?s): the pusher is what the hand holds
    return sample_contacts(world, target, support, rng, max_attempts=ATTEMPTS, deadline=deadline)


def _trajectory(world: World, stream: Stream, inputs: List[object], rng, deadline: float) -> Iterator[object]:
    """Dispatch on the kind of motion the stream certifies."""
    certified = {a.predicate for a in _atoms(stream.certified)}
    values = [v for v in inputs if not isinstance(v, str)]
    if "grasp-motion" in certified:
        motion = grasp_motion(world, inputs[0], values[0], rng)
    elif "place-motion" in certified:
        motion = place_motion(world, values[0], rng)
    elif "push-motion" in certified:
        motion = push_motion(world, values[0], rng)
    else:
        motion = free_motion(world, rng, "held" if world.attachment else "free")
    if motion is not None:
        yield motion


SAMPLERS: Dict[str, Sampler] = {"grasp": _grasp, "placement": _placement, "contact": _contact,
                                "trajectory": _trajectory, "push": _trajectory}


def _atoms(formula) -> List[Atom]:
    if isinstance(formula, Atom):
        return [formula]
    return [a for part in getattr(formula, "parts", ()) for a in _atoms(part)]


class StepSampler:
    """Joint samples of a step's placeholder arguments, drawn stream by stream."""

    def __init__(self, streams: Mapping[str, Stream], placeholders: Mapping[str, Placeholder], counts: Counter):
        self.streams, self.placeholders, self.counts = streams, placeholders, counts
        self.deadline = float("inf")  # (time.perf_counter()) no value is drawn after it
        unknown = sorted({s.sampler or s.name for s in streams.values()} - set(SAMPLERS))
        if unknown:
            raise ValueError(f"no Python sampler named {', '.join(unknown)}; known: {', '.join(sorted(SAMPLERS))}")

    def samples(self, world: World, args: Sequence[str], rng: np.random.Generator,
                per_value: int = 1) -> Iterator[Dict[str, object]]:
        """Assignments {placeholder: value} for the placeholders among `args`."""
        needed = sorted({a for a in args if is_placeholder(a)}, key=lambda a: (self.placeholders[a].level, a))
        yield from self._assign(world, needed, {}, rng, per_value, root=True)

    def _assign(self, world, needed: List[str], values: Dict[str, object], rng, per_value: int, root: bool):
        """Values for `needed` in order; a value that depends on earlier ones (a trajectory
        for a grasp) is drawn at most `per_value` times per combination of those."""
        if not needed:
            yield dict(values)
            return
        name, rest = needed[0], needed[1:]
        holder = self.placeholders[name]
        stream = self.streams[holder.stream]
        inputs = [values.get(v, v) for v in holder.inputs]
        key = stream.sampler or stream.name
        drawn = 0
        for value in SAMPLERS[key](world, stream, inputs, rng, self.deadline):
            if time.perf_counter() > self.deadline:
                break
            self.counts[key] += 1
            values[name] = value
            yield from self._assign(world, rest, values, rng, per_value, root=False)
            drawn += 1
            if not root and drawn >= per_value:
                break
        values.pop(name, None)
