"""The generic samplers by the names domains bind streams to (`:sampler "grasp"`).

The binding is declarative: a stream names its sampler in the domain file, and the sampler
reads the stream's inputs by position (objects first, then values, as `SampleRequest`
sorts them), never the operator or predicate names of a particular domain. Each factory
takes the plan's `SamplerBudget` (budget.py; the default when called without one).
"""
from __future__ import annotations

from typing import Callable, Dict

from .budget import SamplerBudget
from .contact import ContactSampler
from .grasp import GraspSampler
from .interface import Sampler
from .placement import PlacementSampler
from .trajectory import FreeMotionSampler, GraspMotionSampler, PlaceMotionSampler, PushMotionSampler

# name -> a factory of the sampler (its comment: the stream inputs it reads)
GENERIC_SAMPLERS: Dict[str, Callable[[SamplerBudget], Sampler]] = {
    "grasp": GraspSampler,                          # (?x): a grasp of object ?x
    "placement": PlacementSampler,                  # (?x ?s): the held ?x resting on ?s
    "contact": ContactSampler,                      # (... ?y ?s): what the hand holds touching ?y on ?s
    "grasp-motion": GraspMotionSampler,             # (?x ?g): the arm to grasp ?g of ?x
    "place-motion": PlaceMotionSampler,             # (... ?p): the arm to placement ?p
    "push-motion": PushMotionSampler,               # (?c): from contact ?c, a push
    # (): the empty hand elsewhere; (?x): the held ?x elsewhere
    "free-motion": lambda budget=SamplerBudget(): FreeMotionSampler("free", budget),
    "held-motion": lambda budget=SamplerBudget(): FreeMotionSampler("held", budget),
}
