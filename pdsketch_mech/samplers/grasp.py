"""The generic grasp sampler G(O, T_o) (paper Appendix "Samplers for Generic Operations").

Antipodal pairs come from the object's shape alone: a surface point p1 with outward normal
n1, and the point p2 where a ray from just inside p1 along -n1 leaves the solid. The
gripper frame (panda_grasptarget: z = approach, y = closing axis) sits at their midpoint
with y along p2 - p1 and a random approach about y; a candidate is kept only if the arm
reaches it and a pre-grasp pose behind it without touching anything, fingers open.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Iterator, Optional, Tuple

import numpy as np
import pybullet as p
import trimesh

from ..world.collision import CollisionChecker
from ..world.robot import MAX_OPENING
from .geometry import Pose, body_mesh, matrix_pose, pose_matrix, sample_surface
from .types import Grasp

if TYPE_CHECKING:
    from ..world.world import World

ANTIPODAL_COS = float(np.cos(np.radians(15.0)))
MIN_WIDTH, MAX_WIDTH = 0.005, 0.075
PRE_GRASP = 0.08        # metres back along -approach
MAX_UP = 0.3            # largest world z-component of the approach: none from below
INSIDE = 1e-4           # ray origins start this far inside the surface
BATCH = 32              # surface points per ray-casting batch
ANGLE_TRIES = 8         # approach angles drawn per pair before giving it up as "from below"
# IK restarts for a candidate: a hard pose is dropped, drawing another candidate is cheaper
# (10 restarts keep ~92 % of the poses 30 find, in about half the time).
IK_RESTARTS = 10


def antipodal_pairs(mesh: trimesh.Trimesh, count: int, rng: np.random.Generator
                    ) -> Iterator[Optional[Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]]:
    """For `count` sampled surface points, (p1, n1, p2, n2) if the point has an antipodal
    partner within the gripper's range, else None (one item per sample, for budgeting)."""
    p1, n1 = sample_surface(mesh, count, rng)
    tri, ray, hits = mesh.ray.intersects_id(p1 - INSIDE * n1, -n1, multiple_hits=False, return_locations=True)
    found = {int(r): (int(t), h) for t, r, h in zip(tri, ray, hits)}
    for i in range(count):
        if i not in found:
            yield None
            continue
        face, p2 = found[i]
        n2 = mesh.face_normals[face]
        width = float(np.linalg.norm(p2 - p1[i]))
        ok = float(np.dot(n1[i], n2)) < -ANTIPODAL_COS and MIN_WIDTH <= width <= MAX_WIDTH
        yield (p1[i], n1[i], p2, n2) if ok else None


def gripper_frame(p1: np.ndarray, p2: np.ndarray, angle: float) -> np.ndarray:
    """4x4 gripper frame in the object frame: origin at the midpoint, y along p2 - p1,
    z (approach) at `angle` about y."""
    y = (p2 - p1) / np.linalg.norm(p2 - p1)
    helper = np.eye(3)[int(np.argmin(np.abs(y)))]  # the axis least parallel to y
    a = np.cross(y, helper)
    a /= np.linalg.norm(a)
    b = np.cross(y, a)
    z = np.cos(angle) * a + np.sin(angle) * b
    frame = np.eye(4)
    frame[:3, :3] = np.column_stack([np.cross(y, z), y, z])
    frame[:3, 3] = (p1 + p2) / 2
    return frame


def world_grasp_pose(world: "World", grasp: Grasp) -> Pose:
    """The gripper frame in the world for `grasp` at the object's current pose."""
    pos, orn = p.multiplyTransforms(*world.pose(grasp.object), *grasp.in_object)
    return tuple(pos), tuple(orn)


def offset_along_z(pose: Pose, distance: float) -> Pose:
    """`pose` moved `distance` along its own z axis (negative: back from the approach)."""
    matrix = pose_matrix(pose)
    return tuple(float(v) for v in matrix[:3, 3] + distance * matrix[:3, 2]), pose[1]


def grasp_configurations(world: "World", grasp: Grasp, rng: np.random.Generator,
                         check_collisions: bool = True) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """(pre-grasp, grasp) arm configurations for `grasp` at the object's current pose, or
    None if either has no IK or (with `check_collisions`) touches anything, fingers open."""
    kin = world.kinematics
    target = world_grasp_pose(world, grasp)
    q = kin.ik(target[0], target[1], rng, restarts=IK_RESTARTS)
    if q is None:
        return None
    checker = CollisionChecker(world) if check_collisions else None
    with world.saved():
        world.set_fingers(MAX_OPENING / 2)
        if checker is not None and checker.collides(q):
            return None
        pre = offset_along_z(target, -PRE_GRASP)
        q_pre = kin.ik(pre[0], pre[1], rng, seed=q)  # seeded: the retreat is a short straight line
        if q_pre is None or (checker is not None and checker.collides(q_pre)):
            return None
    return q_pre, q


# Corners of the open fingers' boxes in the gripper frame (x across a finger, y along the
# closing axis, z along the approach: the tips reach 7.2 mm past the frame origin).
_FINGER_CORNERS = np.array([[x, y, z, 1.0] for x in (-0.0105, 0.0105) for y in (-0.05, -0.04, 0.04, 0.05)
                            for z in (-0.045, 0.0072)])


def _fingers_clear_of_support(world: "World", obj: str, world_frame: np.ndarray, bottom: float) -> bool:
    """No fingertip below the object's lowest point sits under another body's surface (the
    support): one batched ray cast down to each such corner, which spares an IK solve
    (~0.1 s when it fails) for grasps whose fingers would dig into the table. Under an
    overhang nothing is hit, so a plate pushed past the edge stays graspable."""
    corners = (world_frame @ _FINGER_CORNERS.T)[:3].T
    low = corners[corners[:, 2] < bottom - 0.002]
    if not len(low):
        return True
    starts = [(x, y, bottom + 0.01) for x, y, _ in low]
    hits = p.rayTestBatch(starts, [tuple(c) for c in low], physicsClientId=world.client)
    ignore = {world.bodies[obj].id, world.robot, -1}
    return all(hit[0] in ignore for hit in hits)


def sample_grasps(world: "World", obj: str, rng: np.random.Generator, max_attempts: int = 300) -> Iterator[Grasp]:
    """Reachable, collision-free antipodal grasps of `obj` at its current pose; stops after
    `max_attempts` sampled surface points."""
    mesh = body_mesh(world, obj)
    attempts = 0
    while attempts < max_attempts:
        count = min(BATCH, max_attempts - attempts)
        for pair in antipodal_pairs(mesh, count, rng):
            attempts += 1
            if pair is None:
                continue
            p1, _, p2, _ = pair
            frame = None
            placed = pose_matrix(world.pose(obj))  # the caller may move things between yields
            rotation = placed[:3, :3]
            bottom = float((mesh.vertices @ rotation.T + placed[:3, 3])[:, 2].min())
            for _ in range(ANGLE_TRIES):
                candidate = gripper_frame(p1, p2, rng.uniform(-np.pi, np.pi))
                if (rotation @ candidate[:3, 2])[2] <= MAX_UP:
                    frame = candidate
                    break
            if frame is None or not world.within_reach(placed @ frame) or \
                    not _fingers_clear_of_support(world, obj, placed @ frame, bottom):
                continue
            grasp = Grasp(obj, matrix_pose(frame), float(np.linalg.norm(p2 - p1)),
                          (tuple(float(v) for v in p1), tuple(float(v) for v in p2)))
            if grasp_configurations(world, grasp, rng) is not None:
                yield grasp
