"""transit, transit-cont, grasp, place, move, move-cont: each runs its trajectory in the world
and lets the world settle. Free-space segments are collision-checked before they are
followed; contacts (closing the fingers, lifts, pushes, retreats) are simulated. Whether
the outcome is what the operator promised is read back from the simulated contact graph
by the planner, not assumed here; what an operator can see fail itself (the hand not at
the grasp, a finger missing the object, a push that never touches) it reports."""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional

import numpy as np

from ..world.attachment import relative_pose
from ..world.robot import CLOSED, MAX_OPENING, grasp_opening, rotation_angle
from ..world.values import Contact, Grasp, Placement, Trajectory, approach_axis
from .execution import (ExecutionError, FrameRecorder, back_out, fingers_touching, follow, follow_dynamic,
                        move_straight, robot_touches, set_fingers_dynamic)

if TYPE_CHECKING:
    from ..world.world import World

LIFT = 0.10     # metres up after a grasp
BACK = 0.06     # metres back after a placement or a push
OUT_BEYOND = 0.20  # metres a push's retreat may go on past where it started, to clear its lift
UP = (0.0, 0.0, 1.0)
GRASP_POSITION_TOLERANCE = 5e-3            # metres between the hand and the stored grasp
GRASP_ANGLE_TOLERANCE = np.radians(5.0)


@dataclass(frozen=True)
class Outcome:
    ok: bool
    reason: str = ""


def _guarded(run) -> Outcome:
    try:
        return run() or Outcome(True)
    except ExecutionError as error:
        return Outcome(False, str(error))


def transit(world: "World", trajectory: Trajectory, recorder: Optional[FrameRecorder] = None) -> Outcome:
    """transit and move: a free-space motion (holding something or not)."""
    return _guarded(lambda: follow(world, trajectory.waypoints(), "motion", recorder=recorder))


move = transit


def grasp_error(world: "World", grasp_: Grasp) -> Optional[str]:
    """Why the hand is not at `grasp_` relative to its object (None when it is)."""
    actual = relative_pose(world.pose(grasp_.object), world.tcp_pose())
    offset = float(np.linalg.norm(np.subtract(actual[0], grasp_.in_object[0])))
    angle = rotation_angle(actual[1], grasp_.in_object[1])
    if offset > GRASP_POSITION_TOLERANCE or angle > GRASP_ANGLE_TOLERANCE:
        return (f"the hand is {offset * 1000:.1f} mm and {np.degrees(angle):.1f} deg from the grasp of "
                f"{grasp_.object}")
    return None


def grasp(world: "World", obj: str, grasp_: Grasp, trajectory: Trajectory,
          recorder: Optional[FrameRecorder] = None) -> Outcome:
    """Approach, hold the object where the hand is, close the fingers on it, lift it."""
    def run() -> Optional[Outcome]:
        if world.attachment is not None:
            return Outcome(False, f"already holding {world.attachment.name}")
        if grasp_.object != obj:
            return Outcome(False, f"the grasp is of {grasp_.object}, not {obj}")
        world.set_fingers(grasp_opening(grasp_.width) / 2)  # in free space; the approach is checked so
        follow(world, trajectory.approach, "approach", recorder=recorder)
        follow(world, trajectory.final, "final approach", recorder=recorder)
        error = grasp_error(world, grasp_)
        if error:
            return Outcome(False, error)
        # The constraint first, then the fingers: closing fingers must not shove the object
        # away from the sampled grasp (the constraint keeps it there while they squeeze).
        world.attach(obj)
        set_fingers_dynamic(world, CLOSED, recorder)
        touching = fingers_touching(world, obj)
        if touching < 2:
            return Outcome(False, f"{'one finger' if touching else 'neither finger'} touches {obj} when closed")
        move_straight(world, UP, LIFT, "lift", recorder)
        world.settle()
        return None
    return _guarded(run)


def place(world: "World", obj: str, placement: Placement, trajectory: Trajectory,
          recorder: Optional[FrameRecorder] = None) -> Outcome:
    """Carry the object above the placement, lower it, let go, back off, let it settle.
    The object must then rest without the hand: one that slid after the fingers as they
    backed off (a box let go on a slope, nothing below it) and leans on them is not placed,
    though the contact graph, which leaves the robot out, would say it rests on the support."""
    def run() -> Optional[Outcome]:
        if world.attachment is None or world.attachment.name != obj:
            return Outcome(False, f"not holding {obj}")
        follow(world, trajectory.approach, "approach", recorder=recorder)
        follow(world, trajectory.final, "descent", recorder=recorder)
        world.detach()
        set_fingers_dynamic(world, MAX_OPENING / 2, recorder)
        move_straight(world, -approach_axis(world.tcp_pose()), BACK, "retreat", recorder)
        world.settle()
        if robot_touches(world, obj):
            return Outcome(False, f"{obj} leans on the hand once let go")
        return None
    return _guarded(run)


def push(world: "World", contact: Contact, trajectory: Trajectory, recorder: Optional[FrameRecorder] = None) -> Outcome:
    """transit-cont (bare gripper) and move-cont (a held tool): approach behind the contact,
    push with the position controllers while the simulation runs, back out until the way up
    is clear (`back_out`), lift, settle."""
    def run() -> Optional[Outcome]:
        bare = contact.pusher is None
        held = world.attachment.name if world.attachment else None
        if held != contact.pusher:
            return Outcome(False, f"the pusher is {contact.pusher or 'the bare hand'} but the hand holds "
                                  f"{held or 'nothing'}")
        follow(world, trajectory.approach, "approach", recorder=recorder)
        if bare:
            set_fingers_dynamic(world, CLOSED, recorder)
        touched = follow_dynamic(world, trajectory.final, "push", recorder)
        # Back out of wherever the push went (a tunnel) before lifting: at most the way the
        # push came in and OUT_BEYOND further, where the approach came from.
        direction = np.asarray(contact.direction, dtype=float)
        started = np.asarray(world.kinematics.fk(trajectory.final[0])[0])
        travelled = float(np.dot(np.asarray(world.tcp_pose()[0]) - started, direction / np.linalg.norm(direction)))
        back_out(world, -direction, BACK, max(travelled, 0.0) + OUT_BEYOND, UP, LIFT, recorder)
        move_straight(world, UP, LIFT, "lift", recorder)
        if bare:
            set_fingers_dynamic(world, MAX_OPENING / 2, recorder)
        world.settle()
        if contact.target not in touched:
            return Outcome(False, f"the push never touched {contact.target}")
        return None
    return _guarded(run)
