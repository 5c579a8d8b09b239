"""The contact-mode graph read from the simulation: holding, support and touching.

`support(x, y)`: y pushes x up — x and y touch and the contact normal on y points up
within `SUPPORT_COS` of +z (PyBullet's normal on B points from B towards A). This is what
demonstration segmentation and the operators' effect checks read.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, FrozenSet, List, Optional, Tuple

import pybullet as p

if TYPE_CHECKING:
    from .world import World

SUPPORT_COS = 0.7      # normal within ~45 degrees of vertical: inclined slopes support too
CONTACT_DISTANCE = 2e-3  # metres: closer than this counts as touching


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
            # Normal on B, pointing towards A, summed over the contact patch.
            nz = sum(c[7][2] for c in points) / len(points)
            if nz > SUPPORT_COS and name_a != held:
                support.add((name_a, name_b))
            elif nz < -SUPPORT_COS and name_b != held:
                support.add((name_b, name_a))
            else:
                touching.add(tuple(sorted((name_a, name_b))))
    robot_touching = {names[c[2]] for c in p.getContactPoints(bodyA=world.robot, physicsClientId=client)
                      if c[2] in names and c[8] < CONTACT_DISTANCE and names[c[2]] != held}
    return ContactGraph(held, frozenset(support), frozenset(touching), frozenset(robot_touching))
