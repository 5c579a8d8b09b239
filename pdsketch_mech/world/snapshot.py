"""Save and restore a world's dynamic state, so that simulating on from a restored snapshot
is the same as simulating on in a fresh world that reached that state.

What is saved: every movable body's base pose and velocity, every robot joint's position
and velocity, the motor targets, and what is held (with its grasp). Fixed bodies never move.

PyBullet keeps state that no getter shows and that changes what the next steps simulate:
contact manifolds (solver warm-start), the broadphase's pair order, a constraint's
accumulated impulses. Restoring poses alone leaks them between branches of a search (a
pushed plate ended up 5 mm elsewhere; PyBullet's own saveState/restoreState misses them
too, measured 3–6 mm). So a restore also *canonicalises* the simulator: every collision
object is re-registered with the broadphase (dropping its cached contacts) in a fixed order,
and the grasp constraint is re-created. The planner and replay both start every step from
a restore, so both see the same canonical state. The world also solves contact pairs in
sorted order and never lets bodies sleep (world.py): the broadphase's discovery order and
a body's sleep timer are state no snapshot can read.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Optional, Sequence, Tuple

import pybullet as p

from .attachment import Attachment, create_attachment, release
from .robot import Pose

BodyState = Tuple[int, Tuple[float, ...], Tuple[float, ...], Tuple[float, ...], Tuple[float, ...]]

# Collision groups: fixed bodies (the table, the robot's bolted base) never collide with
# each other; everything else collides with everything.
DYNAMIC, STATIC = 1, 2
# While the arm's configurations are checked (collision.py), only the arm and what it holds
# need contacts: objects resting on the table or on each other are left out of the narrow
# phase (a plate on a ledge, both concave, cost 9/10 of a check's time).
ARM, HELD = 4, 8
Collider = Tuple[int, int, int, int]   # body id, link index, group, mask


@dataclass(frozen=True)
class Snapshot:
    bodies: Tuple[BodyState, ...]
    joints: Tuple[Tuple[float, float], ...]
    arm_targets: Tuple[float, ...]
    finger_target: float
    held: Optional[Tuple[str, Pose]]    # the held object and its grasp (link frame in the hand frame)


def collider_groups(robot: int, fixed: Dict[int, bool], client: int) -> Tuple[Collider, ...]:
    """The canonical collision group and mask of every collision object, in a fixed order."""
    out = []
    for body_id, is_fixed in sorted(fixed.items()):
        out.append((body_id, -1, STATIC, DYNAMIC) if is_fixed else (body_id, -1, DYNAMIC, DYNAMIC | STATIC))
    out.append((robot, -1, STATIC, DYNAMIC))
    for link in range(p.getNumJoints(robot, physicsClientId=client)):
        out.append((robot, link, DYNAMIC, DYNAMIC | STATIC))
    return tuple(out)


def set_check_groups(colliders: Sequence[Collider], robot: int, held: int, client: int) -> None:
    """Collision groups for checking arm configurations: the arm's links against everything,
    the held body `held` (-1: none) against everything but the arm, the rest only against
    those two (a pair collides under PyBullet's AND and OR filter modes alike, and pairs of
    the rest under neither). `reset_contact_caches` puts the canonical groups back."""
    for body_id, link, group, _ in colliders:
        if body_id == robot and link >= 0:
            group, mask = ARM, ARM | DYNAMIC | STATIC
        elif body_id == held:
            group, mask = HELD, DYNAMIC | STATIC
        else:
            mask = ARM | HELD
        p.setCollisionFilterGroupMask(body_id, link, group, mask, physicsClientId=client)


def reset_contact_caches(colliders: Sequence[Collider], client: int) -> None:
    """Drop every cached contact (~0.1 ms for a tabletop): with all collisions filtered out,
    one collision detection pass deletes every overlapping pair and its contact manifold;
    then the canonical groups come back, in a fixed order."""
    for body_id, link, _, _ in colliders:
        p.setCollisionFilterGroupMask(body_id, link, 0, 0, physicsClientId=client)
    p.performCollisionDetection(physicsClientId=client)
    for body_id, link, group, mask in colliders:
        p.setCollisionFilterGroupMask(body_id, link, group, mask, physicsClientId=client)


def take_snapshot(client: int, robot: int, movable_ids: Sequence[int], attachment: Optional[Attachment],
                  arm_targets: Sequence[float], finger_target: float) -> Snapshot:
    bodies = []
    for body_id in movable_ids:
        pos, orn = p.getBasePositionAndOrientation(body_id, physicsClientId=client)
        lin, ang = p.getBaseVelocity(body_id, physicsClientId=client)
        bodies.append((body_id, pos, orn, lin, ang))
    n_joints = p.getNumJoints(robot, physicsClientId=client)
    joints = tuple((s[0], s[1]) for s in p.getJointStates(robot, range(n_joints), physicsClientId=client))
    held = (attachment.name, attachment.in_hand) if attachment else None
    return Snapshot(tuple(bodies), joints, tuple(float(v) for v in arm_targets), float(finger_target), held)


def restore_snapshot(client: int, robot: int, snapshot: Snapshot, attachment: Optional[Attachment],
                     body_ids: Dict[str, int], inertials: Dict[str, Pose], hand_inertial: Pose,
                     colliders: Sequence[Collider]) -> Optional[Attachment]:
    """Put the simulator back in the snapshot's state, canonically; returns the attachment
    now in force (re-created, so its solver state is fresh)."""
    if attachment is not None:
        release(client, attachment)
    for body_id, pos, orn, lin, ang in snapshot.bodies:
        p.resetBasePositionAndOrientation(body_id, pos, orn, physicsClientId=client)
        p.resetBaseVelocity(body_id, lin, ang, physicsClientId=client)
    for j, (position, velocity) in enumerate(snapshot.joints):
        p.resetJointState(robot, j, position, velocity, physicsClientId=client)
    reset_contact_caches(colliders, client)
    if snapshot.held is None:
        return None
    # The saved grasp, not the nominal one the object was picked with, and the object
    # stays where it was saved: nothing is teleported on re-attaching.
    name, in_hand = snapshot.held
    return create_attachment(client, robot, name, body_ids[name], inertials[name], in_hand, hand_inertial)
