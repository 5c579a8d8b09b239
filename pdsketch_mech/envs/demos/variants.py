"""Variants of the scripted demonstrations, to test mechanism extraction on demos that do
more than the trick (`demo record NAME --variant VARIANT`); the committed demos never use them.

- `distractor-push`: the instance gets one extra block (`d0`) on the table within reach, and
  before the task's script runs the closed hand pushes that block 8 cm towards +y — an
  irrelevant push that extraction must still explain (it explains the demo, it does not
  guess the intended one).
"""
from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Callable, Dict, Tuple

import numpy as np

from ...world.asset_index import asset_info
from ..generate import GAP, Instance, Placed
from .geometry import box, extent_along, planar
from .motion import PUSH_STEPS, Driver, top_down

if TYPE_CHECKING:
    from ...world.world import World

DISTRACTOR = "d0"
DISTRACTOR_ASSET = "block/1"
DISTRACTOR_XY = (0.40, -0.30)     # within reach, clear of every task's canonical objects
PUSH = 0.08                        # metres the block is pushed


def with_distractor(instance: Instance) -> Instance:
    """`instance` plus the block `d0` on the table at DISTRACTOR_XY."""
    z = -asset_info(DISTRACTOR_ASSET)["aabb"]["min"][2] + GAP
    block = Placed(DISTRACTOR, DISTRACTOR_ASSET, (DISTRACTOR_XY[0], DISTRACTOR_XY[1], float(z)), 0.0, 1.0, False,
                   "table", role="distractor")
    return replace(instance, objects=instance.objects + (block,))


def push_distractor(world: "World", instance: Instance) -> None:
    """Push `d0` towards +y with the closed fingertips, back off, lift the hand."""
    driver = Driver(world)
    x, y, z, yaw = planar(world, DISTRACTOR)
    lo, hi = box(instance, DISTRACTOR)
    half = extent_along(lo, hi, yaw, (0.0, 1.0))
    tip = float(np.clip((hi[2] - lo[2]) / 2, 0.0015, 0.008))
    start = np.array([x, y - half - 0.03, z + float(lo[2]) + tip + 0.0072])
    driver.close()
    driver.approach(start, [top_down(0.0), top_down(np.pi)], back=0.08, direction=(0.0, 0.0, -1.0))
    driver.line((0.0, 1.0, 0.0), PUSH + 0.03, steps=PUSH_STEPS)
    driver.line((0.0, -1.0, 0.0), 0.03)
    driver.up(0.08)
    driver.open()
    world.settle()


# name -> (instance change, what to do before the task's script)
VARIANTS: Dict[str, Tuple[Callable[[Instance], Instance], Callable[["World", Instance], None]]] = {
    "distractor-push": (with_distractor, push_distractor),
}
