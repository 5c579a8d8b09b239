"""Demonstration anchors: the values a mechanism's demonstration used, transferred to a scene.

`learn extract` keeps, for each value variable of a mechanism's steps, what the demonstration
did, relative to the objects involved (`NAME.anchors.json` beside the fragment; the format is
in docs/mechanisms.md):

- **grasp**: the gripper frame in the grasped object's frame, with the object's bounding box;
- **contact**: the pusher's pose (the held tool, or the gripper frame) at first contact, the
  contact point, push direction and the target's outward normal there, each twice: in the
  target's frame (with its bounding box) and in the *reach frame* (origin at the target, x
  horizontal from the robot's shoulder towards it, z up: "pull it towards me"). The pusher's
  pose is proposed as demonstrated; spread proposals keep only where the target was touched
  and let the generic contact sampler put the tool in hand there (it may be another tool);
- **push**: how far the push went past first contact, and, where it carried the target off its
  support, how far past the support's edge.

`AnchoredSampler` proposes these transferred to the scene (a box of another size scales the
offsets, another pose turns them) first, once per situation (where the step's objects lie and
how the tool is held); after them, a mixture: each proposal is spread around the demonstrated
values with chance `anchor_share`, else the generic sampler's. The generic sampler verifies
every one (IK, collisions, motion). So a mechanism extracted a minute ago first tries what the
user showed, a demonstration that does not fit the scene costs a bounded factor of the generic
search rather than all of it, and learned samplers rank anchored proposals with the rest.
Only geometry and poses are read, never names.
"""
from __future__ import annotations

import itertools
import json
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Iterator, List, Mapping, NamedTuple, Optional, Set, Tuple

import numpy as np

from ..world.values import Grasp
from .budget import SamplerBudget
from .contact import BACK, ContactCandidate, ContactSampler, ContactScene, held_tool_points
from .geometry import body_mesh, matrix_pose, pose_matrix, rotvec_matrices
from .interface import SampleRequest, Sampler

if TYPE_CHECKING:
    from ..world.world import World

SCHEMA = 1
KINDS = {"grasp": "grasp", "contact": "contact", "push": "push-motion"}   # anchor kind -> the sampler it anchors


def anchors_path(fragment: str, mechanism: str) -> str:
    """Where a fragment's mechanism keeps its anchors: beside the fragment."""
    return os.path.join(os.path.dirname(os.path.abspath(fragment)), f"{mechanism}.anchors.json")


@dataclass(frozen=True)
class MechanismAnchors:
    """A mechanism's anchors: variable (`?g`) -> what the demonstration did (module docstring)."""

    mechanism: str
    variables: Mapping[str, Mapping[str, object]]

    def for_sampler(self, variable: Optional[str], sampler: str) -> Optional[Mapping[str, object]]:
        """The anchor of `variable` if it anchors the sampler named `sampler` (else None)."""
        anchor = self.variables.get(variable) if variable else None
        return anchor if anchor is not None and KINDS.get(str(anchor.get("kind"))) == sampler else None


def read_anchors(path: str, mechanism: str) -> MechanismAnchors:
    """The anchors file at `path` for `mechanism`; ValueError (one line) if it is malformed."""
    with open(path, encoding="utf-8") as handle:
        data = json.load(handle)
    if not isinstance(data, dict) or data.get("schema") != SCHEMA:
        raise ValueError(f"{path}: not an anchors file of schema {SCHEMA}")
    if data.get("mechanism") != mechanism:
        raise ValueError(f"{path}: anchors of mechanism {data.get('mechanism')!r}, not {mechanism!r}")
    variables = data.get("variables")
    if not isinstance(variables, dict) or not all(isinstance(v, dict) for v in variables.values()):
        raise ValueError(f"{path}: 'variables' must map each variable to an object")
    return MechanismAnchors(mechanism, variables)


def anchors_beside(fragment: str, mechanism: str) -> Optional[MechanismAnchors]:
    """The anchors file beside `fragment` for `mechanism`, or None if it has none; ValueError
    (one line) if it is malformed."""
    path = anchors_path(fragment, mechanism) if fragment else ""
    return read_anchors(path, mechanism) if path and os.path.isfile(path) else None


class AnchoredSampler(Sampler):
    """The demonstrated values transferred to the scene, once per situation, then a mixture of
    values spread around them and the generic sampler's proposals; the generic sampler
    verifies all."""

    def __init__(self, generic: Sampler, anchor: Mapping[str, object], budget: SamplerBudget = SamplerBudget()):
        super().__init__(budget)
        self.generic, self.anchor = generic, anchor
        self.budget = generic.budget
        self._shown: Set[Tuple] = set()   # situations the demonstrated values were proposed in

    def propose(self, world: "World", request: SampleRequest, rng: np.random.Generator, budget: int) -> Iterator:
        kind = self.anchor["kind"]
        if kind == "grasp":
            anchored = grasp_proposals(world, request.objects()[0], self.anchor, rng, self.sampler_budget)
        elif kind == "contact":
            target, support = request.objects()[-2:]
            anchored = contact_proposals(world, target, support, self.anchor, rng, self.sampler_budget)
        else:
            anchored = push_proposals(self.anchor, rng, self.sampler_budget, world, request.values()[0])
        situation = _situation(world, request)
        if situation not in self._shown:
            self._shown.add(situation)
            yield from anchored.exact
        spread = itertools.islice(anchored.spread, self.sampler_budget.anchor_proposals)
        yield from _mixture(spread, self.generic.propose(world, request, rng, budget), rng,
                            self.sampler_budget.anchor_share)

    def verify(self, world: "World", request: SampleRequest, candidate, rng: np.random.Generator):
        return self.generic.verify(world, request, candidate, rng)


class Anchored(NamedTuple):
    """A demonstration's values transferred to a scene: as demonstrated, then spread around them."""

    exact: List
    spread: Iterator


def _situation(world: "World", request: SampleRequest) -> Tuple:
    """What a step's proposals depend on, to the millimetre: where its objects lie and what
    the hand holds how (a sampler is its stream's for one mechanism's variable already). The
    same values proposed twice in it would simulate the same, so the demonstrated ones are
    proposed once per situation."""
    held = world.held_tcp_in_object() if world.attachment is not None else None
    poses = tuple((name, world.pose(name)) for name in request.objects() if name in world.bodies)
    return _rounded(poses), world.attachment and world.attachment.name, _rounded(held)


def _rounded(value):
    if isinstance(value, (tuple, list)):
        return tuple(_rounded(v) for v in value)
    return round(value, 3) if isinstance(value, float) else value


def _mixture(spread: Iterator, generic: Iterator, rng: np.random.Generator, share: float) -> Iterator:
    """Proposals drawn around the demonstrated values with chance `share`, else the generic
    sampler's (a goal bias, as in RRT): a demonstration that misleads costs about 1/(1 - share)
    of the generic search, which stays complete; either source running out leaves the other."""
    sources = [spread, generic]
    while sources:
        source = sources[0] if len(sources) == 1 or rng.random() < share else sources[1]
        value = next(source, None)
        if value is None:
            sources.remove(source)
            continue
        yield value


# -- transfer --------------------------------------------------------------------------
def _centre_size(lo, hi) -> Tuple[np.ndarray, np.ndarray]:
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    return (lo + hi) / 2, np.maximum(hi - lo, 1e-4)


def _box(anchor: Mapping[str, object]) -> Tuple[np.ndarray, np.ndarray]:
    return _centre_size(*anchor["box"])


def _scaled(point: np.ndarray, demo_box, now_box, budget: SamplerBudget) -> np.ndarray:
    """A point in a demonstration object's frame, moved with its box onto another box."""
    (c0, size0), (c1, size1) = demo_box, now_box
    scale = np.clip(size1 / size0, 1.0 / budget.anchor_max_scale, budget.anchor_max_scale)
    return c1 + (point - c0) * scale


def _mesh_box(world: "World", name: str) -> Tuple[np.ndarray, np.ndarray]:
    return _centre_size(*body_mesh(world, name).bounds)


def _rotation(axis, angle: float) -> np.ndarray:
    axis = np.asarray(axis, dtype=float)
    return rotvec_matrices(axis / max(np.linalg.norm(axis), 1e-12) * angle)


def grasp_proposals(world: "World", obj: str, anchor: Mapping[str, object], rng: np.random.Generator,
                    budget: SamplerBudget) -> Anchored:
    """The demonstrated grasp on `obj` (its offset scaled to `obj`'s box), and grasps spread
    around it (turned about the approach axis and shifted); the fingers close on what a ray
    along the closing axis meets (a grasp whose fingers would close on nothing is skipped)."""
    mesh = body_mesh(world, obj)
    frame = pose_matrix(tuple(tuple(v) for v in anchor["in_object"]))
    centre = _scaled(frame[:3, 3], _box(anchor), _mesh_box(world, obj), budget)

    def grasp(rotation: np.ndarray, position: np.ndarray) -> Optional[Grasp]:
        candidate = np.eye(4)
        candidate[:3, :3], candidate[:3, 3] = rotation, position
        pinch = _pinch(mesh, candidate)
        return None if pinch is None else Grasp(obj, matrix_pose(candidate), float(np.linalg.norm(pinch[1] - pinch[0])),
                                                tuple(tuple(float(v) for v in q) for q in pinch))

    def spread() -> Iterator[Grasp]:
        for _ in range(4 * budget.anchor_proposals):
            turn = _rotation(frame[:3, 2], rng.normal(0.0, budget.anchor_turn))
            value = grasp(turn @ frame[:3, :3], centre + rng.normal(0.0, budget.anchor_shift, 3))
            if value is not None:
                yield value
    exact = grasp(frame[:3, :3], centre)
    return Anchored([exact] if exact is not None else [], spread())


def _pinch(mesh, frame: np.ndarray) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """Where the fingers meet the surface closing along the frame's y axis from either side
    (object frame), or None if they would close on nothing."""
    centre, closing = frame[:3, 3], frame[:3, 1]
    hits = []
    for sign in (1.0, -1.0):
        origin = centre + sign * closing * 0.2
        points, _ = mesh.all_hits(origin, -sign * closing)
        if not len(points):
            return None
        hits.append(points[int(np.argmin(np.linalg.norm(points - origin, axis=1)))])
    return hits[1], hits[0]


def reach_frame(shoulder, centre) -> np.ndarray:
    """Origin at `centre` (a target's), x horizontal from the robot's `shoulder` towards it, z up."""
    centre = np.asarray(centre, dtype=float)
    x = centre - np.asarray(shoulder, dtype=float)
    x[2] = 0.0
    x /= max(np.linalg.norm(x), 1e-9)
    frame = np.eye(4)
    frame[:3, 0], frame[:3, 1], frame[:3, 2], frame[:3, 3] = x, np.cross([0.0, 0.0, 1.0], x), (0.0, 0.0, 1.0), centre
    return frame


def contact_proposals(world: "World", target: str, support: str, anchor: Mapping[str, object],
                      rng: np.random.Generator, budget: SamplerBudget) -> Anchored:
    """The demonstrated contact in the target's frame and in the reach frame: the pusher as
    demonstrated (its gripper frame follows from the current grasp on the tool); then, spread
    around the two demonstrated points on the target (shifted, and put back on the target's
    side by a ray), contacts the generic sampler makes there: the tool in hand may not be the
    demonstrated one, so which of its points touches is the generic sampler's choice."""
    tool = world.attachment.name if world.attachment is not None else None
    tcp = pose_matrix(world.held_tcp_in_object()) if tool is not None else np.eye(4)
    in_target = _transferred(anchor["in_target"], pose_matrix(world.pose(target)), _box(anchor),
                             _mesh_box(world, target), budget)
    in_reach = _transferred(anchor["in_reach"], reach_frame(world.shoulder, world.pose(target)[0]), None, None,
                           budget)
    exact = [ContactCandidate((pusher,), (pusher @ tcp,), normal * BACK if tool else -direction * BACK,
                              point, direction, normal) for pusher, point, direction, normal in (in_target, in_reach)]

    def spread() -> Iterator[ContactCandidate]:
        scene = ContactScene.read(world, target, support, ContactSampler.gap, budget,
                                  held_tool_points(world, rng, budget))
        for _ in range(budget.anchor_proposals):
            for _, point, _, normal in (in_target, in_reach):
                shifted = point + np.append(rng.normal(0.0, budget.anchor_shift, 2), 0.0)
                side = _side_point(world, target, shifted, normal)
                d = scene.direction(side[1]) if side is not None else None
                candidate = scene.candidate(side[0], side[1], d, rng) if d is not None else None
                if candidate is not None:
                    yield candidate
    return Anchored(exact, spread())


def _side_point(world: "World", target: str, point: np.ndarray,
                normal: np.ndarray) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """The point (world) and outward normal where a horizontal ray towards the target's
    vertical axis, through `point` (kept within the target's height), meets its surface; the
    ray comes from the side `point` lies on (from along `normal` if it lies on the axis)."""
    mesh, pose = body_mesh(world, target), pose_matrix(world.pose(target))
    lo, hi = world.aabb(target)
    height = hi[2] - lo[2]
    point = np.array([point[0], point[1], np.clip(point[2], lo[2] + 0.1 * height, hi[2] - 0.1 * height)])
    outward = point - pose[:3, 3]
    outward[2] = 0.0
    if np.linalg.norm(outward) < 1e-6:
        outward = np.array([normal[0], normal[1], 0.0])
    outward /= max(np.linalg.norm(outward), 1e-9)
    rotation = pose[:3, :3]
    origin = rotation.T @ (point + outward - pose[:3, 3])   # 1 m out, in the target's frame
    hits, faces = mesh.all_hits(origin, rotation.T @ -outward)
    if not len(hits):
        return None
    k = int(np.argmin(np.linalg.norm(hits - origin, axis=1)))
    return rotation @ hits[k] + pose[:3, 3], rotation @ mesh.face_normals[faces[k]]


def _transferred(values: Mapping[str, object], frame: np.ndarray, demo_box, now_box,
                 budget: SamplerBudget) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(pusher 4x4, point, direction, normal) in the world from their values in `frame`; with
    boxes, the contact point moves with the box and the pusher keeps its offset from it."""
    pusher = pose_matrix(tuple(tuple(v) for v in values["pusher"]))
    point = np.asarray(values["point"], dtype=float)
    if demo_box is not None:
        moved = _scaled(point, demo_box, now_box, budget)
        pusher[:3, 3] += moved - point
        point = moved
    rotation = frame[:3, :3]
    direction = rotation @ np.asarray(values["direction"], dtype=float)
    direction[2] = 0.0   # pushes run along the support
    direction /= max(np.linalg.norm(direction), 1e-9)
    return frame @ pusher, frame[:3, :3] @ point + frame[:3, 3], direction, rotation @ np.asarray(values["normal"])


def edge_distance(centre: np.ndarray, direction: np.ndarray, support: np.ndarray,
                  bounds: np.ndarray) -> Optional[float]:
    """How far `centre` (world) goes along the horizontal `direction` before it leaves the
    top of a support whose pose is `support` (4x4) and whose box in its own frame is `bounds`
    ((lo, hi)); None if it is not above that box."""
    inverse = np.linalg.inv(support)
    p, d = (inverse[:3, :3] @ centre + inverse[:3, 3])[:2], (inverse[:3, :3] @ direction)[:2]
    lo, hi = np.asarray(bounds[0], dtype=float)[:2], np.asarray(bounds[1], dtype=float)[:2]
    if np.any(p < lo) or np.any(p > hi) or not np.any(np.abs(d) > 1e-9):
        return None
    exits = [((hi[i] if d[i] > 0 else lo[i]) - p[i]) / d[i] for i in range(2) if abs(d[i]) > 1e-9]
    return float(min(exits))


def push_proposals(anchor: Mapping[str, object], rng: np.random.Generator, budget: SamplerBudget,
                   world: Optional["World"] = None, contact=None) -> Anchored:
    """The demonstrated push: where it carried the target past its support's edge, as far past
    the edge as in the demonstration (the target may lie farther from the edge here); and the
    demonstrated distance itself. Then distances spread (relative) around them, in turns."""
    distances = [float(anchor["distance"])]
    if anchor.get("past_edge") is not None and world is not None and contact is not None:
        support = contact.support
        edge = edge_distance(np.asarray(world.pose(contact.target)[0], dtype=float),
                             np.asarray(contact.direction, dtype=float), pose_matrix(world.pose(support)),
                             body_mesh(world, support).bounds)
        if edge is not None:
            distances.insert(0, float(np.clip(edge + float(anchor["past_edge"]), 0.01, 0.6)))

    def spread() -> Iterator[float]:
        for k in itertools.count():
            distance = distances[k % len(distances)]
            yield float(np.clip(distance * (1.0 + rng.normal(0.0, budget.anchor_distance_spread)), 0.01, 0.6))
    return Anchored(list(distances), spread())
