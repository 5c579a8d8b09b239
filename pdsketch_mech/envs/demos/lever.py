"""Lever: put the heavy object on the plate's overhang (the part beyond the ledge's fulcrum,
over the pit); the overhang tips down into the pit and the near side of the plate rises off
the platform; then grasp the plate by its raised rim and lift it."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .edge import grasp_rim
from .geometry import box, closing_for, planar, yaw_quat
from .motion import DemoError, Driver, top_down

if TYPE_CHECKING:
    from ...world.world import World
    from ..generate import Instance

FULCRUM = 0.02      # the ledge's fulcrum edge, beyond the cradle's centre (world/shape_builders.py `ledge`)
CLEAR = 0.012       # between the weight and the rim wall
ABOVE = 0.10


def grasp_from_top(world: "World", instance: "Instance", driver: Driver, name: str, depth: float = 0.02) -> None:
    """Top-down grasp across the object's narrower horizontal side, `depth` below its top."""
    x, y, z, yaw = planar(world, name)
    lo, hi = box(instance, name)
    across = yaw + math.pi / 2 if (hi[1] - lo[1]) <= (hi[0] - lo[0]) else yaw
    centre = np.array([x + (lo[0] + hi[0]) / 2 * math.cos(yaw) - (lo[1] + hi[1]) / 2 * math.sin(yaw),
                       y + (lo[0] + hi[0]) / 2 * math.sin(yaw) + (lo[1] + hi[1]) / 2 * math.cos(yaw)])
    top = z + float(hi[2])
    grip = np.array([centre[0], centre[1], top - min(depth, float(hi[2] - lo[2]) / 2)])
    driver.open()
    driver.approach(grip, [top_down(a) for a in closing_for(across - math.pi / 2)], back=ABOVE)
    driver.grasp(name)
    driver.up(ABOVE)


def demo(world: "World", instance: "Instance", driver: Driver) -> None:
    weight, plate, ledge = "weight", "plate", "ledge"
    grasp_from_top(world, instance, driver, weight)

    # Put the weight on the overhang, its long side along the fulcrum, its far side CLEAR of the rim.
    lx, ly, _, lyaw = planar(world, ledge)
    out = np.array([math.cos(lyaw), math.sin(lyaw)])
    plo, phi = box(instance, plate)
    wlo, whi = box(instance, weight)
    long_x = (whi[0] - wlo[0]) >= (whi[1] - wlo[1])
    yaw = lyaw + (math.pi / 2 if long_x else 0.0)
    half_depth = float(min(whi[0] - wlo[0], whi[1] - wlo[1])) / 2
    inner_rim = float(phi[0]) - 0.008 - 0.01                    # the rim wall's inside at its foot
    reach = min(inner_rim - CLEAR - half_depth, FULCRUM + 0.05)
    if reach - half_depth < FULCRUM - 0.01:
        raise DemoError("the weight does not fit on the plate's overhang")
    px, py, pz, _ = planar(world, plate)
    spot = np.array([lx, ly]) + out * reach
    bottom = pz + float(plo[2]) + 0.006 + 0.004             # the plate's floor, 4 mm above it
    z = bottom - float(wlo[2])
    # Either way round (the weight's yaw and yaw + 180 degrees): the one the arm reaches best.
    # The plate is the support: the weight may rest on its rim as well as on its floor.
    driver.place_held([((spot[0], spot[1], z), yaw_quat(yaw + k * math.pi)) for k in (0, 1)], ignore=(plate,))
    driver.release()
    driver.up(ABOVE)
    driver.settle()

    # The near side is up now: grasp it by the rim.
    _, _, _, tilt = planar(world, plate)
    lo_w, hi_w = world.aabb(plate)
    if hi_w[2] - lo_w[2] < 0.035:
        raise DemoError(f"the plate did not tip (it is {100 * (hi_w[2] - lo_w[2]):.1f} cm tall)")
    grasp_rim(world, instance, driver, plate, -out)
