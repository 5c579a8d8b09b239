"""Where an object would come to rest: the z at which it rests on a given support, and how
far it stands above what is under it.

Both measure with the simulator's own collision shapes (PyBullet pads every convex part by
a margin of about a millimetre, so an object rests a little higher than its mesh says): an
object put at the z found here neither sinks into its support nor falls when the scene
settles. The resting z is found by conservative advancement: move down by the distance to
the nearest body below (no body can be closer than that), until the distance is nil. The
height above what is under it is read from one query, without moving anything: moving a
body, even back to the same numbers, reorders the simulator's collision structures and
changes later simulations in their last digits, and a plan must not depend on a warning.
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


def _fall(world: "World", name: str, onto: Sequence[str]) -> Optional[Tuple[float, str]]:
    """How far `name` would fall straight down from where it is before it touches one of the
    bodies `onto`, and that body as message text; None if none lies below. The world is left
    as found."""
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


def height_above(world: "World", name: str) -> Optional[Tuple[float, str]]:
    """How far `name` stands above the nearest body under it (another object, the robot),
    and that body as message text; None if nothing is under it. Nothing is moved: each
    closest point below counts its distance over its normal's z, the vertical drop onto a
    plane through that point."""
    return _nearest_below(world, world.bodies[name].id, _others(world, name, None), vertical=True)


def resting_z(world: "World", name: str, support: str) -> Optional[float]:
    """The z at which `name`, at its current x, y and orientation, rests on `support` (the
    other bodies ignored); None if `support` is not under it there. The world is left as found."""
    pose = world.pose(name)
    x, y, z = pose[0]
    # Start just clear of the support's bounding box, then drop onto it.
    above = z + world.aabb(support)[1][2] + LIFT - world.aabb(name)[0][2]
    with _kept(world, world.bodies[name].id):
        world.set_pose(name, ((x, y, above), pose[1]))
        landed = _fall(world, name, [support])
    return None if landed is None else above - landed[0]


@contextlib.contextmanager
def _kept(world: "World", body: int) -> Iterator[None]:
    """Put the body back exactly where it was: the simulator's own numbers, not a pose
    converted back and forth."""
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


def _nearest_below(world: "World", body: int, others: Sequence[Tuple[int, str]],
                   vertical: bool = False) -> Optional[Tuple[float, str]]:
    """The distance to the nearest body whose closest point lies below this one (`vertical`:
    the distance straight down to the plane through that point), with its name."""
    best: Optional[Tuple[float, str]] = None
    for other, label in others:
        for point in p.getClosestPoints(body, other, REACH, physicsClientId=world.client):
            # point[7] is the contact normal on the other body, pointing towards this one.
            if point[7][2] > BELOW:
                distance = max(point[8], 0.0) / (point[7][2] if vertical else 1.0)
                if best is None or distance < best[0]:
                    best = (distance, label)
    return best
