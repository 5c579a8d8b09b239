"""`check --reach`: per movable object of a scene, whether the hand can grasp it where it stands.

Reach, as the planner uses it (world/robot.py): a gripper pose is reachable only if the arm's
flange, 0.21 m behind the gripper frame along its approach, lies within 0.82 m of the
shoulder (the arm's second joint, 0.333 m above the robot's base); inverse kinematics and
collisions decide the rest. So an object lying about 0.8 m (horizontally) from the base is at
the edge: this command tries the generic grasp sampler on each object and says.
"""
from __future__ import annotations

from typing import List

import numpy as np

from ..lang.nodes import Problem

ATTEMPTS = 60   # grasp proposals tried per object: a graspable object has feasible ones among the first few


def reach_report(problem: Problem, seed: int = 0) -> List[str]:
    """One line per movable scene object: graspable where it stands or not, and its horizontal
    distance from the shoulder."""
    from ..samplers.grasp import sample_grasps
    from ..world.build import build_world

    lines = []
    with build_world(problem, visual=False) as world:
        world.settle()
        for name, body in world.bodies.items():
            if body.fixed:
                continue
            centre = np.asarray(world.pose(name)[0], dtype=float)
            away = float(np.linalg.norm((centre - np.asarray(world.shoulder, dtype=float))[:2]))
            found = next(sample_grasps(world, name, np.random.default_rng(seed), max_attempts=ATTEMPTS), None)
            verdict = "graspable where it stands" if found is not None else \
                f"not graspable where it stands (none of {ATTEMPTS} grasp proposals reaches it)"
            lines.append(f"{name}: {verdict}; {away:.2f} m from the shoulder horizontally")
    return lines
