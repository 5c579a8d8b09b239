"""A problem's `:scene` -> a `World`: every object loaded from its asset at its pose.

Whatever cannot be simulated is a `PddlError` located at the offending scene entry (an
unknown asset at its `:asset`), so the command-line tools print one `FILE:LINE:COL: error:`
line; when two bodies are involved the message names both:
- an object farther from the robot base than `MOVABLE_RANGE` (movable) or `FIXED_RANGE`
  (fixed): the arm reaches ~0.8 m, a tool a little farther; anything beyond is a typo;
- two objects sinking into each other by more than `OVERLAP` (reported at the movable one,
  or at the later of two alike: the one put where the other already was);
- an object inside the robot, its base included (a fixed body may touch the base: the robot
  is mounted against its table);
- a movable object with nothing under it (below the table, off its edge): the world has no
  floor, so it would fall forever.
An object that sinks into the support it is `:on` is told the z at which it would rest there.

An object given `:position (x y)` is put where it rests on its `:on` support (world/resting.py),
supports first. With a `warnings` list, `build_world` also warns, at its entry, of a movable
object that starts more than `FLOATING` above whatever is under it: it falls when the
simulation starts.
"""
from __future__ import annotations

import math
from typing import Dict, List, Optional, Sequence, Tuple

import pybullet as p

from ..lang.errors import PddlError, PddlWarning
from ..lang.nodes import Problem
from ..lang.scene import SceneObject, build_scene
from .asset_index import resolve_asset
from .resting import height_above, resting_z
from .world import Body, SceneError, World

OVERLAP = 5e-3        # metres of interpenetration tolerated at load time
MOVABLE_RANGE = 2.0   # metres from the robot base a movable object may be
FIXED_RANGE = 5.0     # metres from the robot base a fixed object (furniture) may be
RAY_DEPTH = 100.0     # metres a "what is under it" ray looks down
MAX_RAY_HITS = 32     # bodies a ray reports at most (far more than a tabletop holds)
FLOATING = 5e-3       # metres above what is under it a movable object may start without a warning


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


def build_world(problem: Problem, assets_root: Optional[str] = None, gui: bool = False,
                visual: bool = True, warnings: Optional[List[PddlWarning]] = None) -> World:
    """The world of `problem`'s scene, checked; closes the half-built world if anything fails.
    `visual=False` for a world no camera will see (World). Given `warnings`, appends a
    located warning per movable object that would fall when the simulation starts."""
    objects = build_scene(problem)
    urdfs = resolve_scene_assets(problem, assets_root)
    world = World(gui=gui, visual=visual)
    entries = {e.name: e for e in problem.scene or ()}
    try:
        base = p.getBasePositionAndOrientation(world.robot, physicsClientId=world.client)[0]
        for obj in objects:
            if not obj.rest:  # one without z is checked once it rests
                check_range(obj, base)
            world.add_object(obj, urdfs[obj.name])
        for obj in supports_first([o for o in objects if o.rest]):
            place_on_support(world, obj)
            check_range(obj, base, world.pose(obj.name)[0])
        check_overlaps(world, {o.name: o.support for o in objects})
        check_supported(world)
        if warnings is not None:
            warnings.extend(PddlWarning(f"scene object '{name}': {message}", entries[name].loc)
                            for name, message in check_floating(world))
    except SceneError as exc:
        world.close()
        raise PddlError(str(exc), entries[exc.object_name].loc) from None
    except BaseException:
        world.close()
        raise
    return world


def supports_first(objects: Sequence[SceneObject]) -> List[SceneObject]:
    """`objects` ordered so that each comes after its support when that is among them too
    (the scene has no cycles of supports: lang/scene.py refuses them)."""
    pending = {o.name: o for o in objects}
    ordered: List[SceneObject] = []

    def visit(obj: SceneObject) -> None:
        if obj.name not in pending:
            return
        del pending[obj.name]
        if obj.support in pending:
            visit(pending[obj.support])
        ordered.append(obj)
    for obj in objects:
        visit(obj)
    return ordered


def place_on_support(world: World, obj: SceneObject) -> None:
    """Put an object given `:position (x y)` where it rests on its support."""
    x, y, _ = obj.position
    world.set_pose(obj.name, ((x, y, 0.0), obj.orientation))
    z = resting_z(world, obj.name, obj.support)
    if z is None:
        raise SceneError(obj.name, f"'{obj.support}' is not under it at x = {x:g}, y = {y:g}: it has nowhere to "
                                   f"rest (give x and y over '{obj.support}', or a z)")
    world.set_pose(obj.name, ((x, y, z), obj.orientation))


def check_range(obj: SceneObject, robot_base: Sequence[float], position: Optional[Sequence[float]] = None) -> None:
    """`obj` (at `position`, default its scene position) is within the workspace bound of its
    kind (module docstring)."""
    limit, kind = (FIXED_RANGE, "fixed") if obj.fixed else (MOVABLE_RANGE, "movable")
    distance = math.dist(obj.position if position is None else position, robot_base)
    if distance > limit:
        raise SceneError(obj.name, f"is {distance:.1f} m from the robot base; a {kind} object must be "
                                   f"within {limit:.1f} m of it")


def check_overlaps(world: World, supports: Optional[Dict[str, Optional[str]]] = None) -> None:
    """No two bodies, and no body and the robot (or a movable body and the robot's mount),
    interpenetrate by more than `OVERLAP`. An object sunk into the support it is `:on`
    (`supports`: name -> its support) is blamed, and told the z at which it would rest there."""
    supports = supports or {}
    bodies = list(world.bodies.values())
    for i, body in enumerate(bodies):
        for earlier in bodies[:i]:
            depth = _depth(p.getClosestPoints(body.id, earlier.id, 0.0, physicsClientId=world.client))
            if depth > OVERLAP:
                if supports.get(earlier.name) == body.name:
                    blamed, other = earlier, body
                elif supports.get(body.name) == earlier.name:
                    blamed, other = body, earlier
                else:
                    blamed, other = (earlier, body) if body.fixed and not earlier.fixed else (body, earlier)
                hint = ""
                if supports.get(blamed.name) == other.name:
                    z = resting_z(world, blamed.name, other.name)
                    hint = "" if z is None else f"; at z = {z:.3f} it would rest on '{other.name}'"
                raise SceneError(blamed.name, f"overlaps '{other.name}' by {depth * 100:.1f} cm at their "
                                              f"scene poses{hint}")
        points = p.getClosestPoints(body.id, world.robot, 0.0, physicsClientId=world.client)
        if body.fixed:  # the robot's base may rest on (or against) the furniture it is mounted on
            points = [c for c in points if c[4] != -1]
        depth = _depth(points)
        if depth > OVERLAP:
            deepest = min(points, key=lambda c: c[8])
            raise SceneError(body.name, f"overlaps the robot ({_link_name(world, deepest[4])}) by "
                                        f"{depth * 100:.1f} cm at its scene pose")
        if not body.fixed:   # furniture may stand against the pedestal; a movable object may not be in it
            depth = _depth(p.getClosestPoints(body.id, world.mount, 0.0, physicsClientId=world.client))
            if depth > OVERLAP:
                raise SceneError(body.name, f"overlaps the robot's mount (the pedestal under its base) by "
                                            f"{depth * 100:.1f} cm at its scene pose")


def check_supported(world: World) -> None:
    """A vertical ray down from each movable object's middle meets some other body."""
    for body in world.bodies.values():
        if body.fixed:
            continue
        lo, hi = world.aabb(body.name)
        middle = (lo + hi) / 2
        below = _others_on_ray(world, body, middle, middle - (0.0, 0.0, RAY_DEPTH))
        if below:
            continue
        above = _others_on_ray(world, body, middle, middle + (0.0, 0.0, RAY_DEPTH))
        where = f"is below {above[0]} with nothing under it" if above else "has nothing under it"
        raise SceneError(body.name, f"{where}: it would fall (the world has no floor)")


def check_floating(world: World) -> List[Tuple[str, str]]:
    """(name, message) for each movable object that starts more than `FLOATING` above what is
    under it: it falls when the simulation starts."""
    found = []
    for body in world.bodies.values():
        if body.fixed:
            continue
        landed = height_above(world, body.name)
        if landed is not None and landed[0] > FLOATING:
            drop, below = landed
            z = world.pose(body.name)[0][2] - drop
            found.append((body.name, f"starts {drop * 100:.1f} cm above {below}, so it falls when the "
                                     f"simulation starts; at z = {z:.3f} it would rest on {below}"))
    return found


def _depth(points: Sequence[tuple]) -> float:
    """How deep the deepest of `getClosestPoints`' points is (0 if none penetrates)."""
    return -min((c[8] for c in points), default=0.0)


def _link_name(world: World, link: int) -> str:
    if link == -1:
        return p.getBodyInfo(world.robot, physicsClientId=world.client)[0].decode()
    return p.getJointInfo(world.robot, link, physicsClientId=world.client)[12].decode()


def _others_on_ray(world: World, body: Body, start, end) -> List[str]:
    """The bodies other than `body` that the ray start -> end meets, nearest first, as
    message text ('table', the robot); a ray reports one hit per call, so ask for each in turn."""
    names = {b.id: f"'{b.name}'" for b in world.bodies.values()}
    names[world.robot] = "the robot"
    hits: List[Tuple[float, str]] = []
    for k in range(MAX_RAY_HITS):
        (hit,) = p.rayTestBatch([tuple(start)], [tuple(end)], reportHitNumber=k, physicsClientId=world.client)
        if hit[0] < 0:
            break
        if hit[0] != body.id:
            hits.append((hit[2], names.get(hit[0], f"body {hit[0]}")))
    return [name for _, name in sorted(hits)]
