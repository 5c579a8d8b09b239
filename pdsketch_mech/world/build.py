"""A problem's `:scene` -> a `World`: every object loaded from its asset at its pose.

Errors name the object (`SceneError`): an unknown asset, or a pose where the object sinks
into another object or into the robot by more than `OVERLAP`.
"""
from __future__ import annotations

import os
from typing import Optional

import pybullet as p

from ..lang.nodes import Problem
from ..lang.scene import build_scene
from .asset_index import resolve_asset
from .world import SceneError, World

OVERLAP = 5e-3  # metres of interpenetration tolerated at load time


def default_assets_root() -> str:
    """`$PDSKETCH_ASSETS`, else the repository's `assets/` folder."""
    here = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    return os.environ.get("PDSKETCH_ASSETS") or os.path.join(here, "assets")


def build_world(problem: Problem, assets_root: Optional[str] = None, gui: bool = False) -> World:
    """The world of `problem`'s scene; closes the half-built world if anything fails."""
    root = assets_root or default_assets_root()
    world = World(gui=gui)
    try:
        for obj in build_scene(problem):
            try:
                urdf = resolve_asset(obj.asset, root)
            except ValueError as exc:
                raise SceneError(obj.name, str(exc)) from None
            world.add_object(obj, urdf)
        check_overlaps(world)
    except BaseException:
        world.close()
        raise
    return world


def check_overlaps(world: World) -> None:
    items = list(world.bodies.items())
    for i, (name, body) in enumerate(items):
        others = [(n, b.id) for n, b in items[i + 1:]] + [("the robot", world.robot)]
        for other, other_id in others:
            points = p.getClosestPoints(body.id, other_id, 0.0, physicsClientId=world.client)
            depth = -min((c[8] for c in points), default=0.0)
            if depth > OVERLAP:
                raise SceneError(name, f"overlaps {other if other == 'the robot' else repr(other)} by "
                                       f"{depth * 100:.1f} cm at its scene pose")
