"""Trajectory sampler T: arm motions for grasps, placements, free/held moves and pushes.

A motion is an RRTConnect path to a *pre-pose* (backed off from the target), then a
straight Cartesian segment to the target (the approach of a grasp, the descent of a
placement) — or, for a push, a straight segment along the push direction by a distance
d ~ U[0.05, 0.25] m past first contact (Appendix A.4). Retreats are planned by the
operators after the contact changes (they depend on the simulated outcome).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Iterator, Optional, Sequence

import numpy as np
import pybullet as p

from ..world.attachment import compose
from ..world.motion import LINE_ANG_TOL, LINE_POS_TOL, cartesian_path, path_collision, plan_motion
from ..world.robot import grasp_opening
from ..world.values import Contact, Grasp, Placement, Pose, Trajectory, approach_axis
from .budget import SamplerBudget
from .interface import Sampler

if TYPE_CHECKING:
    from ..world.world import World

PRE_DISTANCE = 0.08       # metres between a pre-pose and its target
PUSH_RANGE = (0.05, 0.25)  # metres of push past first contact
BACK_OFF = 0.02           # metres a push starts behind first contact (as the contact sampler checked)


def _motion(world: "World", goal_tcp: Pose, final_direction: Sequence[float], final_distance: float,
            rng: np.random.Generator, kind: str, ignore: Sequence[str] = (),
            push_distance: Optional[float] = None, budget: SamplerBudget = SamplerBudget()) -> Optional[Trajectory]:
    """RRT (at most `budget.motion_checks` collision checks) to `goal_tcp` moved back by
    `final_distance` along `final_direction`, then the straight segment forward (from the
    pre-pose, included). The straight segment of a grasp or a placement is collision-checked
    here, as executed; a push's is simulated instead."""
    direction = np.asarray(final_direction, dtype=float)
    direction /= np.linalg.norm(direction)
    pre = (tuple(np.asarray(goal_tcp[0]) - direction * final_distance), goal_tcp[1])
    start = world.arm()
    # As precise as the straight segment after it: that segment starts wherever q_pre puts the hand.
    q_pre = world.kinematics.ik(pre[0], pre[1], rng, seed=start, pos_tol=LINE_POS_TOL, ang_tol=LINE_ANG_TOL)
    if q_pre is None:
        return None
    result = plan_motion(world, start, q_pre, ignore=ignore, max_checks=budget.motion_checks,
                         seed=int(rng.integers(1 << 30)))
    if result.path is None:
        return None
    final = cartesian_path(world, q_pre, direction, final_distance + (push_distance or 0.0), rng)
    if final is None:
        return None
    if push_distance is None and path_collision(world, final, ignore) is not None:
        return None
    return Trajectory(kind, result.path, final, push_distance=push_distance)


def grasp_motion(world: "World", obj: str, grasp: Grasp, rng: np.random.Generator,
                 budget: SamplerBudget = SamplerBudget()) -> Optional[Trajectory]:
    """To the pre-grasp, then along the approach axis to the grasp, the fingers open to the
    grasp's opening (as the grasp operator opens them before it moves)."""
    tcp = compose(world.pose(obj), grasp.in_object)
    with world.saved():
        world.set_fingers(grasp_opening(grasp.width) / 2)
        return _motion(world, tcp, approach_axis(tcp), PRE_DISTANCE, rng, "grasp", budget=budget)


def place_motion(world: "World", placement: Placement, rng: np.random.Generator,
                 budget: SamplerBudget = SamplerBudget()) -> Optional[Trajectory]:
    """Carrying the held object to above the placement, then down along the support normal."""
    tcp = compose(placement.pose, world.held_tcp_in_object())
    down = -np.asarray(placement.support_normal, dtype=float)
    return _motion(world, tcp, down, PRE_DISTANCE, rng, "place", budget=budget)


def push_motion(world: "World", contact: Contact, rng: np.random.Generator,
                distance: Optional[float] = None, budget: SamplerBudget = SamplerBudget()) -> Optional[Trajectory]:
    """To just behind first contact, then along the push direction by `distance` past
    first contact (default: d ~ U[0.05, 0.25] m)."""
    tcp = contact.pusher_pose if contact.pusher is None else compose(contact.pusher_pose, world.held_tcp_in_object())
    if distance is None:
        distance = float(rng.uniform(*PUSH_RANGE))
    return _motion(world, tcp, contact.direction, BACK_OFF, rng, "push", push_distance=distance, budget=budget)


class GraspMotionSampler(Sampler[Grasp]):
    """The motion to a grasp (stream inputs: the object and the grasp); one plan per grasp."""

    def visit_budget(self, budget: SamplerBudget) -> int:
        return 1   # the grasp's own motion is the one proposal: not a budget

    def propose(self, world, request, rng, budget) -> Iterator[Grasp]:
        yield request.values()[0]

    def verify(self, world, request, grasp, rng) -> Optional[Trajectory]:
        return grasp_motion(world, request.objects()[0], grasp, rng, self.sampler_budget)


class PlaceMotionSampler(Sampler[Placement]):
    """The motion to a placement (stream inputs end with the placement); one plan each."""

    def visit_budget(self, budget: SamplerBudget) -> int:
        return 1   # the placement's own motion is the one proposal: not a budget

    def propose(self, world, request, rng, budget) -> Iterator[Placement]:
        yield request.values()[0]

    def verify(self, world, request, placement, rng) -> Optional[Trajectory]:
        return place_motion(world, placement, rng, self.sampler_budget)


class PushMotionSampler(Sampler[float]):
    """A push from a contact (the stream's input): proposes how far past first contact."""

    def visit_budget(self, budget: SamplerBudget) -> int:
        return budget.push_proposals

    def propose(self, world, request, rng, budget) -> Iterator[float]:
        for _ in range(budget):
            yield float(rng.uniform(*PUSH_RANGE))

    def verify(self, world, request, distance, rng) -> Optional[Trajectory]:
        return push_motion(world, request.values()[0], rng, distance, self.sampler_budget)


class FreeMotionSampler(Sampler[Pose]):
    """A move of the arm (empty, or holding what it holds) to a random pose with the
    gripper pointing down above the table: proposes the pose, verifies by IK and RRT."""

    def __init__(self, kind: str = "free", budget: SamplerBudget = SamplerBudget()):
        super().__init__(budget)
        self.kind = kind

    def visit_budget(self, budget: SamplerBudget) -> int:
        return budget.free_motion_proposals

    def propose(self, world, request, rng, budget) -> Iterator[Pose]:
        for _ in range(budget):
            down = tuple(p.getQuaternionFromEuler((np.pi, 0.0, float(rng.uniform(-np.pi, np.pi)))))
            yield (float(rng.uniform(0.3, 0.6)), float(rng.uniform(-0.3, 0.3)), float(rng.uniform(0.15, 0.35))), down

    def verify(self, world, request, target, rng) -> Optional[Trajectory]:
        q = world.kinematics.ik(target[0], target[1], rng, seed=world.arm())
        if q is None:
            return None
        result = plan_motion(world, world.arm(), q, max_checks=self.sampler_budget.free_motion_checks,
                             seed=int(rng.integers(1 << 30)))
        return Trajectory(self.kind, result.path) if result.path is not None else None
