"""What self-play stores about one drawn value: the value in numbers, its context, its parents.

A `SampleLog` is attached to a `StepSampler` as an observer (planner/bindings.py): every
value a stream's sampler yields is logged with the mechanism step it was drawn for, the
mechanism's objects' poses at that moment, and which earlier logged values were its parents.
It also watches verification: a proposal that fails it (an unreachable grasp, a contact
the arm cannot take) is logged as a row of its own with `verified` 0, and a value keeps the
numbers of the proposal it came from (`proposal`), since a learned sampler scores proposals
before it verifies them. Labels come at the end of the episode: 1 for the values the
successful plan used (by identity: the plan holds the very objects the samplers yielded),
0 for all others.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Mapping, Optional, Sequence

import numpy as np

from ..samplers.interface import SampleRequest
from ..samplers.learned.encoding import encode_value, pose_array, proposal_row
from ..world.world import World

MAX_PARENTS = 12      # columns of the `parents` array (-1-padded)


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
    proposal: np.ndarray         # the proposal it came from, in the value's layout (= value if unknown)
    verified: int = 1            # 0: a proposal that failed verification (value = proposal)
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
    _proposals: Dict[int, tuple] = field(default_factory=dict)  # id(value) -> (value, its proposal's numbers)

    def __call__(self, request: SampleRequest, value: object) -> None:
        kind, numbers = encode_value(self.world, value)
        proposal = self._proposals.pop(id(value), (None, numbers))[1]
        self._index[id(value)] = len(self.samples)
        self.values.append(value)  # kept alive so that ids stay unique for the episode
        self._append(request, kind, numbers, proposal, verified=1)

    def verified(self, request: SampleRequest, candidate: object, value: Optional[object]) -> None:
        """A proposal was verified (value None: rejected). A proposal that is one of the
        stream's inputs (the grasp a grasp motion is planned for) is no choice of its own."""
        if any(candidate is v for v in request.values()):
            return
        row = proposal_row(self.world, candidate)
        if row is None:
            return
        if value is not None:
            self._proposals[id(value)] = (value, row[1])
            return
        self.values.append(None)
        self._append(request, row[0], row[1], row[1], verified=0)

    def _append(self, request: SampleRequest, kind: str, numbers: np.ndarray, proposal: np.ndarray,
                verified: int) -> None:
        step = request.step
        param = self._variable(request, step.index)
        poses = np.array([pose_array(self.world.pose(o)) for o in self.objects])
        parents = sorted((self._index[id(v)] for v in request.parents.values() if id(v) in self._index),
                         key=lambda k: (self.samples[k].param_index, k))
        self.samples.append(Sample(request.stream, kind, step.index, step.operator, param,
                                   self.parameters.index(param) if param in self.parameters else -1,
                                   numbers, poses, parents, proposal, verified))

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
            sample.label = int(value is not None and id(value) in used)
        return sum(s.label for s in self.samples)
