"""Collision checking of arm configurations: arm vs world, self-collision, held object vs world.

A check teleports the arm (and the held object) in the world itself, so it changes the
world state: callers that must not disturb the simulation wrap checks in `world.saved()`.
PyBullet also reports near-contacts inside its margin; only penetrations deeper than
`PENETRATION` count (DESIGN.md).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Collection, Dict, Iterable, Iterator, Mapping, Optional, Sequence, Tuple

import pybullet as p

from .robot import ARM_JOINTS

if TYPE_CHECKING:
    from .world import World

PENETRATION = 5e-4  # metres


class CollisionChecker:
    """`collides(q)`: would the arm at `q` (holding what the world holds) penetrate anything
    other than the bodies in `ignore`?"""

    def __init__(self, world: "World", ignore: Iterable[str] = (), check_held: bool = True):
        self.world = world
        self.ignore_ids = {world.bodies[name].id for name in ignore}
        self.check_held = check_held
        self.checks = 0

    def collides(self, q: Sequence[float]) -> bool:
        world, client = self.world, self.world.client
        self.checks += 1
        # One multi-joint call: per-joint resets cost ~40% of the check's time.
        p.resetJointStatesMultiDof(world.robot, ARM_JOINTS, [[float(v)] for v in q], physicsClientId=client)
        held_id: Optional[int] = None
        if world.attachment is not None:
            held_id = world.bodies[world.attachment.name].id
            world.set_pose(world.attachment.name, world.held_pose())
        world.check_groups()
        p.performCollisionDetection(physicsClientId=client)
        for contact in p.getContactPoints(bodyA=world.robot, physicsClientId=client):
            other = contact[2]
            # The base link (-1) is bolted down: whatever it touches, no motion can change that.
            if contact[8] < -PENETRATION and contact[3] != -1 and other != held_id and other not in self.ignore_ids:
                return True  # robot-robot pairs that may touch were filtered out at load time
        if held_id is not None and self.check_held:
            for contact in p.getContactPoints(bodyA=held_id, physicsClientId=client):
                other = contact[2]
                if contact[8] < -PENETRATION and other not in self.ignore_ids and other != world.robot:
                    return True
        return False

    def _penetrations(self, q: Sequence[float]) -> Iterator[Tuple[int, int, str, float]]:
        """(our body id, its link, the name of what it penetrates, signed distance) at `q`: the
        arm (not its base) or the held object inside anything but the ignored and each other."""
        world = self.world
        self.collides(q)
        names = {body.id: name for name, body in world.bodies.items()}
        names[world.robot] = "robot"
        names[world.mount] = "the robot's mount"
        held = world.bodies[world.attachment.name].id if world.attachment else None
        for body_id in [world.robot] + ([held] if held is not None else []):
            for contact in p.getContactPoints(bodyA=body_id, physicsClientId=world.client):
                if contact[8] < -PENETRATION and not (body_id == world.robot and contact[3] == -1) \
                        and contact[2] not in self.ignore_ids and contact[2] != held:
                    yield body_id, contact[3], names.get(contact[2], str(contact[2])), contact[8]

    def colliding_bodies(self, q: Sequence[float]) -> Collection[str]:
        """Names of what the arm (or held object) penetrates at `q`, for messages and tests."""
        return {other for _, _, other, _ in self._penetrations(q)}

    def hits(self, q: Sequence[float]) -> str:
        """What the arm (or held object) penetrates at `q`, for messages: per body hit, which
        part of ours goes deepest into it and how far (`the panda_hand 7 mm into 'tray'`)."""
        world = self.world
        deepest: Dict[str, Tuple[float, str]] = {}
        for body_id, link, other, depth in self._penetrations(q):
            part = ("the " + p.getJointInfo(world.robot, link, physicsClientId=world.client)[12].decode()
                    if body_id == world.robot else f"the held '{world.attachment.name}'")
            if other not in deepest or depth < deepest[other][0]:
                deepest[other] = (depth, part)
        quoted = {other: other if other == "robot" or other.startswith("the ") else f"'{other}'" for other in deepest}
        return ", ".join(f"{part} {-depth * 1000:.0f} mm into {quoted[other]}"
                         for other, (depth, part) in sorted(deepest.items())) or "nothing"


def _closest_points(world: "World", name: str) -> Iterator[Tuple[int, float, float]]:
    """(other body id, signed distance, world z of the point on the other body) of body
    `name`'s closest points to every other body it touches or penetrates, where it is now
    (negative distance: penetration)."""
    body_id = world.bodies[name].id
    for other in world.bodies.values():
        if other.id != body_id:
            for contact in p.getClosestPoints(body_id, other.id, 0.0, physicsClientId=world.client):
                yield other.id, contact[8], contact[6][2]


def body_penetration(world: "World", name: str, allowed: Mapping[int, float]) -> Optional[float]:
    """How deep body `name`, where it is now, penetrates the bodies whose ids `allowed` maps
    (metres, the deepest, 0 if none), or None if it penetrates any other body (not the robot)
    by more than PENETRATION, or an allowed one below the world z `allowed` gives it (only
    the part of that body above may hold `name` up). A static query, like `body_penetrates`."""
    deepest = 0.0
    for other, distance, z in _closest_points(world, name):
        if other in allowed and z >= allowed[other]:
            deepest = max(deepest, -distance)
        elif distance < -PENETRATION:
            return None
    return deepest


def body_penetrates(world: "World", name: str, depth: float = 1e-3) -> bool:
    """Does body `name`, where it is now, penetrate another body (not the robot) by more
    than `depth`? A static query: nothing moves. Samplers use it for candidate poses of
    an object (a tool at a contact, an object at a placement) before any IK."""
    return any(distance < -depth for _, distance, _ in _closest_points(world, name))
