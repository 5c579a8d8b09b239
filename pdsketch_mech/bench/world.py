"""`bench world`: speed and reliability of the world's primitives on a fixed, seeded tabletop.

Measures collision checks per second, IK success and time for reachable top-down and side
gripper poses over the table, motion-planning success and time for arm queries among
obstacles, and snapshot/restore time.
"""
from __future__ import annotations

import time
from typing import Dict, List, Tuple

import numpy as np
from scipy.spatial.transform import Rotation

from ..lang.scene import SceneObject
from ..world.asset_index import assets_root, resolve_asset
from ..world.collision import CollisionChecker
from ..world.motion import path_is_free, plan_motion
from ..world.world import World

TARGETS = {"collision_checks_per_s": (">=", 8000), "ik_success_rate": (">=", 0.95), "ik_median_ms": ("<=", 5.0),
           "motion_plan_success_rate": (">=", 0.98), "motion_plan_median_ms": ("<=", 50.0),
           "snapshot_restore_ms": ("<=", 0.5)}

# Obstacles on the table: (asset, x, y, yaw).
OBSTACLES = [("box/0", 0.55, 0.0, 0.3), ("brick/0", 0.42, -0.25, 1.2), ("block/0", 0.40, 0.22, 0.0),
             ("bowl/0", 0.65, 0.25, 0.0), ("hammer/0", 0.62, -0.22, 0.7)]


def tabletop(seed: int = 0) -> World:
    """The benchmark scene: the table's top at z = 0 in front of the robot, and obstacles."""
    root = assets_root()
    world = World(visual=False)
    world.add_object(SceneObject("table", "table", (0.6, 0.0, 0.0), fixed=True), resolve_asset("table", root))
    for i, (asset, x, y, yaw) in enumerate(OBSTACLES):
        name = f"obstacle{i}"
        world.add_object(SceneObject(name, asset, (x, y, 0.5)), resolve_asset(asset, root))
        world.rest_on(name, "table", (x, y), yaw)
    world.settle()
    return world


def gripper_poses(rng: np.random.Generator, count: int) -> List[Tuple[np.ndarray, np.ndarray]]:
    """Half top-down grasps (random yaw), half side grasps pointing away from the robot."""
    poses = []
    for i in range(count):
        if i % 2 == 0:
            position = np.array([rng.uniform(0.3, 0.65), rng.uniform(-0.3, 0.3), rng.uniform(0.05, 0.3)])
            rotation = Rotation.from_euler("xyz", [np.pi, 0.0, rng.uniform(-np.pi / 2, np.pi / 2)])
        else:
            position = np.array([rng.uniform(0.35, 0.6), rng.uniform(-0.25, 0.25), rng.uniform(0.08, 0.3)])
            heading = np.arctan2(position[1], position[0]) + rng.uniform(-0.3, 0.3)
            # The gripper's z axis (approach) horizontal, along the heading.
            rotation = Rotation.from_euler("zyx", [heading, np.pi / 2, rng.uniform(-np.pi / 2, np.pi / 2)])
        poses.append((position, rotation.as_quat()))
    return poses


def measure_world(seed: int = 0, ik_queries: int = 200, motion_queries: int = 60, checks: int = 5000,
                  snapshots: int = 2000) -> Dict[str, float]:
    """Run every measurement; returns the figures keyed as TARGETS."""
    rng = np.random.default_rng(seed)
    world = tabletop(seed)
    try:
        checker = CollisionChecker(world)
        configs = [world.kinematics.limits.sample(rng) for _ in range(checks)]
        with world.saved():
            start = time.perf_counter()
            for q in configs:
                checker.collides(q)
            checks_per_s = checks / (time.perf_counter() - start)

        ik_times, ik_solutions = [], []
        for position, orientation in gripper_poses(rng, ik_queries):
            start = time.perf_counter()
            q = world.kinematics.ik(position, orientation, rng)
            ik_times.append(time.perf_counter() - start)
            if q is not None:
                ik_solutions.append(q)

        with world.saved():
            free = [q for q in ik_solutions if not checker.collides(q)]
        motion_times, motion_ok = [], 0
        for _ in range(motion_queries):
            a, b = rng.choice(len(free), size=2, replace=False)
            start = time.perf_counter()
            result = plan_motion(world, free[a], free[b], max_checks=16000, seed=seed + a * 1000 + b)
            motion_times.append(time.perf_counter() - start)
            motion_ok += result.path is not None and path_is_free(world, result.path)

        snapshot = world.snapshot()
        start = time.perf_counter()
        for _ in range(snapshots):
            world.restore(world.snapshot())
        snapshot_ms = (time.perf_counter() - start) / snapshots * 1000
        world.restore(snapshot)
    finally:
        world.close()
    return {
        "collision_checks_per_s": round(checks_per_s, 1),
        "ik_success_rate": round(len(ik_solutions) / ik_queries, 4),
        "ik_median_ms": round(float(np.median(ik_times)) * 1000, 3),
        "motion_plan_success_rate": round(motion_ok / motion_queries, 4),
        "motion_plan_median_ms": round(float(np.median(motion_times)) * 1000, 3),
        "snapshot_restore_ms": round(snapshot_ms, 4),
        "motion_plan_queries": motion_queries,
        "ik_queries": ik_queries,
    }


def report(figures: Dict[str, float]) -> List[str]:
    """One line per figure with its target and whether it is met."""
    lines = []
    for key, (op, target) in TARGETS.items():
        value = figures[key]
        met = value >= target if op == ">=" else value <= target
        lines.append(f"{key:26s} {value:>12g}   target {op} {target:<8g} {'ok' if met else 'MISSED'}")
    return lines
