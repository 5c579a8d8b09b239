"""Task distributions, declared: which objects, which assets per split, where they go.

A task (`TaskSpec`) is a handful of `ObjectSpec`s — furniture and objects, each with its
asset choices for the train and held-out splits, a canonical pose, how much it is perturbed
(the paper: +-5 cm and +-15 degrees about the canonical pose), a scale range, physical
overrides — plus optional distractors and the goal. One generic generator (`generate.py`)
turns a spec, a split and a seed into an ordinary problem file.

Conventions: positions in metres and yaws in degrees, in the world unless the object names
a `frame` (another object whose sampled pose they are relative to: the plate of the Lever
task moves with its ledge, the Poking target with its tunnel). Objects rest on their `on`
support: the resting height comes from the asset's bounding box in `assets/manifest.json`,
or, for a tilted object (a box on its end), from its collision vertices turned by the tilt.
A turn is always about the vertical: a tilted object keeps its tilt and spins about z.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

Range = Tuple[float, float]

# What each split is for: train feeds self-play, dev every tuning run, test the reported
# tables only. A built-in task's test assets are shapes that neither train nor dev contains
# (variants made for it, `world/shapes.py`), so a reported table measures new shapes, not
# only new poses; dev keeps held-out shapes of its own for tuning. Dev and test never share
# an instance either: their seeds draw from different random streams (generate.py).
SPLITS = ("train", "dev", "test")


@dataclass(frozen=True)
class Assets:
    """Asset choices (`"category/variant"`): `train` for self-play, `dev` (held out from
    train) for tuning, `test_only` (held out from both) for the test split; without
    `test_only`, test draws from `dev` too. The canonical instance uses `train[0]`."""

    train: Tuple[str, ...]
    dev: Tuple[str, ...]
    test_only: Tuple[str, ...] = ()

    def of(self, split: str) -> Tuple[str, ...]:
        if split not in SPLITS:
            raise ValueError(f"unknown split {split!r}: expected one of {', '.join(SPLITS)}")
        if split == "train":
            return self.train
        return self.test_only or self.dev if split == "test" else self.dev

    @property
    def held_out(self) -> Tuple[str, ...]:
        """Every asset train never shows: dev's, then test's own."""
        return self.dev + tuple(a for a in self.test_only if a not in self.dev)

    @property
    def canonical(self) -> str:
        return self.train[0]


@dataclass(frozen=True)
class Align:
    """Place the object so that its footprint's edge on `side` ("+x", "-x", "+y", "-y", in
    its frame) lies `fraction` of its extent along that axis beyond the line `at`: with
    fraction 0.38 and at = the table edge, 38 % of the object overhangs the table. The
    aligned coordinate gets `noise` (metres, +-) instead of the object's own noise."""

    side: str
    at: float
    fraction: float = 0.0
    noise: float = 0.005


@dataclass(frozen=True)
class ObjectSpec:
    name: str
    assets: Assets
    xy: Tuple[float, float] = (0.0, 0.0)          # canonical position (in `frame` if given)
    yaw: float = 0.0                               # canonical yaw, degrees
    tilt: Tuple[float, float] = (0.0, 0.0)         # roll and pitch, degrees: about its own x, then y, before the yaw
    on: Optional[str] = "table"                    # what it rests on (None: placed at height `z`)
    z: float = 0.0                                 # the height of an object resting on nothing (a fixed shelf)
    frame: Optional[str] = None                    # xy/yaw relative to this object's sampled pose
    surface: Optional[float] = None                # the support's top in its own frame (default: its bbox top)
    fixed: bool = False
    noise_xy: Tuple[float, float] = (0.05, 0.05)  # +- metres along x and y
    noise_yaw: float = 15.0                        # +- degrees
    scale: Range = (1.0, 1.0)                      # uniform scale range of sampled instances
    mass: Optional[float] = None
    friction: Optional[float] = None
    align: Optional[Align] = None
    yaw_by_category: Tuple[Tuple[str, float], ...] = ()  # canonical yaw overrides per asset category
    match: Optional[str] = None                    # use the same asset index as this object (paired assets)
    slides: bool = False                           # meant to move when the scene settles
    role: str = ""                                 # what it is for, for the file's header

    def canonical_yaw(self, asset: str) -> float:
        category = asset.split("/")[0]
        return dict(self.yaw_by_category).get(category, self.yaw)


@dataclass(frozen=True)
class Distractors:
    """`count` (inclusive range) extra objects drawn from `pool`, anywhere in `region`
    ((x0, x1), (y0, y1)) on the table, not overlapping anything; named d0, d1, ..."""

    pool: Tuple[str, ...]
    count: Tuple[int, int]
    region: Tuple[Range, Range]


@dataclass(frozen=True)
class TaskSpec:
    name: str
    title: str                                     # the paper's name of the mechanism
    description: str                               # one sentence: the scene and what the demo does
    objects: Tuple[ObjectSpec, ...]
    goal: str                                      # PDDL goal over the objects' names
    distractors: Optional[Distractors] = None
    overlaps_ok: Tuple[Tuple[str, str], ...] = ()  # pairs whose footprints may overlap (a block in a tunnel)
    demo: str = ""                                 # what the scripted demonstration does
    source: str = ""                               # the distribution file it was read from (task_file.py), if any

    def object(self, name: str) -> ObjectSpec:
        return next(o for o in self.objects if o.name == name)
