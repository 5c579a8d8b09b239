"""Arm motion planning: OMPL RRTConnect in joint space, and straight Cartesian lines via IK.

OMPL 2.0.1 (nanobind) traps, from DESIGN.md: index states only with explicit `range(n)`,
test success with `haveExactSolutionPath()`, check start and goal validity first, and keep
OMPL objects inside functions (module-level ones print "leaked" at exit).

Determinism: a query's answer must depend on its seed alone, never on the machine's load
or on earlier queries. OMPL gives each new planner (and path simplifier) a generator
seeded from a process-wide seed sequence, so every query re-seeds that sequence first; and
RRT stops after a number of collision checks, not after a wall-clock time.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, List, Optional, Sequence

import numpy as np
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou

from .collision import CollisionChecker
from .robot import ARM_JOINTS

if TYPE_CHECKING:
    from .world import World

ou.setLogLevel(ou.LOG_NONE)  # failures are reported by MotionResult.reason
RESOLUTION = 0.05   # radians between consecutive waypoints of a returned path
CHECK_STEP = 0.01   # radians between collision checks along an edge (OMPL's setting is relative
                    # to the space's extent, ~13 rad here: 0.005 of it missed thin obstacles)
LINE_POS_TOL = 1e-3  # metres and radians off the line: a grasp executed from it lands within
LINE_ANG_TOL = 1e-2  # millimetres of the sampled one
MAX_CHECKS = 8000     # collision checks an RRT query may use (~1 s on this machine)
START_SLACK = 0.02    # radians past a joint limit a start may be: a push or a lift with physics
                      # on can press a joint a little past it, and every motion from there failed


def _seed_ompl(seed: int) -> None:
    """Restart OMPL's seed sequence: the planner and simplifier allocated next draw from it.
    (OMPL logs an error when re-seeding after the first draw; the log is off and the reseed
    does take effect, which `test_motion_plans_depend_on_the_seed_alone` checks.)"""
    ou.RNG.setSeed(int(seed) % (2 ** 31 - 1) + 1)


@dataclass
class MotionResult:
    path: Optional[np.ndarray]   # (n, 7) joint waypoints including start and goal, or None
    reason: str = ""             # why there is no path
    checks: int = 0              # collision checks used


def plan_motion(world: "World", start: Sequence[float], goal: Sequence[float], ignore: Sequence[str] = (),
                max_checks: int = MAX_CHECKS, seed: int = 0) -> MotionResult:
    """A collision-free joint path from `start` to `goal` (the arm carries what it holds;
    bodies in `ignore` may be touched), found with at most `max_checks` collision checks;
    the same query and seed always give the same path. The world is restored afterwards."""
    checker = CollisionChecker(world, ignore)
    limits = world.kinematics.limits
    with world.saved():
        for label, q, slack in (("start", start, START_SLACK), ("goal", goal, 1e-6)):
            if not limits.contains(q, tol=slack):
                return MotionResult(None, f"{label} is outside the joint limits")
            if checker.collides(q):
                hit = ", ".join(sorted(checker.colliding_bodies(q)))
                return MotionResult(None, f"{label} configuration is in collision with {hit}", checker.checks)
        if _segment_free(checker, start, goal):
            return MotionResult(_interpolate([start, goal]), checks=checker.checks)
        _seed_ompl(seed)
        path = _rrt_connect(checker, limits.lower, limits.upper, start, goal, checker.checks + max_checks)
    if path is not None and np.any(path[0] != np.asarray(start, dtype=float)):
        path = [np.asarray(start, dtype=float)] + path  # RRT started from the start clipped into the limits
    if path is None:
        return MotionResult(None, f"no path found in {max_checks} collision checks", checker.checks)
    return MotionResult(_interpolate(path), checks=checker.checks)


def _segment_free(checker: CollisionChecker, a: Sequence[float], b: Sequence[float], step: float = CHECK_STEP) -> bool:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    n = max(2, int(np.ceil(np.max(np.abs(b - a)) / step)) + 1)
    return not any(checker.collides(a + (b - a) * t) for t in np.linspace(0.0, 1.0, n))


def _rrt_connect(checker: CollisionChecker, lower, upper, start, goal, check_limit: int) -> Optional[List[np.ndarray]]:
    n = len(ARM_JOINTS)
    space = ob.RealVectorStateSpace(n)
    bounds = ob.RealVectorBounds(n)
    for i in range(n):
        bounds.setLow(i, float(lower[i]))
        bounds.setHigh(i, float(upper[i]))
    space.setBounds(bounds)
    setup = og.SimpleSetup(space)
    setup.setStateValidityChecker(lambda state: not checker.collides([state[i] for i in range(n)]))
    info = setup.getSpaceInformation()
    info.setStateValidityCheckingResolution(CHECK_STEP / space.getMaximumExtent())
    start_state, goal_state = space.allocState(), space.allocState()
    for i in range(n):  # clip: our limit check has a tolerance, OMPL's bounds have none
        start_state[i] = float(np.clip(start[i], lower[i], upper[i]))
        goal_state[i] = float(np.clip(goal[i], lower[i], upper[i]))
    setup.setStartAndGoalStates(start_state, goal_state)
    setup.setPlanner(og.RRTConnect(info))
    setup.solve(ob.PlannerTerminationCondition(lambda: checker.checks >= check_limit))
    if not setup.haveExactSolutionPath():
        return None
    solution = setup.getSolutionPath()
    # Rope shortcutting, not SimpleSetup's simplifySolution: measured on Hook-then-Place-on-
    # Slope's plan (68 queries), simplifySolution used 5.8x the collision checks of the search
    # itself (395k against 77k: 30 % of the plan's time) for paths 14 % longer (298.6 rad in
    # all against 262.8); rope shortcutting used 74k. It is deterministic too.
    og.PathSimplifier(info).ropeShortcutPath(solution)
    return [np.array([solution.getState(k)[i] for i in range(n)]) for k in range(solution.getStateCount())]


def _interpolate(waypoints: Sequence[Sequence[float]], resolution: float = RESOLUTION) -> np.ndarray:
    out = [np.asarray(waypoints[0], dtype=float)]
    for a, b in zip(waypoints, waypoints[1:]):
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        n = max(1, int(np.ceil(np.max(np.abs(b - a)) / resolution)))
        out.extend(a + (b - a) * t for t in np.linspace(0.0, 1.0, n + 1)[1:])
    return np.array(out)


def path_is_free(world: "World", path: np.ndarray, ignore: Sequence[str] = (), step: float = CHECK_STEP) -> bool:
    """Every configuration along the densely interpolated path is collision-free."""
    return path_collision(world, path, ignore, step) is None


def path_collision(world: "World", path: Sequence[Sequence[float]], ignore: Sequence[str] = (),
                   step: float = CHECK_STEP) -> Optional[str]:
    """None if every configuration along the densely interpolated path is collision-free
    (a single waypoint is checked too); else what the first colliding one hits."""
    checker = CollisionChecker(world, ignore)
    with world.saved():
        points = [np.asarray(q, dtype=float) for q in path]
        pairs = list(zip(points, points[1:])) if len(points) > 1 else [(q, q) for q in points]
        for a, b in pairs:
            n = max(2, int(np.ceil(np.max(np.abs(b - a)) / step)) + 1)
            for t in np.linspace(0.0, 1.0, n):
                q = a + (b - a) * t
                if checker.collides(q):
                    return ", ".join(sorted(checker.colliding_bodies(q))) or "itself"
    return None


def cartesian_path(world: "World", start: Sequence[float], direction: Sequence[float], distance: float,
                   rng: np.random.Generator, step: float = 0.01, max_joint_jump: float = 0.2) -> Optional[np.ndarray]:
    """Joint waypoints moving the gripper frame in a straight line (fixed orientation) by
    `distance` metres along `direction`, each solved by IK seeded with the previous one;
    None if IK fails or the arm would jump (a wrist flip is not a straight line).
    Collisions are the caller's to check: a push touches the pushed object by design."""
    kin = world.kinematics
    position, orientation = kin.fk(start)
    direction = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    qs = [np.asarray(start, dtype=float)]
    n = max(1, int(np.ceil(distance / step)))
    for k in range(1, n + 1):
        target = np.asarray(position) + direction * distance * k / n
        q = kin.ik(target, orientation, rng, seed=qs[-1], restarts=1, pos_tol=LINE_POS_TOL, ang_tol=LINE_ANG_TOL)
        if q is None or np.max(np.abs(q - qs[-1])) > max_joint_jump:
            return None
        qs.append(q)
    return np.array(qs)
