"""The generic grasp sampler G(O, T_o) (paper Appendix "Samplers for Generic Operations").

Proposing is cheap and geometric; verifying is not. `propose_grasps` draws antipodal pairs
from the object's shape alone (a surface point p1 with outward normal n1, and the point p2
where a ray from just inside p1 along -n1 leaves the solid), puts the gripper frame at their
midpoint with y along p2 - p1, and turns the approach about y to one of the angles that pass
the cheap tests: not from below, the flange within the arm's reach, no fingertip under the
support. `verify_grasp` then asks IK and the collision checker (pre-grasp and grasp, fingers
open to the grasp's opening). A pinch of a thin overhang needs all of this: most pairs and
most approach angles of a plate pushed over the edge are useless, and a uniform draw found
none in 600 samples.
"""
from __future__ import annotations

import weakref
from functools import lru_cache
from typing import TYPE_CHECKING, Callable, Dict, Iterator, List, Optional, Tuple

import numpy as np
import pybullet as p

from ..world.collision import CollisionChecker
from ..world.robot import MAX_OPENING, grasp_opening
from ..world.values import Grasp, Pose
from .budget import SamplerBudget
from .geometry import body_mesh, matrix_pose, pose_matrix, sample_surface
from .gripper import FINGER_HALF_WIDTH, FINGER_SPAN, FINGER_THICKNESS, HAND_BOX
from .interface import SampleRequest, Sampler
from .mesh import Mesh
from .support_heights import SupportHeights

if TYPE_CHECKING:
    from ..world.world import World

ANTIPODAL_COS = float(np.cos(np.radians(15.0)))
MIN_WIDTH, MAX_WIDTH = 0.002, 0.075   # a 3 mm sheet can be pinched; the fingers open to 8 cm
PRE_GRASP = 0.08        # metres back along -approach
MAX_UP = 0.3            # largest world z-component of the approach: none from below
INSIDE = 1e-4           # ray origins start this far inside the surface
# How many points, angles and IK restarts a proposal or a verification spends: budget.py
# (SamplerBudget.grasp_*).


def antipodal_pairs(mesh: Mesh, count: int, rng: np.random.Generator
                    ) -> Iterator[Optional[Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]]:
    """For `count` sampled surface points, (p1, n1, p2, n2) if the point has an antipodal
    partner within the gripper's range, else None (one item per sample, for budgeting)."""
    p1, n1 = sample_surface(mesh, count, rng)
    ok, p2, n2 = _partners(mesh, p1, n1)
    for i in range(count):
        yield (p1[i], n1[i], p2[i], n2[i]) if ok[i] else None


def _partners(mesh: Mesh, p1: np.ndarray, n1: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For surface points `p1` (n, 3) with outward normals `n1`: whether each has an antipodal
    partner in the gripper's range (n,), the partner p2 and its normal n2 (n, 3; zeros where
    none). A ray from just inside p1 along -n1: each ray's answer is its own, whichever
    others are cast with it."""
    ok, p2, n2 = np.zeros(len(p1), dtype=bool), np.zeros((len(p1), 3)), np.zeros((len(p1), 3))
    ray, tri, hits = mesh.first_hits(p1 - INSIDE * n1, -n1)
    for face, i, hit in zip(tri, ray, hits):
        normal = mesh.face_normals[face]
        width = float(np.linalg.norm(hit - p1[i]))
        if float(np.dot(n1[i], normal)) < -ANTIPODAL_COS and MIN_WIDTH <= width <= MAX_WIDTH:
            ok[i], p2[i], n2[i] = True, hit, normal
    return ok, p2, n2


class AntipodalPool:
    """`size` surface points of a shape (object frame; SamplerBudget.grasp_pool_points),
    drawn once per shape (seed 0), and their antipodal partners. Pairs do not depend on
    where the object is, and finding them (a ray through the mesh per point) was a tenth of
    a Lever plan; proposals draw points from this pool instead. A point's partner is found
    the first time a proposal draws it: a plan that needs one grasp of a box draws a few
    hundred of the points, and casting all 4096 rays up front cost 70-150 ms a shape (a
    box, a ladle; 300: 6-8 ms)."""

    def __init__(self, mesh: Mesh, size: int):
        self.mesh, self.size = mesh, size
        self.p1, self.n1 = sample_surface(mesh, size, np.random.default_rng(0))
        self.known = np.zeros(size, dtype=bool)
        self.has_pair = np.zeros(size, dtype=bool)
        self.p2 = np.zeros((size, 3))
        self.rays = 0   # rays cast so far (tests)

    def pairs(self, drawn: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(p1s, p2s) of the points `drawn` (indices into the pool) that have a partner, in order."""
        new = np.unique(drawn[~self.known[drawn]])
        if len(new):
            ok, p2, _ = _partners(self.mesh, self.p1[new], self.n1[new])
            self.has_pair[new], self.p2[new], self.known[new] = ok, p2, True
            self.rays += len(new)
        drawn = drawn[self.has_pair[drawn]]
        return self.p1[drawn], self.p2[drawn]


def antipodal_pool(mesh: Mesh, budget: SamplerBudget = SamplerBudget()) -> AntipodalPool:
    """The shape's pool of `budget.grasp_pool_points` points (shared by every proposal of
    the process that asks for that size)."""
    return _antipodal_pool(mesh, budget.grasp_pool_points)


@lru_cache(maxsize=64)
def _antipodal_pool(mesh: Mesh, size: int) -> AntipodalPool:
    # Keyed by the size alone, not the whole budget: budgets differing elsewhere share pools.
    return AntipodalPool(mesh, size)


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Row-wise u x v of (n, 3) arrays (np.cross's generality costs ~80 us a call; this is its hot path)."""
    return np.stack([u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1], u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2],
                     u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]], axis=1)


def gripper_frames(p1: np.ndarray, p2: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """(n, k, 4, 4) gripper frames in the object frame for n antipodal pairs (p1, p2: (n, 3)):
    origin at the midpoint, y along p2 - p1, z (approach) at each of a pair's `angles` (n, k)
    about y."""
    y = (p2 - p1) / np.linalg.norm(p2 - p1, axis=1, keepdims=True)
    helper = np.eye(3)[np.argmin(np.abs(y), axis=1)]  # the axis least parallel to y
    a = _cross(y, helper)
    a /= np.linalg.norm(a, axis=1, keepdims=True)
    b = _cross(y, a)
    cos, sin = np.cos(angles)[..., None], np.sin(angles)[..., None]            # (n, k, 1)
    frames = np.tile(np.eye(4), angles.shape + (1, 1))
    frames[..., :3, 0] = cos * b[:, None] + sin * _cross(y, b)[:, None]   # x = y cross z (b = y cross a)
    frames[..., :3, 1] = y[:, None]
    frames[..., :3, 2] = cos * a[:, None] + sin * b[:, None]
    frames[..., :3, 3] = ((p1 + p2) / 2)[:, None]
    return frames


def world_grasp_pose(world: "World", grasp: Grasp) -> Pose:
    """The gripper frame in the world for `grasp` at the object's current pose."""
    pos, orn = p.multiplyTransforms(*world.pose(grasp.object), *grasp.in_object)
    return tuple(pos), tuple(orn)


def offset_along_z(pose: Pose, distance: float) -> Pose:
    """`pose` moved `distance` along its own z axis (negative: back from the approach)."""
    matrix = pose_matrix(pose)
    return tuple(float(v) for v in matrix[:3, 3] + distance * matrix[:3, 2]), pose[1]


def grasp_configurations(world: "World", grasp: Grasp, rng: np.random.Generator,
                         check_collisions: bool = True, budget: SamplerBudget = SamplerBudget()
                         ) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """(pre-grasp, grasp) arm configurations for `grasp` at the object's current pose, or
    None if either has no IK (`budget.grasp_ik_restarts` restarts each) or (with
    `check_collisions`) touches anything, fingers open."""
    kin = world.kinematics
    target = world_grasp_pose(world, grasp)
    q = kin.ik(target[0], target[1], rng, restarts=budget.grasp_ik_restarts)
    if q is None:
        return None
    checker = CollisionChecker(world) if check_collisions else None
    with world.saved():
        world.set_fingers(grasp_opening(grasp.width) / 2)
        if checker is not None and checker.collides(q):
            return None
        pre = offset_along_z(target, -PRE_GRASP)
        # Seeded: the retreat is a short straight line. A pre-grasp the seeded solve misses lies
        # at the edge of reach, and as few restarts as for the grasp suffice: with IK's default
        # 30 these failures took a fifth of a CoM plan (5 of 17 grasps verified, 28 ms each).
        q_pre = kin.ik(pre[0], pre[1], rng, seed=q, restarts=budget.grasp_ik_restarts)
        if q_pre is None or (checker is not None and checker.collides(q_pre)):
            return None
    return q_pre, q


CLOUD_POINTS = 1500     # surface points of an object checked against the gripper's boxes
# Fingertips must stay this far above the surface an object rests on: a real hand is not
# calibrated to the millimetre, so pinching the top 1 mm of a caliper lying flat does not
# count as a grasp (it must be pushed over an edge first, as in the paper's Edge task).
SUPPORT_CLEARANCE = 0.005


def _grid(box, per_metre: float = 25.0) -> np.ndarray:
    """A grid over a box (corners included, ~4 cm apart)."""
    axes = [np.linspace(lo, hi, max(2, int(np.ceil((hi - lo) * per_metre)) + 1)) for lo, hi in box]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


_HAND_GRID = _grid(HAND_BOX)
_FINGER_GRID = _grid(((-FINGER_HALF_WIDTH, FINGER_HALF_WIDTH), (0.0, FINGER_THICKNESS), FINGER_SPAN))


def _finger_points(openings: np.ndarray) -> np.ndarray:
    """Grids over both fingers (gripper frame, homogeneous), (n, m, 4): for each of
    `openings` (n,), the fingers that far apart."""
    shift = np.zeros((len(openings), 1, 3))
    shift[:, 0, 1] = np.asarray(openings) / 2
    right = _FINGER_GRID[None] + shift
    points = np.concatenate([right, right * (1.0, -1.0, 1.0)], axis=1)
    return np.concatenate([points, np.ones(points.shape[:2] + (1,))], axis=2)


_HAND_POINTS = np.hstack([_HAND_GRID, np.ones((len(_HAND_GRID), 1))])


def _gripper_points(openings: np.ndarray) -> np.ndarray:
    """Grids over the hand and both fingers (gripper frame, homogeneous), (n, m, 4)."""
    hand = np.broadcast_to(_HAND_POINTS, (len(openings),) + _HAND_POINTS.shape)
    return np.concatenate([hand, _finger_points(openings)], axis=1)


def _inside_gripper(points: np.ndarray, opening: float) -> np.ndarray:
    """Which of `points` (..., 3), gripper frame, lie inside the hand or a finger box."""
    x, y, z = points[..., 0], points[..., 1], points[..., 2]
    hand = (np.abs(x) < HAND_BOX[0][1]) & (np.abs(y) < HAND_BOX[1][1]) & (z > HAND_BOX[2][0]) & (z < HAND_BOX[2][1])
    inner = opening / 2
    finger = (np.abs(x) < FINGER_HALF_WIDTH) & (np.abs(y) > inner) & (np.abs(y) < inner + FINGER_THICKNESS) & \
             (z > FINGER_SPAN[0]) & (z < FINGER_SPAN[1])
    return hand | finger


_HAND_RADIUS = float(np.linalg.norm([max(abs(lo), abs(hi)) for lo, hi in HAND_BOX]))


def _gripper_radius(opening: float) -> float:
    """The farthest any point of the hand or fingers lies from the gripper frame's origin."""
    finger = np.linalg.norm([FINGER_HALF_WIDTH, opening / 2 + FINGER_THICKNESS, max(map(abs, FINGER_SPAN))])
    return max(_HAND_RADIUS, float(finger))


_TIP_CORNERS = np.array([(x, side, extra) for x in (-FINGER_HALF_WIDTH, FINGER_HALF_WIDTH)
                         for side in (-1.0, 1.0) for extra in (0.0, FINGER_THICKNESS)])


def _fingertip_points(openings: np.ndarray) -> np.ndarray:
    """The corners of both fingertips (gripper frame, homogeneous), (n, 8, 4), for each of `openings`."""
    out = np.ones((len(openings), len(_TIP_CORNERS), 4))
    out[..., 0] = _TIP_CORNERS[:, 0]
    out[..., 1] = _TIP_CORNERS[:, 1] * (np.asarray(openings)[:, None] / 2 + _TIP_CORNERS[:, 2])
    out[..., 2] = FINGER_SPAN[1]
    return out


# Tested before the costlier test against the object's own surface: the fingertips (a plate
# lying flat rejects every pair there), then the fingers (a pinch of a caliper lying flat
# passes the fingertips' test and fails here: the tests of its whole pool took 0.65 s, now
# 0.11 s). Every test only clears `keep`, so their order changes nothing but the time.
_EARLY_SUPPORT_TESTS = (_fingertip_points, _finger_points)


def _clear_of_supports(heights: SupportHeights, frames: np.ndarray, points: np.ndarray) -> np.ndarray:
    """For each gripper frame of `frames` (n, 4, 4, world), whether none of its gripper points
    (`points`, (n, m, 4), gripper frame, each frame's own) that is low down lies less than
    SUPPORT_CLEARANCE above another body (`heights`: the surfaces under the object)."""
    placed = np.einsum("nij,npj->npi", frames[:, :3], points)
    frame_of, point_of = np.nonzero(placed[..., 2] < heights.bottom + SUPPORT_CLEARANCE)
    clear = np.ones(len(frames), dtype=bool)
    clear[frame_of[~heights.clear(placed[frame_of, point_of], SUPPORT_CLEARANCE)]] = False
    return clear


@lru_cache(maxsize=64)
def _surface_cloud(mesh: Mesh) -> np.ndarray:
    """Points (N, 3) covering the object's surface (object frame), drawn once."""
    points, _ = sample_surface(mesh, CLOUD_POINTS, np.random.default_rng(0))
    return np.asarray(points)


def _approach_frames(world: "World", mesh: Mesh, placed: np.ndarray, p1s: np.ndarray,
                     p2s: np.ndarray, heights: SupportHeights, rng: np.random.Generator,
                     budget: SamplerBudget = SamplerBudget()) -> List[np.ndarray]:
    """For each antipodal pair (p1s[k], p2s[k], (n, 3) arrays), the gripper frames (object
    frame, (k, 4, 4)) at `budget.grasp_angles` approach angles (random offset) that pass the
    cheap tests, before any IK: the approach is
    not from below, the flange is within reach, no part of the gripper low down sits less
    than SUPPORT_CLEARANCE above another body's surface (the support, `heights`: points of a
    grid over the gripper), and no point of the object's surface is inside the open gripper.
    Under an overhang there is no support, so a plate pushed past the edge stays graspable; a
    pinch whose hand would hang into the table is dropped here, sparing ~0.1 s of failing IK.
    All pairs' frames are tested together, the cheapest tests that reject most first: the
    fingertips and the fingers against the support (_EARLY_SUPPORT_TESTS)."""
    if not len(p1s):
        return []
    angles = budget.grasp_angles
    offsets = rng.uniform(-np.pi, np.pi, len(p1s))
    openings = np.array([grasp_opening(float(width)) for width in np.linalg.norm(p2s - p1s, axis=1)])
    frames = gripper_frames(p1s, p2s, offsets[:, None] + np.arange(angles) * 2 * np.pi / angles)
    in_world = placed @ frames
    reachable = world.within_reach_all(in_world.reshape(-1, 4, 4)).reshape(frames.shape[:2])
    keep = (in_world[..., 2, 2] <= MAX_UP) & reachable                      # (pairs, angles)
    for points_of in _EARLY_SUPPORT_TESTS:
        _drop_on_support(keep, in_world, openings, points_of, heights)
    # Only surface points within the gripper's reach of a pair's midpoint can be inside it;
    # those, in every kept frame of the pair at once (a rigid frame's inverse is [R^T, -R^T t]).
    cloud = _surface_cloud(mesh)
    for k in np.flatnonzero(keep.any(axis=1)):
        origin = frames[k, 0, :3, 3]
        near = cloud[np.sum((cloud - origin) ** 2, axis=1) < _gripper_radius(openings[k]) ** 2]
        if len(near):
            local = np.matmul(near[None] - origin, frames[k, :, :3, :3])
            keep[k] &= ~_inside_gripper(local, openings[k]).any(axis=1)
    _drop_on_support(keep, in_world, openings, _gripper_points, heights)
    return [frames[k][keep[k]] for k in range(len(p1s))]


def _drop_on_support(keep: np.ndarray, in_world: np.ndarray, openings: np.ndarray,
                     points_of: Callable[[np.ndarray], np.ndarray], heights: SupportHeights) -> None:
    """Clear `keep` (pairs, angles) where the gripper frame's points (`points_of(openings)`,
    (n, m, 4), each pair's opening) are not clear of the support."""
    pair_of, angle_of = np.nonzero(keep)
    if len(pair_of):
        clear = _clear_of_supports(heights, in_world[pair_of, angle_of], points_of(openings[pair_of]))
        keep[pair_of[~clear], angle_of[~clear]] = False


def _scene(world: "World") -> tuple:
    """Where everything is: the support heights under an object hold while this does."""
    return tuple(world.pose(name) for name in world.bodies) + (tuple(np.round(world.arm(), 6)),)


def _support_heights(world: "World", obj: str, mesh: Mesh, scene: tuple) -> Tuple[np.ndarray, SupportHeights]:
    """The object's pose matrix and the support heights around it in `scene`, shared by the
    calls that propose grasps of it there: a learned sampler fills its batch with several
    calls, and a step revisited in the same state calls again, and each would cast the same
    rays (a quarter of a call's time on a plate's rim)."""
    known = _HEIGHTS.setdefault(world, {})
    # The grid spans the object's AABB as PyBullet has it, which depends on how the object got
    # where it is (simulated or set), not only on where it is: the same AABB too, or new heights.
    key = (obj, scene, p.getAABB(world.bodies[obj].id, physicsClientId=world.client))
    if key not in known:
        if len(known) >= 16:
            del known[next(iter(known))]
        placed = pose_matrix(world.pose(obj))
        bottom = float((mesh.vertices @ placed[:3, :3].T + placed[:3, 3])[:, 2].min())
        known[key] = placed, SupportHeights(world, obj, bottom, _gripper_radius(MAX_OPENING))
    return known[key]


_HEIGHTS: "weakref.WeakKeyDictionary[World, Dict[Tuple[str, tuple], Tuple[np.ndarray, SupportHeights]]]" = \
    weakref.WeakKeyDictionary()


def propose_grasps(world: "World", obj: str, rng: np.random.Generator, max_points: int,
                   budget: SamplerBudget = SamplerBudget()) -> Iterator[Grasp]:
    """Geometrically plausible grasps of `obj` at its current pose (no IK, no collision
    checks); examines at most `max_points` surface points, `budget.grasp_batch` at a time."""
    mesh = body_mesh(world, obj)
    examined = 0
    scene, heights = None, None
    pool = antipodal_pool(mesh, budget)
    while examined < max_points:
        count = min(budget.grasp_batch, max_points - examined)
        examined += count
        now = _scene(world)
        if now != scene:  # the caller may move things between batches
            scene = now
            placed, heights = _support_heights(world, obj, mesh, scene)
        p1s, p2s = pool.pairs(rng.integers(pool.size, size=count))
        for p1, p2, frames in zip(p1s, p2s, _approach_frames(world, mesh, placed, p1s, p2s, heights, rng, budget)):
            if len(frames):
                frame = frames[int(rng.integers(len(frames)))]
                yield Grasp(obj, matrix_pose(frame), float(np.linalg.norm(p2 - p1)),
                            (tuple(float(v) for v in p1), tuple(float(v) for v in p2)))


def verify_grasp(world: "World", grasp: Grasp, rng: np.random.Generator,
                 budget: SamplerBudget = SamplerBudget()) -> bool:
    """The arm reaches the grasp and its pre-grasp without touching anything."""
    return grasp_configurations(world, grasp, rng, budget=budget) is not None


class GraspSampler(Sampler[Grasp]):
    """The stream's first input is the object to grasp; proposals have already passed the
    cheap geometric tests, so fewer are verified per visit than for other samplers."""

    def visit_budget(self, budget: SamplerBudget) -> int:
        return budget.grasp_proposals

    def propose(self, world: "World", request: SampleRequest, rng: np.random.Generator,
                budget: int) -> Iterator[Grasp]:
        points = self.sampler_budget.grasp_points_per_proposal * budget
        return propose_grasps(world, request.objects()[0], rng, points, self.sampler_budget)

    def verify(self, world: "World", request: SampleRequest, grasp: Grasp, rng: np.random.Generator) -> Optional[Grasp]:
        return grasp if verify_grasp(world, grasp, rng, self.sampler_budget) else None


def sample_grasps(world: "World", obj: str, rng: np.random.Generator, max_attempts: Optional[int] = None,
                  deadline: float = float("inf"), budget: SamplerBudget = SamplerBudget()) -> Iterator[Grasp]:
    """Reachable, collision-free antipodal grasps of `obj` at its current pose; stops after
    `max_attempts` proposals (default `budget.sample_attempts`; `grasp_points_per_proposal`
    times as many surface points) or at `deadline` (time.perf_counter())."""
    request = SampleRequest("sample-grasp", (obj,), ("?x",), deadline=deadline)
    limit = budget.sample_attempts if max_attempts is None else max_attempts
    return GraspSampler(budget).draw(world, request, rng, budget=limit)
