"""Bodies beside a mechanism's own objects that its classifiers may see: the nearest ones.

A mechanism's classifiers see its objects' shapes and poses. What decides a Poking push is
not among them: the tunnel the block sits in, which fixes the only direction the block can
leave by. `context_objects` names the bodies nearest the mechanism's movable objects (gap
between bounding boxes, then distance between their centres; the mechanism's own objects
and the robot excluded): the tunnel around the block, a wall behind a plate, a distractor
beside a box. Self-play records them with the mechanism's objects (`learn selfplay
--context N`) and the planner adds the same bodies, chosen by the same rule, when it scores
proposals for a checkpoint trained so. The rule reads geometry only, never names.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, List, Sequence, Tuple

import numpy as np

if TYPE_CHECKING:
    from ...world.world import World


def box_gap(a: Tuple[np.ndarray, np.ndarray], b: Tuple[np.ndarray, np.ndarray]) -> float:
    """Distance between two axis-aligned boxes (lo, hi); 0 when they overlap."""
    separation = np.maximum(0.0, np.maximum(b[0] - a[1], a[0] - b[1]))
    return float(np.linalg.norm(separation))


def context_objects(world: "World", objects: Sequence[str], count: int) -> List[str]:
    """The `count` bodies of `world` nearest the movable ones among `objects`, nearest first.
    Always `count` names, so that every episode and plan has as many objects as its
    classifiers: where the world has fewer other bodies the last is repeated, and where it
    has none (or none of `objects` moves) the first of `objects` stands in."""
    if count <= 0:
        return []
    movable = [o for o in objects if o in world.bodies and not world.bodies[o].fixed]
    if not movable:
        return [objects[0]] * count
    boxes = {o: world.aabb(o) for o in movable}
    centres = {o: (box[0] + box[1]) / 2.0 for o, box in boxes.items()}
    ranked = []
    for name in world.bodies:
        if name in objects:
            continue
        box = world.aabb(name)
        centre = (box[0] + box[1]) / 2.0
        gap = min(box_gap(box, boxes[o]) for o in movable)
        distance = min(float(np.linalg.norm(centre - centres[o])) for o in movable)
        ranked.append((round(gap, 4), distance, name))
    nearest = [name for _, _, name in sorted(ranked)[:count]] or [objects[0]]
    return nearest + [nearest[-1]] * (count - len(nearest))
