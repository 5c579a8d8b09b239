"""What the hand holds: the object, its pose in the hand frame, and the constraint holding it.

This is the one home of grasp frames; the world, collision checking and snapshots import it.

PyBullet expresses a constraint's `parentFramePosition`/`childFramePosition` (and
orientations) in each link's *inertial* (centre-of-mass) frame, not the URDF link frame
(DESIGN.md). Both the Panda hand and many assets have offset inertial frames, so the
constraint frame is converted here: get it wrong and a held spoon hangs centimetres below
the sampled grasp.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Tuple

import pybullet as p

from .robot import HAND_LINK, Pose

CONSTRAINT_FORCE = 2000.0  # newtons: holds a tool that pushes a heavy box without sagging


@dataclass(frozen=True)
class Attachment:
    """`name` (PyBullet body `body_id`) is held with its link frame at `in_hand` in the hand
    link frame; `constraint` is the PyBullet constraint id doing it."""

    name: str
    body_id: int
    in_hand: Pose
    constraint: int


def compose(a: Pose, b: Pose) -> Pose:
    pos, orn = p.multiplyTransforms(a[0], a[1], b[0], b[1])
    return tuple(pos), tuple(orn)


def invert(a: Pose) -> Pose:
    pos, orn = p.invertTransform(a[0], a[1])
    return tuple(pos), tuple(orn)


def hand_inertial(client: int, robot: int) -> Pose:
    """The hand link's centre-of-mass frame in its URDF link frame."""
    info = p.getDynamicsInfo(robot, HAND_LINK, physicsClientId=client)
    return tuple(info[3]), tuple(info[4])


def create_attachment(client: int, robot: int, name: str, body_id: int, body_inertial: Pose,
                      in_hand: Pose, hand_com: Pose) -> Attachment:
    """A fixed constraint keeping the object's link frame at `in_hand` in the hand link frame
    (`body_inertial`, `hand_com`: the object's and the hand's centre-of-mass frames in their
    link frames)."""
    # Constraint frames are relative to the COM frames: hand COM -> hand link -> object link -> object COM.
    parent = compose(compose(invert(hand_com), in_hand), body_inertial)
    constraint = p.createConstraint(robot, HAND_LINK, body_id, -1, p.JOINT_FIXED, (0, 0, 0),
                                    parent[0], (0, 0, 0), parent[1], (0, 0, 0, 1), physicsClientId=client)
    p.changeConstraint(constraint, maxForce=CONSTRAINT_FORCE, physicsClientId=client)
    return Attachment(name, body_id, (tuple(in_hand[0]), tuple(in_hand[1])), constraint)


def release(client: int, attachment: Attachment) -> None:
    p.removeConstraint(attachment.constraint, physicsClientId=client)


def held_pose(hand: Pose, attachment: Attachment) -> Pose:
    """Where the held object's link frame is when the hand link is at `hand`."""
    return compose(hand, attachment.in_hand)


def relative_pose(frame: Pose, pose: Pose) -> Tuple[Tuple[float, ...], Tuple[float, ...]]:
    """`pose` expressed in `frame`."""
    return compose(invert(frame), pose)
