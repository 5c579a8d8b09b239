"""The Franka Panda: joints, forward and inverse kinematics, and the gripper.

IK runs in a private kinematics-only PyBullet client holding just the arm, so solving never
disturbs the simulated world. Every IK answer is verified with forward kinematics and the
joint limits (PyBullet's solver can return angles outside them).
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

import numpy as np
import pybullet as p
import pybullet_data

PANDA_URDF = os.path.join(pybullet_data.getDataPath(), "franka_panda", "panda.urdf")
ARM_JOINTS = tuple(range(7))
FINGER_JOINTS = (9, 10)
HAND_LINK = 8            # panda_hand: attachments are made to it
TCP_LINK = 11            # panda_grasptarget: the point between the fingertips
HOME = (0.0, -0.5, 0.0, -2.2, 0.0, 1.7, 0.785)
MAX_OPENING = 0.08       # metres between the fingers, fully open
GRASP_CLEARANCE = 0.02   # the fingers open this much wider than the object before closing
CLOSED = 0.002           # finger half-width when "closed" on nothing: at 0 the finger meshes overlap
SHOULDER = 0.333         # joint 2 above the base
WRIST = 0.21             # the flange, behind the gripper frame along its z axis
REACH = 0.82             # no flange is farther than this from the shoulder (FK samples: 0.808)

Pose = Tuple[Tuple[float, float, float], Tuple[float, float, float, float]]  # (xyz, quaternion xyzw)

# The pedestal the arm is bolted to, in the base frame: from the floor (the table is 0.75 m
# high) up to just under the base link, a little wider than its footprint, and clear of the
# table's near edge (0.1 m in front of the base).
MOUNT_MIN = (-0.17, -0.11, -0.75)
MOUNT_MAX = (0.08, 0.11, -0.002)
MOUNT_RGBA = (0.35, 0.35, 0.38, 1.0)


def rotation_angle(a: Sequence[float], b: Sequence[float]) -> float:
    """The angle (radians) of the rotation between unit quaternions `a` and `b`."""
    # Plain floats: IK asks this after every solver call (scipy's Rotation cost ~50 us a time).
    return 2.0 * math.acos(min(1.0, abs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3])))


def load_panda(client: int, base: Pose = ((0, 0, 0), (0, 0, 0, 1)), self_collision: bool = True,
               visual: bool = True, collision: bool = True) -> int:
    """Load the arm with self-collision between non-adjacent links (DESIGN.md: the
    EXCLUDE_PARENT flag keeps it; EXCLUDE_ALL_PARENTS would disable it on a serial arm).
    Without `visual` the meshes only a camera sees are not read (5/6 of loading the arm);
    without `collision` it is a kinematic chain only (IK and FK)."""
    flags = p.URDF_USE_SELF_COLLISION | p.URDF_USE_SELF_COLLISION_EXCLUDE_PARENT if self_collision else 0
    flags |= 0 if visual else p.URDF_IGNORE_VISUAL_SHAPES
    flags |= 0 if collision else p.URDF_IGNORE_COLLISION_SHAPES
    return p.loadURDF(PANDA_URDF, base[0], base[1], useFixedBase=True, flags=flags, physicsClientId=client)


def load_mount(client: int, base: Pose = ((0, 0, 0), (0, 0, 0, 1)), visual: bool = True) -> int:
    """The pedestal under the arm's base: a static box, in the physics, in collision checks
    and in renders (a robot floating beside the table would let the arm pass where its
    column stands)."""
    half = [(hi - lo) / 2 for lo, hi in zip(MOUNT_MIN, MOUNT_MAX)]
    centre = [(hi + lo) / 2 for lo, hi in zip(MOUNT_MIN, MOUNT_MAX)]
    position, orientation = p.multiplyTransforms(base[0], base[1], centre, (0, 0, 0, 1))
    shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=client)
    look = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=MOUNT_RGBA,
                               physicsClientId=client) if visual else -1
    return p.createMultiBody(0.0, shape, look, position, orientation, physicsClientId=client)


def disable_touching_self_pairs(client: int, robot: int) -> List[Tuple[int, int]]:
    """Turn off self-collision for robot link pairs already touching at the current (home)
    configuration: the hand and fingers overlap by design."""
    p.performCollisionDetection(physicsClientId=client)
    pairs = sorted({tuple(sorted((c[3], c[4])))
                    for c in p.getContactPoints(robot, robot, physicsClientId=client)
                    if c[8] < 0})
    for a, b in pairs:
        p.setCollisionFilterPair(robot, robot, a, b, 0, physicsClientId=client)
    return pairs


@dataclass(frozen=True)
class JointLimits:
    lower: np.ndarray
    upper: np.ndarray

    def contains(self, q: Sequence[float], tol: float = 1e-6) -> bool:
        q = np.asarray(q)
        return bool(np.all(q >= self.lower - tol) and np.all(q <= self.upper + tol))

    def sample(self, rng: np.random.Generator) -> np.ndarray:
        return rng.uniform(self.lower, self.upper)


def joint_limits(body: int, client: int) -> JointLimits:
    info = [p.getJointInfo(body, j, physicsClientId=client) for j in ARM_JOINTS]
    return JointLimits(np.array([i[8] for i in info]), np.array([i[9] for i in info]))


class Kinematics:
    """FK and IK for the gripper frame, in a client of its own."""

    def __init__(self, base: Pose = ((0, 0, 0), (0, 0, 0, 1))):
        self.client = p.connect(p.DIRECT)
        self.body = load_panda(self.client, base, self_collision=False, visual=False, collision=False)
        self.limits = joint_limits(self.body, self.client)
        self._ranges = list(self.limits.upper - self.limits.lower)

    def close(self) -> None:
        if self.client >= 0:
            p.disconnect(self.client)
            self.client = -1

    def _set(self, q: Sequence[float]) -> None:
        # One multi-joint call: seven resetJointState calls were a sixth of IK's time.
        p.resetJointStatesMultiDof(self.body, ARM_JOINTS, [[float(v)] for v in q], physicsClientId=self.client)

    def fk(self, q: Sequence[float], link: int = TCP_LINK) -> Pose:
        """World pose of `link` (default: the gripper frame) at joint angles `q`."""
        self._set(q)
        return self._link_pose(link)

    def _link_pose(self, link: int = TCP_LINK) -> Pose:
        state = p.getLinkState(self.body, link, computeForwardKinematics=True, physicsClientId=self.client)
        return tuple(state[4]), tuple(state[5])

    def ik(self, position: Sequence[float], orientation: Sequence[float], rng: np.random.Generator,
           seed: Optional[Sequence[float]] = None, restarts: int = 30, chain: int = 3,
           pos_tol: float = 0.005, ang_tol: float = 0.05) -> Optional[np.ndarray]:
        """Joint angles placing the gripper frame at the pose, or None.

        Each attempt chains `chain` solver calls from a start (the seed, home, then random
        configurations) and is accepted only if FK agrees within the tolerances (metres,
        radians) and the angles are within the joint limits. Many short attempts beat a few
        long ones (`bench world`: 30 x 3 reaches 99 % of side grasps, 12 x 4 only 92 %).
        """
        starts: List[Sequence[float]] = [s for s in (seed, HOME) if s is not None]
        norm = math.sqrt(sum(v * v for v in orientation))
        target = tuple(float(v) / norm for v in orientation)
        for attempt in range(restarts):
            start = starts[attempt] if attempt < len(starts) else self.limits.sample(rng)
            self._set(start)
            q = np.asarray(start, dtype=float)
            for _ in range(chain):
                solution = p.calculateInverseKinematics(
                    self.body, TCP_LINK, list(position), list(orientation),
                    lowerLimits=list(self.limits.lower), upperLimits=list(self.limits.upper),
                    jointRanges=self._ranges, restPoses=list(q), maxNumIterations=100,
                    residualThreshold=1e-5, physicsClientId=self.client)
                q = np.clip(np.asarray(solution[:7]), self.limits.lower, self.limits.upper)
                self._set(q)
                pos, orn = self._link_pose()
                if math.dist(pos, position) <= pos_tol and rotation_angle(orn, target) <= ang_tol:
                    return q
        return None


def grasp_opening(width: float) -> float:
    """How far apart the fingers are before they close on an object `width` thick."""
    return min(MAX_OPENING, width + GRASP_CLEARANCE)
