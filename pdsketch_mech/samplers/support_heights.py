"""How high the first surface below an object's bottom is, around the object: a height map
cast lazily, for the grasp sampler's test that no part of the gripper low down sits on the
support.

The grasp sampler asks this of every low point of every candidate gripper frame: thousands
per batch of antipodal pairs, most of them near points already asked about (the frames of
one pair overlap, and so do pairs). A ray per point cost a third of a dry grasp visit; here
a ray is cast once per node of a grid (GRID metres), when a point first needs it, and a
point is answered by its nearest node. The test only filters what IK and the collision
checker then verify, so being a node off (2 mm at most) near an edge costs nothing but a
candidate; taking the highest of the four nodes around a point instead rejected half the
grasps of a plate's rim next to its curb.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Iterable

import numpy as np
import pybullet as p

if TYPE_CHECKING:
    from ..world.world import World

GRID = 0.003            # metres between the nodes rays are cast at
START_ABOVE = 0.01      # rays start this far above the object's bottom
RAYS_PER_BATCH = 4096   # below PyBullet's cap on one rayTestBatch


class SupportHeights:
    """The z of the first surface of another body below `bottom` + START_ABOVE, on a grid over
    `obj`'s footprint widened by `reach` (ignoring `obj` itself and the robot: a ray that
    meets them first sees no support there, as a single ray would). Valid while nothing moves."""

    def __init__(self, world: "World", obj: str, bottom: float, reach: float):
        self.client, self.bottom = world.client, bottom   # not the world: grasp.py keeps these per world, weakly
        self.ignore = {world.bodies[obj].id, world.robot, -1}
        lo, hi = p.getAABB(world.bodies[obj].id, physicsClientId=world.client)
        self.origin = np.array(lo[:2]) - reach - GRID
        shape = np.ceil((np.array(hi[:2]) + reach + GRID - self.origin) / GRID).astype(int) + 1
        self.heights = np.full(shape, np.nan)   # nan: not cast yet; -inf: no support below
        self.floor = bottom - reach - 0.01      # rays end here, below any point of the gripper
        self.rays = 0                           # rays cast so far (stats, tests)

    def surface_below(self, points: np.ndarray) -> np.ndarray:
        """For world points (n, 3), the z of the surface below each (its nearest node's)."""
        node = np.rint((points[:, :2] - self.origin) / GRID).astype(int)
        flat = np.clip(node[:, 0], 0, self.heights.shape[0] - 1) * self.heights.shape[1] + \
            np.clip(node[:, 1], 0, self.heights.shape[1] - 1)
        self._cast(np.unique(flat[np.isnan(self.heights.flat[flat])]))
        return self.heights.flat[flat]

    def clear(self, points: np.ndarray, clearance: float) -> np.ndarray:
        """Whether each world point (n, 3) lies at least `clearance` above the surface below it."""
        if not len(points):
            return np.ones(0, dtype=bool)
        return self.surface_below(points) < points[:, 2] - clearance

    def _cast(self, todo: np.ndarray) -> None:
        """Cast the rays of the nodes `todo` (flat indices into the grid)."""
        if not len(todo):
            return
        xy = self.origin + np.column_stack(np.unravel_index(todo, self.heights.shape)) * GRID
        starts = np.column_stack([xy, np.full(len(xy), self.bottom + START_ABOVE)])
        ends = np.column_stack([xy, np.full(len(xy), self.floor)])
        found = np.full(len(todo), -np.inf)
        for start in range(0, len(todo), RAYS_PER_BATCH):
            hits = p.rayTestBatch(starts[start:start + RAYS_PER_BATCH].tolist(),
                                  ends[start:start + RAYS_PER_BATCH].tolist(), physicsClientId=self.client)
            found[start:start + len(hits)] = list(_support_z(hits, self.ignore))
        self.heights.flat[todo] = found
        self.rays += len(todo)


def _support_z(hits: Iterable[tuple], ignore: set) -> Iterable[float]:
    for hit in hits:
        yield -np.inf if hit[0] in ignore else hit[3][2]
