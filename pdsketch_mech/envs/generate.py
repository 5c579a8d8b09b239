"""The one generator: a `TaskSpec`, a split and a seed -> an instance -> a problem file.

`sample(task, split, seed)` draws every choice from one random generator in a fixed order,
so the same (task, split, seed) always gives the same instance and the same bytes
(`problem_text`). The train and dev splits seed it with `seed`, the test split with (seed,
TEST_STREAM): dev and test never share an instance (nor, where a task names test-only
assets, a shape: spec.py). Without a seed it gives the canonical instance: the first train
asset of every object at its canonical pose and scale (1 where its range allows), without distractors. With
`vary_assets=False` it keeps the canonical assets and perturbs only the poses (what the
scripted demonstrations are checked on).

Resting heights come from the assets' bounding boxes in `assets/manifest.json` (an object's
frame is at its centre of mass, so it rests at `top - scale * aabb.min.z`), a millimetre
above the support; a tilted object's box is its collision vertices' after the tilt. An
object on a movable support (a plate, a tray) is written without a height: the scene loader
rests it on what is under it, the plate's inner surface rather than its rim. Overlaps are checked on oriented footprints with their height ranges;
a sample with an overlap is redrawn. Nothing here imports PyBullet.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from ..world.asset_index import asset_info, collision_vertices
from .spec import ObjectSpec, TaskSpec

GAP = 0.001          # metres between an object's lowest point and its support's top
CLEARANCE = 0.01     # metres between the footprints of objects on the same level
MAX_TRIES = 200      # redraws of a whole instance before giving up
DISTRACTOR_TRIES = 60
TEST_STREAM = 2026   # keeps test instances apart from dev ones (which may have the same assets)


@dataclass(frozen=True)
class Placed:
    """One object of an instance, where the scene will put it."""

    name: str
    asset: str
    position: Tuple[float, float, float]
    yaw: float                       # degrees about z
    scale: float = 1.0
    fixed: bool = False
    on: Optional[str] = None
    mass: Optional[float] = None
    friction: Optional[float] = None
    slides: bool = False
    role: str = ""
    tilt: Tuple[float, float] = (0.0, 0.0)   # roll, pitch (degrees), before the yaw
    rests: bool = False              # its height is left to the scene loader, which rests it on its support

    def bbox(self) -> Tuple[np.ndarray, np.ndarray]:
        """Its bounding box in its yaw frame (tilted with it), scaled."""
        lo, hi = tilted_box(self.asset, self.tilt)
        return lo * self.scale, hi * self.scale

    def footprint(self) -> np.ndarray:
        """The bounding box's four corners on the table, world frame (4 x 2)."""
        lo, hi = self.bbox()
        return _corners(lo, hi, self.yaw) + np.array(self.position[:2])

    def heights(self) -> Tuple[float, float]:
        lo, hi = self.bbox()
        return self.position[2] + lo[2], self.position[2] + hi[2]


@dataclass(frozen=True)
class Instance:
    task: TaskSpec
    split: str
    seed: Optional[int]
    objects: Tuple[Placed, ...]
    vary_assets: bool = True

    @property
    def name(self) -> str:
        if self.seed is None:
            return f"{self.task.name}-canonical"
        return f"{self.task.name}-{self.split}-{self.seed}" + ("" if self.vary_assets else "-poses")

    def object(self, name: str) -> Placed:
        return next(o for o in self.objects if o.name == name)

    @property
    def held_out(self) -> bool:
        """Whether an object the task names (distractors aside) is of a category its train
        split never shows: what learned samplers must generalise to."""
        seen = {a.split("/")[0] for spec in self.task.objects for a in spec.assets.train}
        named = {spec.name for spec in self.task.objects}
        return any(o.asset.split("/")[0] not in seen for o in self.objects if o.name in named)

    def command(self) -> str:
        """The command line that regenerates this instance."""
        task = self.task.source or self.task.name
        if self.seed is None:
            return f"python -m pdsketch_mech.envs {task} --canonical"
        extra = "" if self.vary_assets else " --canonical-assets"
        return f"python -m pdsketch_mech.envs {task} --split {self.split} --seed {self.seed}{extra}"

    def init_facts(self) -> List[str]:
        """The contact graph the scene starts in: what rests on what, which bodies are fixed.
        (Furniture resting on the table is not a support fact: the contact graph leaves
        pairs of fixed bodies out.)"""
        facts = ["(handempty)"]
        facts += [f"(fixed {o.name})" for o in self.objects if o.fixed]
        facts += [f"(support {o.name} {o.on})" for o in self.objects if o.on and not o.fixed]
        return facts

    def problem_text(self) -> str:
        task = self.task
        lines = [f"; {task.title}: {task.description}",
                 f"; Generated by `{self.command()}`; do not edit.",
                 f"(define (problem {self.name})",
                 "  (:domain mech-basis)",
                 f"  (:objects {' '.join(o.name for o in self.objects)} - item)",
                 "  (:init",
                 *[f"    {fact}" for fact in self.init_facts()[:-1]],
                 f"    {self.init_facts()[-1]})",
                 f"  (:goal {task.goal})",
                 "  (:scene"]
        entries = [_scene_entry(o) for o in self.objects]
        lines += [f"    {entry}" for entry in entries[:-1]] + [f"    {entries[-1]})"]
        lines[-1] += ")"
        return "\n".join(lines) + "\n"


def _num(value: float, digits: int = 4) -> str:
    """Fixed precision, trailing zeros dropped, never '-0'."""
    text = f"{value:.{digits}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def _scene_entry(o: Placed) -> str:
    position = o.position[:2] if o.rests else o.position
    parts = [f'({o.name} :asset "{o.asset}"', ":position (" + " ".join(_num(v) for v in position) + ")"]
    if any(_num(a, 2) != "0" for a in o.tilt):
        parts.append(f":rpy-deg ({_num(o.tilt[0], 2)} {_num(o.tilt[1], 2)} {_num(o.yaw, 2)})")
    elif _num(o.yaw, 2) != "0":
        parts.append(f":rpy-deg (0 0 {_num(o.yaw, 2)})")
    if o.fixed:
        parts.append(":fixed")
    if _num(o.scale, 3) != "1":
        parts.append(f":scale {_num(o.scale, 3)}")
    if o.on:
        parts.append(f":on {o.on}")
    if o.mass is not None:
        parts.append(f":mass {_num(o.mass, 3)}")
    if o.friction is not None:
        parts.append(f":friction {_num(o.friction, 3)}")
    return " ".join(parts) + ")"


def tilted_box(asset: str, tilt: Tuple[float, float]) -> Tuple[np.ndarray, np.ndarray]:
    """The asset's bounding box (unscaled) after turning it by `tilt` (roll about x, then
    pitch about y, degrees): from the manifest upright, from its collision vertices tilted,
    so that a box on its end rests on its end."""
    if not any(tilt):
        info = asset_info(asset)
        return np.array(info["aabb"]["min"]), np.array(info["aabb"]["max"])
    roll, pitch = (math.radians(a) for a in tilt)
    cr, sr, cp, sp = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch)
    turn = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]]) @ np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr],
                                                                                   [0.0, sr, cr]])
    points = np.array(collision_vertices(asset)) @ turn.T
    return points.min(axis=0), points.max(axis=0)


def _rotate(xy: np.ndarray, yaw_deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    return xy @ np.array([[c, s], [-s, c]])


def _corners(lo: Sequence[float], hi: Sequence[float], yaw_deg: float) -> np.ndarray:
    local = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    return _rotate(local, yaw_deg)


def _separated(a: np.ndarray, b: np.ndarray, margin: float) -> bool:
    """Two convex polygons are apart by at least `margin` along some edge normal (SAT)."""
    for poly in (a, b):
        for i in range(len(poly)):
            edge = poly[(i + 1) % len(poly)] - poly[i]
            normal = np.array([-edge[1], edge[0]]) / (np.linalg.norm(edge) or 1.0)
            pa, pb = a @ normal, b @ normal
            if pa.max() + margin <= pb.min() or pb.max() + margin <= pa.min():
                return True
    return False


def overlapping(a: Placed, b: Placed, margin: float = CLEARANCE) -> bool:
    (a0, a1), (b0, b1) = a.heights(), b.heights()
    if a1 <= b0 or b1 <= a0:
        return False
    return not _separated(a.footprint(), b.footprint(), margin)


def _exempt(task: TaskSpec, a: Placed, b: Placed) -> bool:
    pair = {a.name, b.name}
    return (a.on == b.name or b.on == a.name or a.on is None or b.on is None
            or any(pair == set(p) for p in task.overlaps_ok))


def first_overlap(task: TaskSpec, objects: Sequence[Placed]) -> Optional[Tuple[str, str]]:
    for i, a in enumerate(objects):
        for b in objects[:i]:
            if not _exempt(task, a, b) and overlapping(a, b):
                return b.name, a.name
    return None


def _support_top(support: Placed, spec_surface: Optional[float]) -> float:
    if spec_surface is not None:
        return support.position[2] + spec_surface * support.scale
    return support.position[2] + support.bbox()[1][2]


def _place(spec: ObjectSpec, asset: str, scale: float, offsets: Sequence[float],
           placed: Dict[str, Placed]) -> Placed:
    """The object at its canonical pose perturbed by `offsets` (dx, dy, dyaw, dalign)."""
    dx, dy, dyaw, dalign = offsets
    yaw = spec.canonical_yaw(asset) + dyaw
    xy = np.array(spec.xy, dtype=float) + (dx, dy)
    lo, hi = (v * scale for v in tilted_box(asset, spec.tilt))
    if spec.align is not None:
        corners = _corners(lo, hi, yaw)
        axis = "xy".index(spec.align.side[1])
        extent = corners[:, axis].max() - corners[:, axis].min()
        if spec.align.side[0] == "+":
            xy[axis] = spec.align.at + spec.align.fraction * extent - corners[:, axis].max()
        else:
            xy[axis] = spec.align.at - spec.align.fraction * extent - corners[:, axis].min()
        xy[axis] += dalign
    if spec.frame is not None:
        frame = placed[spec.frame]
        xy = _rotate(xy[None, :], frame.yaw)[0] + np.array(frame.position[:2])
        yaw += frame.yaw
    if spec.on is None:
        z = spec.z   # on nothing: where the problem put it (a fixed shelf keeps its height)
    else:
        top = _support_top(placed[spec.on], spec.surface)
        z = top - lo[2] + (0.0 if spec.fixed else GAP)
    yaw = (yaw + 180.0) % 360.0 - 180.0
    # On a movable support (a plate, a tray, a bowl) its top is not its box's: the scene
    # loader rests the object on what is under it (the plate's inner surface, not its rim).
    rests = spec.on is not None and spec.surface is None and not placed[spec.on].fixed
    return Placed(spec.name, asset, (float(xy[0]), float(xy[1]), float(z)), float(yaw), float(scale), spec.fixed,
                  spec.on, spec.mass, spec.friction, spec.slides, spec.role, spec.tilt, rests)


def _choose(spec: ObjectSpec, split: str, rng: Optional[np.random.Generator], vary: bool,
            chosen: Dict[str, int]) -> Tuple[str, int]:
    choices = spec.assets.of(split) if vary else spec.assets.train
    draw = int(rng.integers(len(choices))) if rng is not None else 0
    if not vary:
        index = 0
    elif spec.match is not None:
        index = chosen[spec.match] % len(choices)
    else:
        index = draw
    return choices[index], index


def canonical_scale(spec: ObjectSpec) -> float:
    """The scale of the canonical instance: 1 where the range allows it, else the nearest
    end (a problem's `:scale 0.8` object is 0.8 in its own scene regenerated)."""
    return min(max(1.0, spec.scale[0]), spec.scale[1])


def instance_entropy(split: str, seed: int) -> Union[int, Tuple[int, int]]:
    """What seeds the generator of instance `seed` of `split` (module docstring)."""
    return (seed, TEST_STREAM) if split == "test" else seed


def sample(task: TaskSpec, split: str = "train", seed: Optional[int] = None, vary_assets: bool = True) -> Instance:
    """An instance of `task` (module docstring)."""
    rng = None if seed is None else np.random.default_rng(instance_entropy(split, seed))
    for _ in range(MAX_TRIES):
        placed: Dict[str, Placed] = {}
        chosen: Dict[str, int] = {}
        for spec in task.objects:
            asset, chosen[spec.name] = _choose(spec, split, rng, vary_assets, chosen)
            if rng is None:
                scale, offsets = canonical_scale(spec), (0.0, 0.0, 0.0, 0.0)
            else:
                drawn = float(rng.uniform(*spec.scale))  # drawn either way: the same seed, the same poses
                scale = drawn if vary_assets else canonical_scale(spec)
                nx, ny = spec.noise_xy
                align_noise = spec.align.noise if spec.align is not None else 0.0
                offsets = (rng.uniform(-nx, nx), rng.uniform(-ny, ny), rng.uniform(-spec.noise_yaw, spec.noise_yaw),
                           rng.uniform(-align_noise, align_noise))
            placed[spec.name] = _place(spec, asset, round(scale, 3), [round(float(v), 6) for v in offsets], placed)
        objects = list(placed.values())
        if first_overlap(task, objects) is None:
            if rng is not None and vary_assets and task.distractors is not None:
                objects += _distractors(task, split, rng, objects)
            return Instance(task, split, seed, tuple(objects), vary_assets)
        if rng is None:
            pair = first_overlap(task, objects)
            raise ValueError(f"task {task.name}: the canonical instance has overlapping objects {pair}")
    raise RuntimeError(f"task {task.name}: no instance without overlaps in {MAX_TRIES} draws (seed {seed})")


def _distractors(task: TaskSpec, split: str, rng: np.random.Generator, objects: List[Placed]) -> List[Placed]:
    spec = task.distractors
    count = int(rng.integers(spec.count[0], spec.count[1] + 1))
    (x0, x1), (y0, y1) = spec.region
    out: List[Placed] = []
    for k in range(count):
        asset = spec.pool[int(rng.integers(len(spec.pool)))]
        for _ in range(DISTRACTOR_TRIES):
            xy, yaw = (rng.uniform(x0, x1), rng.uniform(y0, y1)), rng.uniform(-180.0, 180.0)
            info = asset_info(asset)
            z = -info["aabb"]["min"][2] + GAP
            candidate = Placed(f"d{k}", asset, (round(float(xy[0]), 6), round(float(xy[1]), 6), float(z)),
                               round(float(yaw), 6), 1.0, False, "table", role="distractor")
            if all(_exempt(task, candidate, o) or not overlapping(candidate, o) for o in objects + out):
                out.append(candidate)
                break
    return out
