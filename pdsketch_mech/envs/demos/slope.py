"""Slope-and-Blocker: lay the blocker across the slope, flat on its surface, then put the
block on the slope just above it; the block slides onto the blocker and stays there."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Tuple

import numpy as np
import pybullet as p

from .geometry import box
from .lever import grasp_from_top
from .motion import DemoError, Driver

if TYPE_CHECKING:
    from ...world.world import World
    from ..generate import Instance

BOARD = 0.01          # the slope's board thickness (world/shape_builders.py `slope`)
LENGTH = 0.3          # the board's length along the incline
BLOCKER_AT = 0.35     # the blocker's centre, as a fraction of the board from its lower end
GAP = 0.003           # objects are let go this far above the surface
ABOVE = 0.08


def slope_angle(instance: "Instance") -> float:
    """The incline (radians) from the slope's bounding box: the board rises LENGTH sin(a),
    plus its thickness BOARD cos(a) (solved by fixed-point iteration)."""
    lo, hi = box(instance, "slope")
    height = float(hi[2] - lo[2]) / instance.object("slope").scale
    a = math.asin(min(1.0, height / LENGTH))
    for _ in range(30):
        a = math.asin(min(1.0, (height - BOARD * math.cos(a)) / LENGTH))
    return a


def surface_pose(world: "World", instance: "Instance", along: float, lift: float, spin: float
                 ) -> Tuple[Tuple[float, float, float], Tuple[float, float, float, float]]:
    """A pose lying flat on the slope: `along` (fraction of the board from its lower end) up
    the incline, `lift` metres along the surface normal, turned by `spin` about the normal
    (0: the object's x up the incline)."""
    a = slope_angle(instance)
    c, s = math.cos(a), math.sin(a)
    run = LENGTH * c
    dx = -(run - BOARD * s) / 2
    # The top surface starts at (dx - board sin a, board cos a) in the slope's frame.
    x0, z0 = dx - BOARD * s, BOARD * c
    d = along * LENGTH
    local = np.array([x0 + d * c, 0.0, z0 + d * s]) + lift * np.array([-s, 0.0, c])
    pos, orn = world.pose("slope")
    tilt = p.getQuaternionFromEuler((0.0, -a, 0.0))
    turn = p.getQuaternionFromEuler((0.0, 0.0, spin))
    world_pos, world_orn = p.multiplyTransforms(pos, orn, tuple(local), p.multiplyTransforms((0, 0, 0), tilt, (0, 0, 0), turn)[1])
    return tuple(world_pos), tuple(world_orn)


def place_on_slope(world: "World", instance: "Instance", driver: Driver, name: str, along: float, spin: float) -> None:
    """Put the held `name` flat on the slope at `along`, turned by `spin` (or spin + 180 deg)."""
    lo, _ = box(instance, name)
    lift = -float(lo[2]) + GAP
    poses = [surface_pose(world, instance, along, lift, spin + k * math.pi) for k in (0, 1)]
    driver.place_held(poses, back=ABOVE)
    driver.release()
    driver.up(ABOVE)


def demo(world: "World", instance: "Instance", driver: Driver) -> None:
    blocker, block = "blocker", "block"
    # The blocker lies across the incline: its long axis (x) along the slope's y.
    grasp_from_top(world, instance, driver, blocker, depth=0.008)
    place_on_slope(world, instance, driver, blocker, BLOCKER_AT, math.pi / 2)
    driver.settle()

    # The block goes just above it and slides down onto it.
    blo, bhi = box(instance, blocker)
    klo, khi = box(instance, block)
    width = float(min(bhi[0] - blo[0], bhi[1] - blo[1]))
    above = BLOCKER_AT + (width / 2 + float(khi[0] - klo[0]) / 2 + 0.012) / LENGTH
    if above > 0.9:
        raise DemoError("no room for the block above the blocker")
    grasp_from_top(world, instance, driver, block)
    place_on_slope(world, instance, driver, block, above, 0.0)
    driver.settle()
