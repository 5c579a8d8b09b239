"""Hook: grasp the tool by its handle, put its crook behind the box, pull the box towards the
robot, put the tool down where it was, grasp the box.

The tool is an L whose crook sits at the +x end of the handle and reaches towards +y (the
canonical `l-stick`; a hammer's head works the same way). Everything else is read from the
world: the tool's and the box's poses, and their sizes from the manifest.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .geometry import box, closing_for, extent_along, planar, rot2, to_world, yaw_quat
from .motion import PUSH_STEPS, DemoError, Driver, top_down

if TYPE_CHECKING:
    from ...world.world import World
    from ..generate import Instance

ABOVE = 0.10        # metres: pre-grasp height above a grasp
HOVER = 0.004       # metres the tool glides above the table while it pulls
BEHIND = 0.015      # metres between the box's far side and the crook's inner face
REACHED = 0.64      # the box is pulled until its centre is this far from the robot's base


def demo(world: "World", instance: "Instance", driver: Driver) -> None:
    tool, target = "tool", "target"
    lo, hi = box(instance, tool)
    side = float(hi[2] - lo[2])                     # the handle's thickness (square section)
    handle_y = float(lo[1]) + side / 2              # the handle's centre line, tool frame
    tx, ty, tz, tyaw = planar(world, tool)
    rest_z = tz

    # 1. Grasp the handle 5 cm from its end, top-down, fingers across it.
    grip_local = (float(lo[0]) + 0.05, handle_y, 0.0)
    grip = to_world(world, tool, grip_local)
    grip[2] = tz + float(hi[2]) - 0.008
    driver.open()
    driver.approach(grip, [top_down(a) for a in closing_for(tyaw)], back=ABOVE)
    driver.grasp(tool)
    driver.up(ABOVE)

    # 2. Put the crook behind the box: the tool's +x axis points away from the robot, the
    #    handle passes beside the box, the crook's inner face just beyond the box's far side.
    bx, by, bz, byaw = planar(world, target)
    blo, bhi = box(instance, target)
    pull = -np.array([bx, by]) / math.hypot(bx, by)          # towards the robot's base
    away = -pull
    yaw = math.atan2(away[1], away[0])
    depth = extent_along(blo, bhi, byaw, pull)                # the box's half-depth along the pull
    width = extent_along(blo, bhi, byaw, (-pull[1], pull[0]))
    crook_inner = float(hi[0]) - side
    box_in_tool = np.array([crook_inner - depth - BEHIND, handle_y + side / 2 + width + 0.012])
    origin = np.array([bx, by]) - rot2(yaw) @ box_in_tool
    low = (tuple(origin) + (rest_z + HOVER,), yaw_quat(yaw))
    distance = math.hypot(bx, by) - REACHED
    pull3 = (pull[0], pull[1], 0.0)
    driver.place_held([low], back=float(bhi[2] - blo[2]) + 0.03, then=(pull3, distance))

    # 3. Pull the box towards the robot.
    driver.line(pull3, distance, steps=PUSH_STEPS)

    # 4. Lift the tool clear and put it down where it was (or beside that, if the box is there).
    driver.up(0.06)
    put = (tx, ty, rest_z + 0.002)
    nx, ny, _, _ = planar(world, target)
    if abs(nx - tx) < 0.3 and abs(ny - ty) < 0.2:
        put = (tx, ty + 0.15, rest_z + 0.002)
    driver.place_held([(put, yaw_quat(tyaw))])
    driver.release()
    driver.up(0.08)

    # 5. Grasp the box from the top, across its width.
    bx, by, bz, byaw = planar(world, target)
    if math.hypot(bx, by) > 0.8:
        raise DemoError(f"the box is still {math.hypot(bx, by):.2f} m from the robot")
    top = bz + float(bhi[2])
    grip = np.array([bx, by, top - 0.02])
    driver.approach(grip, [top_down(a) for a in closing_for(byaw)], back=ABOVE)
    driver.grasp(target)
    driver.up(ABOVE)
