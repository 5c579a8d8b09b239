"""Demonstration anchors: the values a mechanism's demonstration used, transferred to a scene.

`learn extract` keeps, for each value variable of a mechanism's steps, what the demonstration
did, relative to the objects involved (`NAME.anchors.json` beside the fragment; the format is
in docs/mechanisms.md):

- **grasp**: the gripper frame in the grasped object's frame, with the object's bounding box;
- **contact**: the pusher's pose (the held tool, or the gripper frame) at first contact, the
  contact point, push direction and the target's outward normal there, each twice: in the
  target's frame (with its bounding box) and in the *reach frame* (origin at the target, x
  horizontal from the robot's shoulder towards it, z up: "pull it towards me");
- **push**: how far the push went past first contact, and, where it carried the target off its
  support, how far past the support's edge.

`AnchoredSampler` proposes these transferred to the scene first (a box of another size scales
the offsets, another pose turns them, and all but the first get spread), then the generic
sampler's proposals; the generic sampler verifies every one (IK, collisions, motion). So a
mechanism extracted a minute ago first tries what the user showed, and learned samplers rank
anchored proposals with the rest. Only geometry and poses are read, never names.
"""
from __future__ import annotations

import itertools
import json
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Iterator, Mapping, Optional, Tuple

import numpy as np
from scipy.spatial.transform import Rotation

from ..world.values import Grasp
from .budget import SamplerBudget
from .contact import BACK, ContactCandidate
from .geometry import body_mesh, matrix_pose, pose_matrix
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
    """The demonstrated value transferred to the scene (then with spread), then the generic
    sampler's proposals; the generic sampler verifies both."""

    def __init__(self, generic: Sampler, anchor: Mapping[str, object], budget: SamplerBudget = SamplerBudget()):
        super().__init__(budget)
        self.generic, self.anchor = generic, anchor
        self.budget = generic.budget

    def propose(self, world: "World", request: SampleRequest, rng: np.random.Generator, budget: int) -> Iterator:
        kind, count = self.anchor["kind"], self.sampler_budget.anchor_proposals
        if kind == "grasp":
            anchored = grasp_proposals(world, request.objects()[0], self.anchor, rng, self.sampler_budget)
        elif kind == "contact":
            target = request.objects()[-2]
            anchored = contact_proposals(world, target, self.anchor, rng, self.sampler_budget)
        else:
            anchored = push_proposals(self.anchor, rng, self.sampler_budget, world, request.values()[0])
        yield from itertools.islice(anchored, count)
        yield from self.generic.propose(world, request, rng, budget)

    def verify(self, world: "World", request: SampleRequest, candidate, rng: np.random.Generator):
        return self.generic.verify(world, request, candidate, rng)


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
    return Rotation.from_rotvec(axis / max(np.linalg.norm(axis), 1e-12) * angle).as_matrix()


def grasp_proposals(world: "World", obj: str, anchor: Mapping[str, object], rng: np.random.Generator,
                    budget: SamplerBudget) -> Iterator[Grasp]:
    """The demonstrated grasp on `obj` (its offset scaled to `obj`'s box), then spread around
    it; the fingers close on what a ray along the closing axis meets (a grasp whose fingers
    would close on nothing is skipped)."""
    mesh = body_mesh(world, obj)
    frame = pose_matrix(tuple(tuple(v) for v in anchor["in_object"]))
    centre = _scaled(frame[:3, 3], _box(anchor), _mesh_box(world, obj), budget)
    for k in range(4 * budget.anchor_proposals):
        candidate = np.eye(4)
        # The first exactly as demonstrated; the rest turned about the approach axis and shifted.
        turn = _rotation(frame[:3, 2], rng.normal(0.0, budget.anchor_turn)) if k else np.eye(3)
        candidate[:3, :3] = turn @ frame[:3, :3]
        candidate[:3, 3] = centre + (rng.normal(0.0, budget.anchor_shift, 3) if k else 0.0)
        pinch = _pinch(mesh, candidate)
        if pinch is not None:
            yield Grasp(obj, matrix_pose(candidate), float(np.linalg.norm(pinch[1] - pinch[0])),
                        tuple(tuple(float(v) for v in q) for q in pinch))


def _pinch(mesh, frame: np.ndarray) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """Where the fingers meet the surface closing along the frame's y axis from either side
    (object frame), or None if they would close on nothing."""
    centre, closing = frame[:3, 3], frame[:3, 1]
    hits = []
    for sign in (1.0, -1.0):
        origin = centre + sign * closing * 0.2
        points, _, _ = mesh.ray.intersects_location([origin], [-sign * closing])
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


def contact_proposals(world: "World", target: str, anchor: Mapping[str, object], rng: np.random.Generator,
                      budget: SamplerBudget) -> Iterator[ContactCandidate]:
    """The demonstrated contact in the target's frame and in the reach frame, in turns; the
    first of each exactly, the rest turned about the vertical through the contact point and
    shifted. The pusher's gripper frame follows from the current grasp on the tool."""
    tool = world.attachment.name if world.attachment is not None else None
    tcp = pose_matrix(world.held_tcp_in_object()) if tool is not None else np.eye(4)
    in_target = _transferred(anchor["in_target"], pose_matrix(world.pose(target)), _box(anchor),
                             _mesh_box(world, target), budget)
    in_reach = _transferred(anchor["in_reach"], reach_frame(world.shoulder, world.pose(target)[0]), None, None,
                           budget)
    for k in range(budget.anchor_proposals):
        for pusher, point, direction, normal in (in_target, in_reach):
            if k:
                turn = np.eye(4)
                turn[:3, :3] = _rotation((0.0, 0.0, 1.0), rng.normal(0.0, budget.anchor_turn))
                shift = np.eye(4)
                shift[:2, 3] = rng.normal(0.0, budget.anchor_shift, 2)
                about = np.eye(4)
                about[:3, 3] = point
                move = shift @ about @ turn @ np.linalg.inv(about)
                pusher, direction, normal = move @ pusher, move[:3, :3] @ direction, move[:3, :3] @ normal
                point = move[:3, 3] + move[:3, :3] @ point
            yield ContactCandidate((pusher,), (pusher @ tcp,), normal * BACK if tool else -direction * BACK,
                                   point, direction, normal)


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
                   world: Optional["World"] = None, contact=None) -> Iterator[float]:
    """The demonstrated push: where it carried the target past its support's edge, as far past
    the edge as in the demonstration (the target may lie farther from the edge here); and the
    demonstrated distance itself. Then spread (relative) around them, in turns."""
    distances = [float(anchor["distance"])]
    if anchor.get("past_edge") is not None and world is not None and contact is not None:
        support = contact.support
        edge = edge_distance(np.asarray(world.pose(contact.target)[0], dtype=float),
                             np.asarray(contact.direction, dtype=float), pose_matrix(world.pose(support)),
                             body_mesh(world, support).bounds)
        if edge is not None:
            distances.insert(0, float(np.clip(edge + float(anchor["past_edge"]), 0.01, 0.6)))
    yield from distances
    for k in itertools.count():
        distance = distances[k % len(distances)]
        yield float(np.clip(distance * (1.0 + rng.normal(0.0, budget.anchor_distance_spread)), 0.01, 0.6))
