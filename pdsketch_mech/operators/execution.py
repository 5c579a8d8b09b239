"""Following joint trajectories: teleported through free space, position-controlled
(with physics) when the motion is meant to push something."""
from __future__ import annotations

from typing import TYPE_CHECKING, List, Optional, Sequence

import numpy as np

from ..world.motion import cartesian_path
from ..world.render import Camera, render

if TYPE_CHECKING:
    from ..world.world import World

STEPS_PER_WAYPOINT = 8   # ~33 ms of simulated time per 1 cm waypoint: pushes move at ~0.3 m/s
SETTLE_AFTER_PUSH = 60


class Recorder:
    """Collects frames of an execution for a GIF: one every `every` waypoints."""

    def __init__(self, camera: Camera = Camera(), every: int = 4):
        self.camera, self.every, self.frames = camera, every, []
        self._count = 0

    def tick(self, world: "World", force: bool = False) -> None:
        self._count += 1
        if force or self._count % self.every == 0:
            self.frames.append(render(world, self.camera))


def follow(world: "World", path: Sequence[Sequence[float]], recorder: Optional[Recorder] = None) -> None:
    """Teleport the arm (and what it holds) along a collision-checked path."""
    for q in path:
        world.set_arm(q)
        if recorder:
            recorder.tick(world)


def follow_dynamic(world: "World", path: Sequence[Sequence[float]], recorder: Optional[Recorder] = None) -> None:
    """Drive the arm along `path` with its position controllers, simulating contacts."""
    for q in path:
        world.arm_targets = np.asarray(q, dtype=float)
        world.step(STEPS_PER_WAYPOINT)
        if recorder:
            recorder.tick(world)
    world.step(SETTLE_AFTER_PUSH)


def retreat(world: "World", direction: Sequence[float], distance: float, rng: np.random.Generator,
            recorder: Optional[Recorder] = None) -> bool:
    """Move the gripper straight along `direction` (teleported); False if IK cannot."""
    path = cartesian_path(world, world.arm(), direction, distance, rng)
    if path is None:
        return False
    follow(world, path, recorder)
    return True


def segments(*parts: np.ndarray) -> List[np.ndarray]:
    return [part for part in parts if len(part)]
