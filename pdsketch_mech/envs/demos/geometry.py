"""Small geometry helpers for the scripts: planar poses, boxes from the manifest, grasp offsets."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Sequence, Tuple

import numpy as np
import pybullet as p

from ..generate import Instance

if TYPE_CHECKING:
    from ...world.world import World

Pose = Tuple[Tuple[float, float, float], Tuple[float, float, float, float]]


def planar(world: "World", name: str) -> Tuple[float, float, float, float]:
    """(x, y, z, yaw) of an object's link frame."""
    (x, y, z), orn = world.pose(name)
    return x, y, z, float(p.getEulerFromQuaternion(orn)[2])


def box(instance: Instance, name: str) -> Tuple[np.ndarray, np.ndarray]:
    """The object's bounding box in its own frame (scaled), from the manifest."""
    return instance.object(name).bbox()


def rot2(yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s], [s, c]])


def to_world(world: "World", name: str, local: Sequence[float]) -> np.ndarray:
    """A point given in the object's frame, in the world."""
    pos, orn = world.pose(name)
    return np.array(p.multiplyTransforms(pos, orn, tuple(local), (0, 0, 0, 1))[0])


def yaw_quat(yaw: float) -> Tuple[float, float, float, float]:
    return tuple(p.getQuaternionFromEuler((0.0, 0.0, yaw)))


def extent_along(lo: np.ndarray, hi: np.ndarray, yaw: float, direction: Sequence[float]) -> float:
    """Half the object's footprint extent along the world direction (unit, planar)."""
    corners = np.array([[x, y] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])]) @ rot2(yaw).T
    d = np.asarray(direction[:2], dtype=float)
    d /= np.linalg.norm(d)
    proj = corners @ d
    return float(proj.max() - proj.min()) / 2


def closing_for(yaw: float) -> Tuple[float, float]:
    """The two top-down closing angles across an object's local y axis (its width)."""
    return yaw + math.pi / 2, yaw - math.pi / 2


__all__ = ["box", "closing_for", "extent_along", "planar", "rot2", "to_world", "yaw_quat"]
