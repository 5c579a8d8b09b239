"""What samplers yield: small frozen dataclasses, all poses as ((x, y, z), (qx, qy, qz, qw))."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional, Tuple

import numpy as np

Vec3 = Tuple[float, float, float]
Pose = Tuple[Vec3, Tuple[float, float, float, float]]


@dataclass(frozen=True)
class Grasp:
    """The gripper frame (panda_grasptarget: z = approach, y = closing axis) in the object's
    frame, and the distance between the two contact surfaces."""

    object: str
    in_object: Pose
    width: float
    points: Tuple[Vec3, Vec3] = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))  # the antipodal pair, object frame


@dataclass(frozen=True)
class Placement:
    """Where the held object goes: its world pose just above `support`'s surface."""

    object: str
    support: str
    pose: Pose
    support_normal: Vec3 = (0.0, 0.0, 1.0)


@dataclass(frozen=True)
class Contact:
    """A pusher (the held object, or the bare gripper when `pusher` is None) touching `target`.

    `pusher_pose` is the world pose of the pusher at first contact: the held object's pose,
    or the gripper frame's pose for the bare gripper. `direction` is the (unit) push
    direction in the world, opposite the target's surface normal at the contact."""

    pusher: Optional[str]
    target: str
    support: str
    pusher_pose: Pose
    direction: Vec3
    point: Vec3           # contact point on the target, world frame
    normal: Vec3          # target surface normal there, world frame (points out of the target)


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Joint-space waypoints, split into a free approach and a final straight segment
    (approach to a grasp, descent to a placement, or a push), and a retreat."""

    kind: str                                 # "free", "grasp", "place", "held", "push"
    approach: np.ndarray                      # (n, 7) from the current configuration
    final: np.ndarray = field(default_factory=lambda: np.zeros((0, 7)))
    retreat: np.ndarray = field(default_factory=lambda: np.zeros((0, 7)))
    push_distance: Optional[float] = None

    def waypoints(self) -> np.ndarray:
        parts = [a for a in (self.approach, self.final, self.retreat) if len(a)]
        return np.concatenate(parts) if parts else np.zeros((0, 7))


def approach_axis(tcp: Pose) -> np.ndarray:
    """The gripper frame's z axis (the approach direction) in the world."""
    import pybullet as p   # here, not above: reading a plan's values needs no simulator
    # PyBullet's own rotation, not a numpy formula: the last bits differ, and plans follow them.
    return np.array(p.getMatrixFromQuaternion(tcp[1])).reshape(3, 3)[:, 2]


# The basis operators and the values each is executed with (its trajectory last).
OPERATOR_VALUES = {"transit": (Trajectory,), "move": (Trajectory,), "grasp": (Grasp, Trajectory),
                   "place": (Placement, Trajectory), "transit-cont": (Contact, Trajectory),
                   "move-cont": (Contact, Trajectory)}
