"""The contact-mode graph read from the simulation: holding, support and touching.

`support(x, y)`: y pushes x up — x and y touch and the contact normal on y points up
within `SUPPORT_COS` of +z (PyBullet's normal on B points from B towards A). This is what
demonstration segmentation and the operators' effect checks read.

The normal of a pair is averaged over its *closest* contact points only, those within
`CONTACT_BAND` of the nearest: a plate resting on a ledge (normals up, 0 mm) whose rim passes
1-2 mm from the ledge's wall or lip (normals sideways) rests on the ledge; averaging over every
point inside `CONTACT_DISTANCE` would call it merely touching.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, FrozenSet, List, Optional, Sequence, Tuple

import numpy as np
import pybullet as p

if TYPE_CHECKING:
    from .world import World

SUPPORT_COS = 0.7      # normal within ~45 degrees of vertical: inclined slopes support too
CONTACT_DISTANCE = 2e-3  # metres: closer than this counts as touching
CONTACT_BAND = 5e-4      # metres: the points that set a pair's normal, beyond its closest one


def pair_normal_z(distances: Sequence[float], normal_zs: Sequence[float]) -> float:
    """The z of a touching pair's mean contact normal, over its points within `CONTACT_BAND`
    of the closest one (`distances` and `normal_zs` per contact point, nonempty)."""
    d = np.asarray(distances, dtype=float)
    z = np.asarray(normal_zs, dtype=float)
    return float(z[d <= d.min() + CONTACT_BAND].mean())


@dataclass(frozen=True)
class ContactGraph:
    holding: Optional[str]
    support: FrozenSet[Tuple[str, str]]    # (x, y): y supports x
    touching: FrozenSet[Tuple[str, str]]   # unordered pairs, each stored once sorted; no support between them
    robot_touching: FrozenSet[str]          # objects the hand or arm touches (other than the held one)

    def supports_of(self, name: str) -> List[str]:
        return sorted(y for x, y in self.support if x == name)

    def facts(self) -> List[Tuple[str, ...]]:
        """As PDDL atoms of the basis domain."""
        out: List[Tuple[str, ...]] = [("holding", self.holding)] if self.holding else [("handempty",)]
        out += [("support", x, y) for x, y in sorted(self.support)]
        out += [("touching", x, y) for x, y in sorted(self.touching)]
        return out


def read_contacts(world: "World") -> ContactGraph:
    """The contact graph of the world as it is now (no stepping)."""
    client = world.client
    world.physics_groups()
    p.performCollisionDetection(physicsClientId=client)
    names = {body.id: name for name, body in world.bodies.items()}
    held = world.attachment.name if world.attachment else None
    support, touching = set(), set()
    items = list(world.bodies.items())
    for i, (name_a, body_a) in enumerate(items):
        for name_b, body_b in items[i + 1:]:
            if body_a.fixed and body_b.fixed:
                continue
            points = [c for c in p.getContactPoints(body_a.id, body_b.id, physicsClientId=client)
                      if c[8] < CONTACT_DISTANCE]
            if not points:
                continue
            # Normal on B, pointing towards A, averaged over the closest points of the patch.
            nz = pair_normal_z([c[8] for c in points], [c[7][2] for c in points])
            if nz > SUPPORT_COS and name_a != held:
                support.add((name_a, name_b))
            elif nz < -SUPPORT_COS and name_b != held:
                support.add((name_b, name_a))
            else:
                touching.add(tuple(sorted((name_a, name_b))))
    robot_touching = {names[c[2]] for c in p.getContactPoints(bodyA=world.robot, physicsClientId=client)
                      if c[2] in names and c[8] < CONTACT_DISTANCE and names[c[2]] != held}
    return ContactGraph(held, frozenset(support), frozenset(touching), frozenset(robot_touching))
