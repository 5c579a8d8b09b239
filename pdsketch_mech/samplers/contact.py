"""The generic object-contact sampler C(O1, O2, T_o2, O_s, T_s) (paper Appendix "Samplers for
Generic Operations", "Object Contact (C)").

The pusher O1 is the held object, or the bare gripper when nothing is held. A contact pairs a
point p2 on the target's side (outward normal n2 nearly perpendicular to the support normal
n_s: we never push a target into its support) with a pose of the pusher `gap` away from p2
along n2, facing it: the push direction is -n2 projected onto the support plane. A held
tool's pose T puts one of its own surface points p1 there (T p1 = p2 + gap n2, T n1 = -n2),
turned about n2 to keep the tool's current "up" as well as possible. A candidate is kept
only if the arm reaches the contact pose and a pre-contact pose backed off along n2 without
penetrating anything. Only shapes and poses are read, never names or categories.
"""
from __future__ import annotations

import time

from functools import lru_cache
from typing import TYPE_CHECKING, Iterator, Optional, Tuple

import numpy as np
import pybullet as p
import trimesh
from scipy.spatial.transform import Rotation

from ..world.collision import CollisionChecker
from ..world.robot import CLOSED
from .geometry import body_mesh, matrix_pose, pose_matrix, sample_surface
from .types import Contact

if TYPE_CHECKING:
    from ..world.world import World

SIDE_COS = 0.2          # |n2 . n_s| below this: a side of the target
FLARED_COS = 0.5        # ... or below this when no face qualifies (plates, bowls: rims at ~25 deg)
UP_COS = 0.2            # tool points whose normal keeps the tool's "up" within this
BACK = 0.05             # pre-contact: metres further back along n2
PENETRATION = 1e-3      # deeper than this counts as penetrating (tool vs world)
BATCH = 32              # target points drawn at a time
TOOL_POOL = 2048        # tool surface points drawn once per call
ANGLE_TRIES = 3         # rotations about n2 per pair: the best one, then perturbations
ANGLE_SPREAD = 0.3      # radians, std of those perturbations
# The closed Panda fingers in the gripper frame (measured from panda.urdf's finger meshes):
FINGER_HALF = 0.0105    # half their thickness along the frame's x axis
FINGER_TIP = 0.0072     # how far the fingertips reach beyond the frame origin along z
HAND_BACK = 0.039       # the hand's underside, behind the frame origin along z
IK_RESTARTS = 10        # fewer than IK's default: a failure costs ~70 ms at 30, most are out of reach


@lru_cache(maxsize=128)
def _face_weights(mesh: trimesh.Trimesh) -> np.ndarray:
    """Sampling weights per face: half by area, half uniform over planar regions, so that
    small faces of a shape (the inside of a hook's crook) are not drowned by big ones."""
    area = mesh.area_faces
    region_area = area.copy()
    for facet, facet_area in zip(mesh.facets, mesh.facets_area):
        region_area[facet] = facet_area
    regions = len(mesh.faces) - sum(len(f) for f in mesh.facets) + len(mesh.facets)
    weights = 0.5 * area / area.sum() + 0.5 * area / np.maximum(region_area, 1e-12) / regions
    return weights / weights.sum()


def surface_points(mesh: trimesh.Trimesh, count: int, rng: np.random.Generator) -> Tuple[np.ndarray, np.ndarray]:
    """`count` surface points (mesh frame) with outward normals, drawn by `_face_weights`."""
    return sample_surface(mesh, count, rng, _face_weights(mesh))


def support_frame(world: "World", target: str, support: str) -> Tuple[np.ndarray, np.ndarray]:
    """(n_s, a point of the support surface): the mean contact normal from `support` to
    `target` and the mean contact point on the support; +z and the top of the support's
    bounding box under the target when they are not within 2 cm."""
    a, b, client = world.bodies[target].id, world.bodies[support].id, world.client
    p.performCollisionDetection(physicsClientId=client)
    # A target resting a hair above its support has no contact points: use the closest ones.
    contacts = p.getContactPoints(a, b, physicsClientId=client) or p.getClosestPoints(a, b, 0.02, physicsClientId=client)
    if contacts:
        normal = np.mean([c[7] for c in contacts], axis=0)  # on B (support), from B to A
        if np.linalg.norm(normal) > 1e-6:
            return normal / np.linalg.norm(normal), np.mean([c[6] for c in contacts], axis=0)
    lo, hi = world.aabb(target)
    return np.array([0.0, 0.0, 1.0]), np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, world.aabb(support)[1][2]])


def _penetrates(world: "World", name: str) -> bool:
    """Does body `name`, where it is now, penetrate another body (the robot aside)?"""
    body_id = world.bodies[name].id
    for other in world.bodies.values():
        if other.id != body_id and any(c[8] < -PENETRATION for c in p.getClosestPoints(
                body_id, other.id, 0.0, physicsClientId=world.client)):
            return True
    return False


def _arm_reaches(world: "World", gripper: np.ndarray, back: np.ndarray, rng: np.random.Generator,
                 checker: CollisionChecker) -> bool:
    """IK for the gripper frame `gripper` (4x4) and for it moved by `back`, both free of
    collisions (the world's current fingers and held object)."""
    backed = gripper.copy()
    backed[:3, 3] += back
    if not (world.within_reach(gripper) and world.within_reach(backed)):
        return False
    pose = matrix_pose(gripper)
    q = world.kinematics.ik(pose[0], pose[1], rng, seed=world.arm(), restarts=IK_RESTARTS)
    if q is None or checker.collides(q):
        return False
    q_pre = world.kinematics.ik(np.add(pose[0], back), pose[1], rng, seed=q)
    return q_pre is not None and not checker.collides(q_pre)


def _rotation_between(a: np.ndarray, b: np.ndarray) -> Rotation:
    """The smallest rotation taking unit vector a to unit vector b."""
    axis = np.cross(a, b)
    sin, cos = np.linalg.norm(axis), float(np.dot(a, b))
    if sin < 1e-9:
        if cos > 0:
            return Rotation.identity()
        axis = np.cross(a, np.eye(3)[int(np.argmin(np.abs(a)))])  # any axis perpendicular to a
        return Rotation.from_rotvec(np.pi * axis / np.linalg.norm(axis))
    return Rotation.from_rotvec(axis / sin * np.arctan2(sin, cos))


def _gripper_contact(world: "World", p2: np.ndarray, d: np.ndarray, n_s: np.ndarray, level: float,
                     top: float, gap: float, rng: np.random.Generator) -> Optional[np.ndarray]:
    """The gripper frame (4x4) pushing at p2 with closed fingers, or None. Heights are along
    n_s above the support surface (`level`); `top` is the target's top."""
    h2 = float(np.dot(p2, n_s)) - level
    # Fingertips hit the side between 1 cm above the support and 5 mm below the target's top,
    # high enough that the hand (wider than the fingers along d) passes over the target.
    lo, hi = max(0.01, top - (FINGER_TIP + HAND_BACK) + 0.005), top - 0.005
    if hi < lo:  # a flat target: as high as its top allows, at least halfway up
        lo = hi = max(top / 2, hi)
    tip = float(np.clip(h2 - 0.01, lo, hi))
    if not tip - 0.002 <= h2 <= tip + FINGER_TIP + HAND_BACK - 0.002:
        return None  # the fingers would not touch the target at p2
    position = p2 - d * (gap + FINGER_HALF) + n_s * (tip + FINGER_TIP - h2)
    z = -n_s
    checker = CollisionChecker(world)
    back = -d * BACK
    with world.saved():
        world.set_fingers(CLOSED)
        for sign in rng.permutation([1.0, -1.0]):  # the hand's yaw either way round
            x = sign * d
            frame = np.eye(4)
            frame[:3, :3] = np.column_stack([x, np.cross(z, x), z])
            frame[:3, 3] = position
            if _arm_reaches(world, frame, back, rng, checker):
                return frame
    return None


def _tool_contact(world: "World", tool: str, p1: np.ndarray, n1: np.ndarray, p2: np.ndarray, n2: np.ndarray,
                  up: np.ndarray, tcp_in_tool: np.ndarray, gap: float, rng: np.random.Generator
                  ) -> Optional[np.ndarray]:
    """The tool pose (4x4) with T p1 = p2 + gap n2 and T n1 = -n2, or None."""
    r0 = _rotation_between(n1, -n2)
    # Turn about n2 so that the tool's up (tool frame) maps as close to world z as possible.
    v = r0.apply(up)
    v_perp, z_perp = v - np.dot(v, n2) * n2, np.array([0.0, 0.0, 1.0]) - n2[2] * n2
    best = float(np.arctan2(np.dot(n2, np.cross(v_perp, z_perp)), np.dot(v_perp, z_perp)))
    angles = [best] + list(best + rng.normal(0.0, ANGLE_SPREAD, ANGLE_TRIES - 1))
    checker = CollisionChecker(world)
    back = n2 * BACK
    with world.saved():
        for angle in angles:
            pose = np.eye(4)
            pose[:3, :3] = (Rotation.from_rotvec(angle * n2) * r0).as_matrix()
            pose[:3, 3] = p2 + gap * n2 - pose[:3, :3] @ p1
            backed = pose.copy()
            backed[:3, 3] += back
            world.set_pose(tool, matrix_pose(pose))
            if _penetrates(world, tool):
                continue
            world.set_pose(tool, matrix_pose(backed))
            if _penetrates(world, tool):
                continue
            if _arm_reaches(world, pose @ tcp_in_tool, back, rng, checker):
                return pose
    return None


def sample_contacts(world: "World", target: str, support: str, rng: np.random.Generator,
                    max_attempts: int = 300, gap: float = 0.01,
                    deadline: float = float("inf")) -> Iterator[Contact]:
    """Reachable, collision-free contacts of the held object (or the bare gripper) with the
    side of `target`, which rests on `support`; stops after `max_attempts` candidates (one
    target point each, with a tool point when a tool is held) or at `deadline`
    (time.perf_counter()). The world is left as found."""
    tool = world.attachment.name if world.attachment is not None else None
    target_mesh = body_mesh(world, target)
    if tool is not None:
        tool_points, tool_normals = surface_points(body_mesh(world, tool), TOOL_POOL, rng)
        tcp_in_tool = pose_matrix(world.held_tcp_in_object())
    attempts = 0
    while attempts < max_attempts:
        # Re-read the scene per batch: the caller may move things between yields.
        n_s, support_point = support_frame(world, target, support)
        level = float(np.dot(support_point, n_s))
        target_pose = pose_matrix(world.pose(target))
        world_vertices = target_mesh.vertices @ target_pose[:3, :3].T + target_pose[:3, 3]
        top = float(np.max(world_vertices @ n_s)) - level
        tilt = np.abs(target_mesh.face_normals @ (target_pose[:3, :3].T @ n_s))
        side_cos = SIDE_COS if np.any(tilt < SIDE_COS) else FLARED_COS
        if tool is not None:
            up = pose_matrix(world.pose(tool))[:3, :3].T @ np.array([0.0, 0.0, 1.0])
        count = min(BATCH, max_attempts - attempts)
        local_points, local_normals = surface_points(target_mesh, count, rng)
        points = local_points @ target_pose[:3, :3].T + target_pose[:3, 3]
        normals = local_normals @ target_pose[:3, :3].T
        for p2, n2 in zip(points, normals):
            attempts += 1
            if time.perf_counter() > deadline:
                return
            if abs(float(np.dot(n2, n_s))) >= side_cos:
                continue
            d = -(n2 - np.dot(n2, n_s) * n_s)
            d /= np.linalg.norm(d)
            if tool is None:
                frame = _gripper_contact(world, p2, d, n_s, level, top, gap, rng)
            else:
                # Tool faces that can meet n2 while the tool keeps its up: n1 . up = -n2 . z.
                usable = np.flatnonzero(np.abs(tool_normals @ up + n2[2]) < UP_COS)
                if not len(usable):
                    continue
                i = int(rng.choice(usable))
                frame = _tool_contact(world, tool, tool_points[i], tool_normals[i], p2, n2, up,
                                      tcp_in_tool, gap, rng)
            if frame is not None:
                yield Contact(tool, target, support, matrix_pose(frame), tuple(float(v) for v in d),
                              tuple(float(v) for v in p2), tuple(float(v) for v in n2))
