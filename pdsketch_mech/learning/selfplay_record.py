"""What self-play stores about one drawn value: the value in numbers, its context, its parents.

A `SampleLog` is attached to a `StepSampler` as an observer (planner/bindings.py): every
value a stream's sampler yields is logged with the mechanism step it was drawn for, the
mechanism's objects' poses at that moment, and which earlier logged values were its parents.
Labels come at the end of the episode: 1 for the values the successful plan used (by
identity: the plan holds the very objects the samplers yielded), 0 for all others.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from ..samplers.interface import SampleRequest
from ..samplers.types import Contact, Grasp, Placement, Trajectory
from ..world.world import World

VALUE_WIDTH = 16      # columns of the `value` array (NaN-padded; `value_dim` says how many are used)
MAX_PARENTS = 12      # columns of the `parents` array (-1-padded)

# The numeric form of each kind of value, column by column (README "Self-play" repeats it).
VALUE_LAYOUT: Dict[str, Tuple[str, ...]] = {
    "grasp": ("x", "y", "z", "qx", "qy", "qz", "qw", "width"),  # gripper pose in the object's frame
    "contact": ("px", "py", "pz", "pqx", "pqy", "pqz", "pqw",  # pusher pose, world frame
                "cx", "cy", "cz", "nx", "ny", "nz", "dx", "dy", "dz"),  # point, normal, direction
    "placement": ("x", "y", "z", "qx", "qy", "qz", "qw"),  # the object's world pose
    "trajectory": ("q0", "q1", "q2", "q3", "q4", "q5", "q6",  # joints at the end of the final segment
                   "x", "y", "z", "qx", "qy", "qz", "qw",  # the gripper (TCP) pose there, world frame
                   "push"),  # push distance (NaN when not a push)
}


def pose_array(pose) -> List[float]:
    (x, y, z), (qx, qy, qz, qw) = pose
    return [x, y, z, qx, qy, qz, qw]


def encode_value(world: World, value: object) -> Tuple[str, np.ndarray]:
    """(kind, numbers) for a sampler's value; the layout is VALUE_LAYOUT[kind]."""
    if isinstance(value, Grasp):
        return "grasp", np.array(pose_array(value.in_object) + [value.width])
    if isinstance(value, Contact):
        return "contact", np.array(pose_array(value.pusher_pose) + list(value.point) + list(value.normal)
                                   + list(value.direction))
    if isinstance(value, Placement):
        return "placement", np.array(pose_array(value.pose))
    if isinstance(value, Trajectory):
        # The end of the final segment is where the trajectory acts (the grasp, the placement,
        # the push's end); the retreat after it carries no choice.
        ends = [part for part in (value.final, value.approach) if len(part)]
        q = np.asarray(ends[0][-1], dtype=float) if ends else np.full(7, np.nan)
        tcp = pose_array(world.kinematics.fk(q)) if ends else [np.nan] * 7
        push = np.nan if value.push_distance is None else float(value.push_distance)
        return "trajectory", np.concatenate([q, tcp, [push]])
    raise TypeError(f"self-play cannot record a value of type {type(value).__name__}")


@dataclass
class Sample:
    stream: str
    kind: str
    step: int                    # the mechanism step's index
    operator: str
    param: str                   # the mechanism's variable (e.g. "?g1")
    param_index: int             # its position among the mechanism's parameters
    value: np.ndarray
    poses: np.ndarray            # (objects, 7): the mechanism's objects where they were
    parents: List[int]           # logged samples this one was drawn given, in mechanism order
    label: int = 0


@dataclass
class SampleLog:
    """The observer: logs every drawn value of one episode (one world, one grounding)."""

    world: World
    objects: Sequence[str]                       # the mechanism's object arguments, in order
    step_variables: Sequence[Sequence[str]]      # per step: the mechanism call's argument terms
    parameters: Sequence[str]                    # the mechanism's parameter names, in order
    placeholders: Mapping[str, object]           # placeholder name -> Placeholder (its stream)
    samples: List[Sample] = field(default_factory=list)
    values: List[object] = field(default_factory=list)  # the logged objects themselves (identity)
    _index: Dict[int, int] = field(default_factory=dict)  # id(value) -> sample index

    def __call__(self, request: SampleRequest, value: object) -> None:
        step = request.step
        param = self._variable(request, step.index)
        kind, numbers = encode_value(self.world, value)
        poses = np.array([pose_array(self.world.pose(o)) for o in self.objects])
        parents = sorted((self._index[id(v)] for v in request.parents.values() if id(v) in self._index),
                         key=lambda k: (self.samples[k].param_index, k))
        self._index[id(value)] = len(self.samples)
        self.values.append(value)  # kept alive so that ids stay unique for the episode
        self.samples.append(Sample(request.stream, kind, step.index, step.operator, param,
                                   self.parameters.index(param) if param in self.parameters else -1,
                                   numbers, poses, parents))

    def _variable(self, request: SampleRequest, index: int) -> str:
        """The mechanism variable the drawn placeholder stands for: the step's placeholder
        argument created by this stream (and not drawn yet), mapped through the call."""
        terms = self.step_variables[index] if index < len(self.step_variables) else ()
        for position, arg in enumerate(request.step.args):
            holder = self.placeholders.get(arg)
            if holder is not None and holder.stream == request.stream and arg not in request.parents:
                return terms[position] if position < len(terms) else arg
        return request.stream

    def label(self, plan_values: Optional[Sequence[Mapping[str, object]]]) -> int:
        """Label the samples the plan used 1 (by identity), the rest 0; how many are 1."""
        used = {id(v) for values in plan_values or () for v in values.values()}
        for sample, value in zip(self.samples, self.values):
            sample.label = int(id(value) in used)
        return sum(s.label for s in self.samples)
