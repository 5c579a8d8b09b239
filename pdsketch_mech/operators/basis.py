"""transit, transit-cont, grasp, place, move, move-cont: each runs its trajectory in the world
and lets the world settle. Whether the outcome is what the operator promised is read back
from the simulated contact graph by the planner, not assumed here."""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional

import numpy as np

from ..samplers.types import Contact, Grasp, Placement, Trajectory
from ..world.robot import CLOSED, MAX_OPENING
from .execution import Recorder, follow, follow_dynamic, retreat

if TYPE_CHECKING:
    from ..world.world import World

LIFT = 0.10     # metres up after a grasp
BACK = 0.06     # metres back after a placement or a push
UP = (0.0, 0.0, 1.0)


@dataclass(frozen=True)
class Outcome:
    ok: bool
    reason: str = ""


def _approach_axis(world: "World") -> np.ndarray:
    import pybullet as p
    return np.array(p.getMatrixFromQuaternion(world.tcp_pose()[1])).reshape(3, 3)[:, 2]


def transit(world: "World", trajectory: Trajectory, rng: np.random.Generator,
            recorder: Optional[Recorder] = None) -> Outcome:
    follow(world, trajectory.waypoints(), recorder)
    return Outcome(True)


move = transit  # holding something: the world carries it along with the hand


def grasp(world: "World", obj: str, grasp_: Grasp, trajectory: Trajectory, rng: np.random.Generator,
          recorder: Optional[Recorder] = None) -> Outcome:
    """Approach, close the fingers on the object, hold it, lift it."""
    if world.attachment is not None:
        return Outcome(False, f"already holding {world.attachment.name}")
    follow(world, trajectory.approach, recorder)
    follow(world, trajectory.final, recorder)
    world.set_fingers(min(MAX_OPENING / 2, grasp_.width / 2))
    world.attach(obj)
    if not retreat(world, UP, LIFT, rng, recorder):
        return Outcome(False, "no straight lift after the grasp")
    world.settle()
    return Outcome(True)


def place(world: "World", obj: str, placement: Placement, trajectory: Trajectory, rng: np.random.Generator,
          recorder: Optional[Recorder] = None) -> Outcome:
    """Carry the object above the placement, lower it, let go, back off, let it settle."""
    follow(world, trajectory.approach, recorder)
    follow(world, trajectory.final, recorder)
    world.detach()
    world.set_fingers(MAX_OPENING / 2)
    if not retreat(world, -_approach_axis(world), BACK, rng, recorder):
        return Outcome(False, "no straight retreat after the placement")
    world.settle()
    return Outcome(True)


def push(world: "World", contact: Contact, trajectory: Trajectory, rng: np.random.Generator,
         recorder: Optional[Recorder] = None) -> Outcome:
    """transit-cont (bare gripper) and move-cont (a held tool): approach behind the contact,
    push with the position controllers while the simulation runs, back off, settle."""
    bare = contact.pusher is None
    follow(world, trajectory.approach, recorder)
    if bare:
        world.set_fingers(CLOSED)
    follow_dynamic(world, trajectory.final, recorder)
    back = -np.asarray(contact.direction, dtype=float)
    ok = retreat(world, back, BACK, rng, recorder) and retreat(world, UP, LIFT, rng, recorder)
    if bare:
        world.set_fingers(MAX_OPENING / 2)
    world.settle()
    return Outcome(ok, "" if ok else "no straight retreat after the push")
