"""A problem's `:scene` -> a `World`: every object loaded from its asset at its pose.

Problems are reported as `PddlError`s located at the scene entry (or its `:asset`), so the
command-line tools print them as one `FILE:LINE:COL: error:` line: an unknown asset, or a
pose where an object sinks into another object or into the robot by more than `OVERLAP`.
"""
from __future__ import annotations

from typing import Dict, Optional

import pybullet as p

from ..lang.errors import PddlError
from ..lang.nodes import Problem, SceneEntry
from ..lang.scene import build_scene
from .asset_index import resolve_asset
from .world import SceneError, World

OVERLAP = 5e-3  # metres of interpenetration tolerated at load time


def resolve_scene_assets(problem: Problem, root: Optional[str] = None) -> Dict[str, str]:
    """Object name -> URDF path for every scene entry; an unknown asset is a located error."""
    urdfs = {}
    for entry in problem.scene or ():
        prop = next((q for q in entry.props if q.key == ":asset"), None)
        if prop is None or not isinstance(prop.value, str):
            continue  # build_scene reports a missing or malformed :asset
        try:
            urdfs[entry.name] = resolve_asset(prop.value, root)
        except (ValueError, FileNotFoundError) as exc:
            raise PddlError(f"scene object '{entry.name}': {exc}", prop.loc) from None
    return urdfs


def build_world(problem: Problem, assets_root: Optional[str] = None, gui: bool = False) -> World:
    """The world of `problem`'s scene; closes the half-built world if anything fails."""
    objects = build_scene(problem)
    urdfs = resolve_scene_assets(problem, assets_root)
    world = World(gui=gui)
    try:
        for obj in objects:
            world.add_object(obj, urdfs[obj.name])
        check_overlaps(world)
    except SceneError as exc:
        world.close()
        entry: Optional[SceneEntry] = next(e for e in problem.scene if e.name == exc.object_name)
        raise PddlError(str(exc), entry.loc) from None
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
            # The robot's bolted-down base (link -1) may rest on the table it is mounted on.
            depth = -min((c[8] for c in points if not (other_id == world.robot and c[4] == -1)), default=0.0)
            if depth > OVERLAP:
                raise SceneError(name, f"overlaps {other if other == 'the robot' else repr(other)} by "
                                       f"{depth * 100:.1f} cm at its scene pose")
