"""Sampler values as fixed-layout numbers: what self-play stores and what classifiers read.

The same encoding serves both sides, so that a classifier scores a proposal at planning time
exactly as it saw the values it was trained on. Proposals that are not values yet (a contact
candidate tries several pusher poses) are encoded as the value their first try would give.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Dict, List, Optional, Tuple

import numpy as np

from ...world.values import Contact, Grasp, Placement, Trajectory
from ..contact import ContactCandidate
from ..geometry import matrix_pose

if TYPE_CHECKING:
    from ...world.world import World

VALUE_WIDTH = 16      # the widest layout; stored rows are NaN-padded to it

# The numeric form of each kind of value, column by column (README "Self-play" repeats it).
VALUE_LAYOUT: Dict[str, Tuple[str, ...]] = {
    "grasp": ("x", "y", "z", "qx", "qy", "qz", "qw", "width"),  # gripper pose in the object's frame
    "contact": ("px", "py", "pz", "pqx", "pqy", "pqz", "pqw",  # pusher pose, world frame
                "cx", "cy", "cz", "nx", "ny", "nz", "dx", "dy", "dz"),  # point, normal, direction
    "placement": ("x", "y", "z", "qx", "qy", "qz", "qw"),  # the object's world pose
    "trajectory": ("q0", "q1", "q2", "q3", "q4", "q5", "q6",  # joints at the end of the final segment
                   "x", "y", "z", "qx", "qy", "qz", "qw",  # the gripper (TCP) pose there, world frame
                   "push"),  # push distance (NaN when not a push)
    # A push's trajectory as a classifier sees it: the one choice a push sampler makes (the
    # motion to the contact is planned, the straight push follows the contact's direction).
    "push": ("distance",),
}

# Kinds a classifier can rank before verification: their proposals carry the whole value.
RANKABLE = ("grasp", "contact", "placement", "push")


def pose_array(pose) -> List[float]:
    """A ((x, y, z), (qx, qy, qz, qw)) pose as 7 numbers, the quaternion with qw >= 0 (q and
    -q are the same rotation; one sign keeps the numbers a function of the pose)."""
    (x, y, z), q = pose
    q = [float(v) for v in q]
    if q[3] < 0:
        q = [-v for v in q]
    return [float(x), float(y), float(z)] + q


# A fixed body weighs this much as a classifier sees it: immovable, whatever its file says.
FIXED_MASS_KG = 1000.0
MIN_MASS_KG = 1e-3


def mass_features(world: "World", names) -> np.ndarray:
    """(len(names),) the log of each body's mass in kg, as self-play records it. Which object
    can tip a lever is told by its weight, not its shape: a task's heavy object and its
    distractors are drawn from the same categories. (No classifier reads it yet: reading it
    changed no Lever plan; results/HISTORY.md, 2026-11-28.)"""
    masses = [FIXED_MASS_KG if world.bodies[n].fixed else max(world.mass(n), MIN_MASS_KG) for n in names]
    return np.log(np.asarray(masses, dtype=float))


def encode_value(world: "World", value: object) -> Tuple[str, np.ndarray]:
    """(kind, numbers) for a sampler's value; the layout is VALUE_LAYOUT[kind]."""
    if isinstance(value, Grasp):
        return "grasp", np.array(pose_array(value.in_object) + [value.width])
    if isinstance(value, Contact):
        return "contact", np.array(pose_array(value.pusher_pose) + list(value.point) + list(value.normal)
                                   + list(value.direction))
    if isinstance(value, Placement):
        return "placement", np.array(pose_array(value.pose))
    if isinstance(value, Trajectory):
        # The end of the final segment is where the trajectory acts (the grasp, the placement,
        # the push's end); the retreat after it carries no choice.
        ends = [part for part in (value.final, value.approach) if len(part)]
        q = np.asarray(ends[0][-1], dtype=float) if ends else np.full(7, np.nan)
        tcp = pose_array(world.kinematics.fk(q)) if ends else [np.nan] * 7
        push = np.nan if value.push_distance is None else float(value.push_distance)
        return "trajectory", np.concatenate([q, tcp, [push]])
    raise TypeError(f"cannot encode a value of type {type(value).__name__}")


def encode_as(world: "World", value: object, kind: str) -> np.ndarray:
    """The numbers of a value in the layout of `kind` (a push trajectory as a "push")."""
    if kind == "push":
        return np.array([np.nan if getattr(value, "push_distance", None) is None else value.push_distance])
    return encode_value(world, value)[1]


def encode_proposal(world: "World", proposal: object) -> Optional[np.ndarray]:
    """The numbers of the value a proposal becomes if it verifies (None: not rankable)."""
    if isinstance(proposal, (Grasp, Contact, Placement)):
        return encode_value(world, proposal)[1]
    if isinstance(proposal, float):  # samplers/trajectory.py PushMotionSampler: a push distance
        return np.array([proposal])
    if isinstance(proposal, ContactCandidate) and proposal.pushers:
        return np.array(pose_array(matrix_pose(proposal.pushers[0])) + list(proposal.point)
                        + list(proposal.normal) + list(proposal.direction))
    return None


def proposal_row(world: "World", proposal: object) -> Optional[Tuple[str, np.ndarray]]:
    """(stored kind, numbers in VALUE_LAYOUT[kind]) of a proposal, as self-play stores it: a
    push distance as a trajectory row holding only its distance (`row_kind` reads it back as
    a "push"). None: the proposal is not rankable."""
    numbers = encode_proposal(world, proposal)
    if numbers is None:
        return None
    if isinstance(proposal, float):
        row = np.full(len(VALUE_LAYOUT["trajectory"]), np.nan)
        row[-1] = numbers[0]
        return "trajectory", row
    kind = "contact" if isinstance(proposal, ContactCandidate) else encode_value(world, proposal)[0]
    return kind, numbers
