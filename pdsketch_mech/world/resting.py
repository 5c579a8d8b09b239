"""Where an object would come to rest: how far it would fall straight down from its pose,
and the z at which it rests on a given support.

Both measure with the simulator's own collision shapes (PyBullet pads every convex part by
a margin of about a millimetre, so an object rests a little higher than its mesh says): an
object put at the z found here neither sinks into its support nor falls when the scene
settles. The fall is found by conservative advancement: move down by the distance to the
nearest body below (no body can be closer than that), until the distance is nil.
"""
from __future__ import annotations

import contextlib
from typing import TYPE_CHECKING, Iterator, List, Optional, Sequence, Tuple

import pybullet as p

if TYPE_CHECKING:
    from .world import World

TOUCHING = 1e-5       # metres: closer than this, two bodies touch
BELOW = 0.3           # the z of a contact normal (from the other body to this one) that makes it "below"
MAX_ADVANCES = 50     # conservative-advancement steps at most (a flat support takes one or two)
REACH = 3.0           # metres below an object that are searched for something to land on
LIFT = 0.01           # metres above a support's bounding box a resting object is dropped from


def fall(world: "World", name: str, onto: Optional[Sequence[str]] = None) -> Optional[Tuple[float, str]]:
    """How far `name` would fall straight down from where it is before it touches a body
    below it (among `onto`, default: every other body and the robot), and that body as
    message text ('table', the robot); None if nothing lies below. The world is left as found."""
    pose = world.pose(name)
    body = world.bodies[name].id
    others = _others(world, name, onto)
    dropped, below = 0.0, None
    with _kept(world, body):
        for _ in range(MAX_ADVANCES):
            nearest = _nearest_below(world, body, others)
            if nearest is None:
                return None if below is None else (dropped, below)
            distance, below = nearest
            if distance <= TOUCHING or dropped + distance > REACH:
                break
            dropped += distance
            x, y, z = pose[0]
            world.set_pose(name, ((x, y, z - dropped), pose[1]))
    return dropped, below


def resting_z(world: "World", name: str, support: str) -> Optional[float]:
    """The z at which `name`, at its current x, y and orientation, rests on `support` (the
    other bodies ignored); None if `support` is not under it there. The world is left as found."""
    pose = world.pose(name)
    x, y, z = pose[0]
    # Start just clear of the support's bounding box, then drop onto it.
    above = z + world.aabb(support)[1][2] + LIFT - world.aabb(name)[0][2]
    with _kept(world, world.bodies[name].id):
        world.set_pose(name, ((x, y, above), pose[1]))
        landed = fall(world, name, [support])
    return None if landed is None else above - landed[0]


@contextlib.contextmanager
def _kept(world: "World", body: int) -> Iterator[None]:
    """Put the body back exactly where it was (the simulator's own numbers, not a pose
    converted back and forth): measuring must not change what the planner simulates."""
    client = world.client
    position, orientation = p.getBasePositionAndOrientation(body, physicsClientId=client)
    velocity = p.getBaseVelocity(body, physicsClientId=client)
    try:
        yield
    finally:
        p.resetBasePositionAndOrientation(body, position, orientation, physicsClientId=client)
        p.resetBaseVelocity(body, *velocity, physicsClientId=client)


def _others(world: "World", name: str, onto: Optional[Sequence[str]]) -> List[Tuple[int, str]]:
    if onto is not None:
        return [(world.bodies[n].id, f"'{n}'") for n in onto]
    return [(b.id, f"'{b.name}'") for b in world.bodies.values() if b.name != name] + [(world.robot, "the robot")]


def _nearest_below(world: "World", body: int, others: Sequence[Tuple[int, str]]) -> Optional[Tuple[float, str]]:
    """The distance to the nearest body whose closest point lies below this one, with its name."""
    best: Optional[Tuple[float, str]] = None
    for other, label in others:
        for point in p.getClosestPoints(body, other, REACH, physicsClientId=world.client):
            # point[7] is the contact normal on the other body, pointing towards this one.
            if point[7][2] > BELOW and (best is None or point[8] < best[0]):
                best = (max(point[8], 0.0), label)
    return best
