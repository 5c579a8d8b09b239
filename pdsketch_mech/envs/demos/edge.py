"""Edge: push the flat object with the closed fingers until 35 % of it overhangs the table's
+y edge, then grasp the overhang — a plate by its rim at its outermost point, the outer
finger beyond the table's edge where there is room for it now — and lift it."""
from __future__ import annotations

from typing import TYPE_CHECKING, List, Sequence, Tuple

import numpy as np
import pybullet as p

from ..tasks import SMALL_TABLE_EDGE_Y as TABLE_EDGE_Y
from .geometry import box, planar, rot2
from .motion import PUSH_STEPS, DemoError, Driver, frame_quat, top_down

if TYPE_CHECKING:
    from ...world.world import World
    from ..generate import Instance

OVERHANG = 0.35      # of the object's extent across the edge
LIFT = 0.10
RIM_FLARE = 28.0     # degrees: a plate's rim wall leans out by 8 mm over its 15 mm height
RIM_TILTS = (0.0, 15.0, 30.0, 45.0, 60.0, 75.0)   # degrees the rim grasp's approach may lean sideways


def footprint_y(world: "World", instance: "Instance", name: str) -> Tuple[float, float]:
    """The object's lowest and highest world y (its oriented bounding box)."""
    x, y, _, yaw = planar(world, name)
    lo, hi = box(instance, name)
    corners = np.array([[a, b] for a in (lo[0], hi[0]) for b in (lo[1], hi[1])]) @ rot2(yaw).T
    return y + corners[:, 1].min(), y + corners[:, 1].max()


def push_to_edge(world: "World", instance: "Instance", driver: Driver, name: str, overhang: float = OVERHANG) -> None:
    """Push `name` towards +y with the closed fingers until `overhang` of it is past the edge."""
    x, y, z, yaw = planar(world, name)
    y0, y1 = footprint_y(world, instance, name)
    lo, hi = box(instance, name)
    height = float(hi[2] - lo[2])
    tip = float(np.clip(height / 2, 0.0015, 0.008))      # fingertip height above the table
    tcp_z = z + float(lo[2]) + tip + 0.0072               # the tips reach 7.2 mm past the gripper frame
    start = np.array([x, y0 - 0.03, tcp_z])
    driver.close()
    driver.approach(start, [top_down(0.0), top_down(np.pi)], back=0.08, direction=(0.0, 0.0, -1.0))
    distance = TABLE_EDGE_Y + overhang * (y1 - y0) - y1 + 0.03
    driver.line((0.0, 1.0, 0.0), distance, steps=PUSH_STEPS)
    driver.line((0.0, -1.0, 0.0), 0.03)
    driver.up(0.08)
    driver.settle()


def rim_grasp(world: "World", instance: "Instance", name: str, direction: Sequence[float]
              ) -> Tuple[np.ndarray, List[tuple]]:
    """Where to grasp the plate `name` by its rim on the side facing `direction` (world,
    horizontal), and gripper orientations to try, best first: fingers closing along the
    rim wall's normal (outwards and down: the wall flares), approaching from above, tilted
    sideways by 0-75 degrees, preferring approaches that point away from the robot. All in
    the plate's own frame, so a tilted plate is grasped along its tilted rim."""
    pos, orn = world.pose(name)
    rot = np.array(p.getMatrixFromQuaternion(orn)).reshape(3, 3)
    lo, hi = box(instance, name)
    scale = instance.object(name).scale
    d = rot.T @ np.array([direction[0], direction[1], 0.0])
    d[2] = 0.0
    d /= np.linalg.norm(d)
    up = np.array([0.0, 0.0, 1.0])
    # The wall's middle: 9 mm inside the rim, halfway up the 15 mm wall (scaled with the plate).
    local = d * (float(hi[0]) - 0.009 * scale) + up * (float(lo[2]) + 0.0075 * scale)
    target = np.asarray(pos) + rot @ local
    wall = np.radians(RIM_FLARE)
    closing = np.cos(wall) * d - np.sin(wall) * up
    down = -(np.sin(wall) * d + np.cos(wall) * up)   # perpendicular to the closing axis
    side = np.cross(closing, down)
    candidates = []
    for tilt in np.radians(RIM_TILTS):
        for s in ((1.0, -1.0) if tilt else (1.0,)):
            approach = rot @ (np.cos(tilt) * down + np.sin(tilt) * s * side)
            outward = float(np.dot(approach[:2], target[:2] / np.linalg.norm(target[:2])))
            for sign in (1, -1):
                candidates.append((-round(outward, 1), abs(float(tilt)), frame_quat(approach, sign * (rot @ closing))))
    candidates.sort(key=lambda c: (c[0], c[1]))
    return target, [c[2] for c in candidates]


def grasp_rim(world: "World", instance: "Instance", driver: Driver, name: str, direction: Sequence[float],
              lift: float = LIFT) -> None:
    """Grasp the plate `name` by its rim on the side facing `direction` and lift it."""
    target, orientations = rim_grasp(world, instance, name, direction)
    driver.open()
    driver.approach(target, orientations)
    driver.grasp(name)
    driver.up(lift)


def pinch_overhang(world: "World", instance: "Instance", driver: Driver, name: str) -> None:
    """Grasp the overhanging part of the pushed object: a plate by its rim at its outermost point."""
    if instance.object(name).asset.split("/")[0] != "plate":
        raise DemoError(f"the Edge script grasps plates by the rim; {instance.object(name).asset} is not one")
    _, y1 = footprint_y(world, instance, name)
    if y1 - TABLE_EDGE_Y < 0.03:
        raise DemoError(f"{name} overhangs the edge by {100 * (y1 - TABLE_EDGE_Y):.1f} cm only")
    grasp_rim(world, instance, driver, name, (0.0, 1.0))


def demo(world: "World", instance: "Instance", driver: Driver) -> None:
    push_to_edge(world, instance, driver, "flat")
    pinch_overhang(world, instance, driver, "flat")
