"""The sampler interface: what a stream's sampler is told, and the propose/verify split.

A domain binds each stream to a sampler by name (`:sampler "grasp"`); `registry.py` maps the
names to objects of the classes below. A sampler draws values for one stream of one step of
a skeleton, in the simulated state the plan has reached, and is told where it stands: the
step's operator and arguments, the mechanism the step belongs to and the step's index in it,
the objects' current poses, and the values earlier steps of that mechanism (its parent
parameters) and this step's earlier streams drew.

Drawing is split in two. `propose` is cheap and geometric (shapes, poses, ray casts, static
collision queries: no IK, no motion planning, no simulation) and may yield many candidates;
`verify` does the expensive part and returns the value, or None. The generic `draw` verifies
in proposal order; a learned sampler proposes a batch, scores it, and verifies the best first.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, Generic, Iterator, Mapping, Optional, Tuple, TypeVar

import numpy as np

from ..world.values import Pose
from .budget import SamplerBudget

if TYPE_CHECKING:
    from ..world.world import World

Candidate = TypeVar("Candidate")


@dataclass(frozen=True)
class StepContext:
    """The step of a skeleton a value is drawn for."""

    operator: str                       # the basis operator, e.g. "move-cont"
    args: Tuple[str, ...]               # its ground arguments (objects and placeholders)
    mechanism: Optional[str] = None     # the mechanism the step belongs to (None: a basis step)
    mechanism_args: Tuple[str, ...] = ()  # the mechanism's object arguments
    index: int = 0                      # the step's position in its mechanism (0 for basis steps)
    roles: Tuple[Tuple[str, str], ...] = ()  # the mechanism's placeholders -> its variables ("#grasp4", "?g1")
    # Nothing earlier in the skeleton touched the step's objects: they lie where the scene
    # began (statistics only, so not part of what the step is).
    at_start: bool = field(default=False, compare=False)

    def role(self, placeholder: str) -> Optional[str]:
        """The mechanism variable `placeholder` stands for (None: a basis step's, or unknown)."""
        return dict(self.roles).get(placeholder)


@dataclass(frozen=True)
class SampleRequest:
    """One stream to sample at one step: its inputs and everything known about the step."""

    stream: str                                      # the stream's name in the domain
    inputs: Tuple[object, ...]                       # the stream's input values, in declared order
    input_names: Tuple[str, ...]                     # ... and their variable names (?x, ?g, ...)
    step: StepContext = field(default_factory=lambda: StepContext("", ()))
    poses: Mapping[str, Pose] = field(default_factory=dict)     # the step's objects, where they are now
    parents: Mapping[str, object] = field(default_factory=dict)  # placeholder -> value drawn earlier
    deadline: float = float("inf")                   # time.perf_counter(): nothing is verified after it
    # Told of every proposal verified, with its value or None (self-play logs rejected
    # proposals too: a learned sampler ranks proposals, most of which never become values).
    on_verified: Optional[Callable[[object, Optional[object]], None]] = field(default=None, compare=False)

    def verified(self, candidate: object, value: Optional[object]) -> None:
        """Report that `candidate` was verified, giving `value` (None: rejected)."""
        if self.on_verified is not None:
            self.on_verified(candidate, value)

    def input(self, name: str) -> object:
        """The value of the stream input `name` (e.g. "?x")."""
        return self.inputs[self.input_names.index(name)]

    def values(self) -> Tuple[object, ...]:
        """The inputs that are values (grasps, contacts, ...) rather than object names."""
        return tuple(v for v in self.inputs if not isinstance(v, str))

    def objects(self) -> Tuple[str, ...]:
        """The inputs that are object names."""
        return tuple(v for v in self.inputs if isinstance(v, str))


class Sampler(Generic[Candidate]):
    """A generic sampler: cheap proposals, expensive verification.

    `sampler_budget` holds every search budget the sampler reads (budget.py); `budget` is
    how many proposals one visit of a step verifies at most, the field of it that is this
    sampler's (`visit_budget`)."""

    # Class-level defaults, for subclasses whose __init__ does not call this one's.
    sampler_budget: SamplerBudget = SamplerBudget()
    budget: int = SamplerBudget().proposals
    examined: int = 0   # proposals verified so far (statistics: samples drawn from this sampler)

    def __init__(self, budget: SamplerBudget = SamplerBudget()):
        self.sampler_budget = budget
        self.budget = self.visit_budget(budget)

    def visit_budget(self, budget: SamplerBudget) -> int:
        """Proposals one visit verifies at most, read from `budget` (`proposals` unless a
        sampler has a field of its own)."""
        return budget.proposals

    def propose(self, world: "World", request: SampleRequest, rng: np.random.Generator,
                budget: int) -> Iterator[Candidate]:
        """Candidates from geometry alone; `budget` is about how many the caller will take
        (a proposer that filters its draws bounds its own work by it, so that a shape with
        no feasible candidates ends the generator)."""
        raise NotImplementedError

    def verify(self, world: "World", request: SampleRequest, candidate: Candidate,
               rng: np.random.Generator) -> Optional[object]:
        """The value for `candidate` if it is feasible (IK, collisions, motion), else None.
        The world is left as found."""
        raise NotImplementedError

    def draw(self, world: "World", request: SampleRequest, rng: np.random.Generator,
             budget: Optional[int] = None) -> Iterator[object]:
        """Verified values, at most `budget` (default `self.budget`) proposals examined."""
        limit = self.budget if budget is None else budget
        for examined, candidate in enumerate(self.propose(world, request, rng, limit)):
            if examined >= limit or time.perf_counter() > request.deadline:
                return
            self.examined += 1
            value = self.verify(world, request, candidate, rng)
            request.verified(candidate, value)
            if value is not None:
                yield value
