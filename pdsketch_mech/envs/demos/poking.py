"""Poking: grasp the stick by its end, push it along the tunnel's axis through the tunnel
until the block comes out of the far end, pull the stick back, put it down where it was,
grasp the block."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Tuple

import numpy as np

from .geometry import box, closing_for, extent_along, planar, to_world, yaw_quat
from .lever import grasp_from_top
from .motion import PUSH_STEPS, DemoError, Driver, top_down

if TYPE_CHECKING:
    from ...world.world import World
    from ..generate import Instance

ABOVE = 0.10
LEAD = 0.03         # the stick's tip starts this far before the tunnel's mouth
OUT = 0.025         # the block is pushed until its near side is this far out of the far mouth
HEIGHT = 0.012      # the stick's underside above the table while it pokes


def grasp_end(world: "World", instance: "Instance", driver: Driver, name: str, inset: float = 0.03) -> None:
    """Top-down grasp across the tool `inset` metres from its -x end."""
    x, y, z, yaw = planar(world, name)
    lo, hi = box(instance, name)
    grip = to_world(world, name, (float(lo[0]) + inset, (float(lo[1]) + float(hi[1])) / 2 if hi[1] - lo[1] < 0.03
                                   else 0.0, 0.0))
    grip[2] = z + float(hi[2]) - 0.008
    driver.open()
    driver.approach(grip, [top_down(a) for a in closing_for(yaw)], back=ABOVE)
    driver.grasp(name)
    driver.up(ABOVE)


def demo(world: "World", instance: "Instance", driver: Driver) -> None:
    tool, target, tunnel = "tool", "target", "tunnel"
    tx, ty, tz, tyaw = planar(world, tool)
    grasp_end(world, instance, driver, tool)
    byaw = planar(world, target)[3]
    axis, travel = poke(world, instance, driver)
    driver.line((-axis[0], -axis[1], 0.0), travel)

    # Put the stick back where it was, then take the block.
    driver.up(0.06)
    driver.place_held([((tx, ty, tz + 0.002), yaw_quat(tyaw))])
    driver.release()
    driver.up(0.08)
    cx, cy, _, _ = planar(world, tunnel)
    bx, by, _, _ = planar(world, target)
    if np.dot((bx - cx, by - cy), axis) - extent_along(*box(instance, target), byaw, axis) < \
            _half_length(instance, tunnel):
        raise DemoError("the block did not come out of the tunnel")
    grasp_from_top(world, instance, driver, target)


def poke(world: "World", instance: "Instance", driver: Driver) -> Tuple[np.ndarray, float]:
    """With the stick held, put it before the tunnel's mouth and push it along the axis
    until the block is out of the far end; returns the axis (xy) and how far it went."""
    tool, target, tunnel = "tool", "target", "tunnel"
    # The tunnel's axis (its +x): the stick goes in at the -x mouth.
    cx, cy, _, cyaw = planar(world, tunnel)
    axis = np.array([math.cos(cyaw), math.sin(cyaw)])
    half_length = _half_length(instance, tunnel)
    bx, by, _, byaw = planar(world, target)
    blo, bhi = box(instance, target)
    half_depth = extent_along(blo, bhi, byaw, axis)
    # The line through the block's centre along the axis; s = distance along it from the tunnel's centre.
    s_block = float(np.dot((bx - cx, by - cy), axis))
    offset = np.array([bx, by]) - s_block * axis
    lo, hi = box(instance, tool)
    tip = float(hi[0])                                       # the tool's +x end, in its frame
    yaw = math.atan2(axis[1], axis[0])
    s_tip0 = -half_length - LEAD
    z = float(HEIGHT - lo[2])
    start = offset + (s_tip0 - tip) * axis                   # the tool frame's origin, tip LEAD before the mouth
    driver.place_held([((start[0], start[1], z), yaw_quat(yaw))], back=0.06)

    # Poke: the block's near side ends OUT beyond the far mouth.
    travel = (half_length + OUT) - (s_tip0)
    if s_block - half_depth < s_tip0:
        raise DemoError("the block is not inside the tunnel")
    driver.line((axis[0], axis[1], 0.0), travel, steps=PUSH_STEPS)
    return axis, travel


def _half_length(instance: "Instance", tunnel: str) -> float:
    """Half the tunnel's length along its axis (its +x)."""
    lo, hi = box(instance, tunnel)
    return float(hi[0] - lo[0]) / 2
