"""Center-of-Mass: grasp the plate by its rim where it overhangs the table's edge, carry it
over the small block with its centre of mass (its frame's origin) above the block's centre,
lower it onto the block and let go: it balances there."""
from __future__ import annotations

from typing import TYPE_CHECKING

from .edge import grasp_rim
from .geometry import box, planar
from .motion import DemoError, Driver

if TYPE_CHECKING:
    from ...world.world import World
    from ..generate import Instance

GAP = 0.003     # the plate is let go this far above the block


def demo(world: "World", instance: "Instance", driver: Driver) -> None:
    flat, pedestal = "flat", "pedestal"
    if instance.object(flat).asset.split("/")[0] != "plate":
        raise DemoError(f"the CoM script grasps plates by the rim; {instance.object(flat).asset} is not one")
    grasp_rim(world, instance, driver, flat, (0.0, 1.0), lift=0.08)

    px, py, pz, _ = planar(world, pedestal)
    _, phi = box(instance, pedestal)
    flo, _ = box(instance, flat)
    orientation = world.pose(flat)[1]
    z = pz + float(phi[2]) - float(flo[2]) + GAP
    driver.place_held([((px, py, z), orientation)], back=0.06)
    driver.release()
    driver.up(0.08)
