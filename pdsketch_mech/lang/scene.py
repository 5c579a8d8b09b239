"""A problem's `:scene` section -> `SceneObject`s: what the simulator loads, and where.

Scene syntax, one entry per physical object declared in `:objects`:

    (:scene
      (table :asset "table" :position (0 0 0) :fixed)
      (hook  :asset "l-stick/0" :position (0.45 0.1 0.02) :rpy-deg (0 0 90) :on table)
      (box   :asset "block/1" :position (0.8 0 0.03) :quat (0 0 0 1) :mass 0.3 :friction 0.6))

`:position (x y)` (no z) puts an object with `:on SUPPORT` where it rests on its support.
Orientation is given at most once: `:quat (x y z w)`, `:rpy (r p y)` in radians, or
`:rpy-deg (r p y)` in degrees (default: identity). `:scale` is one factor (or three equal
ones). Values must make physical sense: mass, friction and scale within `LIMITS`, and no
object resting `:on` itself, directly or through a cycle.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, List, Optional, Tuple

from .errors import PddlError, did_you_mean
from .nodes import Problem, SceneEntry, SceneProp, Symbol

Vec3 = Tuple[float, float, float]
Quat = Tuple[float, float, float, float]

# key -> what its value must be, for the messages.
SCENE_KEYS = {
    ":asset": 'an asset name string, e.g. "block/0"',
    ":position": "a vector (x y z) in metres, or (x y) with :on",
    ":quat": "a unit quaternion (x y z w)",
    ":rpy": "roll pitch yaw in radians (r p y)",
    ":rpy-deg": "roll pitch yaw in degrees (r p y)",
    ":fixed": "a flag with no value",
    ":mass": "a number of kilograms in [0.001, 1000]",
    ":friction": "a friction coefficient in [0, 10]",
    ":scale": "a factor in [0.01, 100] (one number, or three equal numbers)",
    ":on": "the name of the supporting scene object",
    ":color": "a vector (r g b a) with entries in [0, 1]",
}


# The physically meaningful range of each number (inclusive): PyBullet misbehaves far
# outside them (a 1e-300 scale makes degenerate meshes, an infinite mass explodes).
LIMITS = {":mass": (0.001, 1000.0), ":friction": (0.0, 10.0), ":scale": (0.01, 100.0)}


@dataclass(frozen=True)
class SceneObject:
    """One physical body of a problem, ready to be loaded into a world."""

    name: str
    asset: str
    position: Vec3
    orientation: Quat = (0.0, 0.0, 0.0, 1.0)
    fixed: bool = False
    mass: Optional[float] = None
    friction: Optional[float] = None
    scale: Vec3 = (1.0, 1.0, 1.0)
    support: Optional[str] = None
    color: Optional[Tuple[float, float, float, float]] = None
    # `:position (x y)`: z is where the object rests on `support`, found when the world is
    # built (world/build.py); until then position[2] is 0.
    rest: bool = False


def build_scene(problem: Problem) -> Tuple[SceneObject, ...]:
    """Validate `problem.scene` and return its objects; `()` when the problem has no scene."""
    declared = {o.name for o in problem.objects}
    entries: Dict[str, SceneEntry] = {}
    for entry in problem.scene or ():
        if entry.name not in declared:
            raise PddlError(f"scene object '{entry.name}' is not declared in :objects"
                            f"{did_you_mean(entry.name, declared)}", entry.loc)
        if entry.name in entries:
            raise PddlError(f"scene object '{entry.name}' appears twice", entry.loc)
        entries[entry.name] = entry
    objects = tuple(_scene_object(entry) for entry in entries.values())
    for obj, entry in zip(objects, entries.values()):
        if obj.support is not None and obj.support not in entries:
            raise PddlError(f"scene object '{obj.name}' is :on '{obj.support}', which has no scene entry",
                            _prop(entry, ":on").loc)
    _check_support_cycles(objects, entries)
    return objects


def _prop(entry: SceneEntry, key: str) -> SceneProp:
    return next(p for p in entry.props if p.key == key)


def _check_support_cycles(objects: Tuple[SceneObject, ...], entries: Dict[str, SceneEntry]) -> None:
    """No object may rest on itself, directly or through others (`a :on b`, `b :on a`)."""
    support = {obj.name: obj.support for obj in objects}
    settled: set = set()  # objects whose chain of supports is known to end
    for name in support:
        chain: List[str] = []
        on_chain: set = set()
        current: Optional[str] = name
        while current is not None and current not in settled:
            if current in on_chain:
                cycle = chain[chain.index(current):] + [current]
                what = ("is :on itself" if len(cycle) == 2 else
                        "rests on itself through a cycle: " + " :on ".join(cycle))
                raise PddlError(f"scene object '{current}' {what}", _prop(entries[current], ":on").loc)
            chain.append(current)
            on_chain.add(current)
            current = support[current]
        settled.update(chain)


def _scene_object(entry: SceneEntry) -> SceneObject:
    props: Dict[str, SceneProp] = {}
    for prop in entry.props:
        if prop.key not in SCENE_KEYS:
            raise PddlError(f"scene object '{entry.name}': unknown property '{prop.key}'"
                            f"{did_you_mean(prop.key, SCENE_KEYS)}; expected one of "
                            f"{', '.join(SCENE_KEYS)}", prop.loc)
        if prop.key in props:
            raise PddlError(f"scene object '{entry.name}': '{prop.key}' is given twice", prop.loc)
        props[prop.key] = prop
    for required in (":asset", ":position"):
        if required not in props:
            raise PddlError(f"scene object '{entry.name}' has no {required} ({SCENE_KEYS[required]})",
                            entry.loc)
    rotations = [p.key for p in entry.props if p.key in (":quat", ":rpy", ":rpy-deg")]
    if len(rotations) > 1:
        raise PddlError(f"scene object '{entry.name}': give one orientation, not both "
                        f"{rotations[0]} and {rotations[1]}", props[rotations[1]].loc)

    def check(key: str, ok: bool) -> None:
        if not ok:
            raise PddlError(f"scene object '{entry.name}': {key} must be {SCENE_KEYS[key]}", props[key].loc)

    asset = props[":asset"].value
    check(":asset", isinstance(asset, str) and bool(asset.strip()))
    position = _vector(props[":position"].value, 3)
    rest = position is None and _vector(props[":position"].value, 2) is not None
    if rest:
        if ":on" not in props:
            raise PddlError(f"scene object '{entry.name}': :position (x y) gives no z, so it needs :on SUPPORT "
                            "to rest on; or give (x y z)", props[":position"].loc)
        position = (*props[":position"].value, 0.0)
    check(":position", position is not None)
    orientation: Quat = (0.0, 0.0, 0.0, 1.0)
    if ":quat" in props:
        quat = _vector(props[":quat"].value, 4)
        check(":quat", quat is not None and math.isclose(math.sqrt(sum(q * q for q in quat)), 1.0,
                                                         abs_tol=1e-3))
        orientation = tuple(q / math.sqrt(sum(x * x for x in quat)) for q in quat)
    for key, degrees in ((":rpy", False), (":rpy-deg", True)):
        if key in props:
            rpy = _vector(props[key].value, 3)
            check(key, rpy is not None)
            orientation = quat_from_rpy(*(math.radians(a) for a in rpy) if degrees else rpy)
    if ":fixed" in props:
        check(":fixed", props[":fixed"].value is None)
    for key in (":mass", ":friction"):
        if key in props:
            check(key, _in_limits(key, props[key].value))
    mass, friction = _number(props, ":mass"), _number(props, ":friction")
    scale: Vec3 = (1.0, 1.0, 1.0)
    if ":scale" in props:
        value = props[":scale"].value
        scale = (value,) * 3 if isinstance(value, float) else _vector(value, 3)
        check(":scale", scale is not None and all(_in_limits(":scale", s) for s in scale))
        if len(set(scale)) > 1:
            raise PddlError(f"scene object '{entry.name}': :scale {_text(scale)} is not uniform; the "
                            "simulator scales models by one factor: give one number", props[":scale"].loc)
    support = None
    if ":on" in props:
        check(":on", isinstance(props[":on"].value, Symbol))
        support = props[":on"].value.name
    color = None
    if ":color" in props:
        color = _vector(props[":color"].value, 4)
        check(":color", color is not None and all(0.0 <= c <= 1.0 for c in color))
    return SceneObject(entry.name, asset.strip(), position, orientation, ":fixed" in props, mass,
                       friction, scale, support, color, rest)


def quat_from_rpy(roll: float, pitch: float, yaw: float) -> Quat:
    """The quaternion (x y z w) of fixed-axis rotations about x, then y, then z (as
    PyBullet's getQuaternionFromEuler); plain math keeps scipy out of a classical run."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)


def _in_limits(key: str, value) -> bool:
    low, high = LIMITS[key]
    return isinstance(value, float) and low <= value <= high


def _text(vector) -> str:
    return "(" + " ".join(f"{v:g}" for v in vector) + ")"


def _vector(value, length: int):
    if isinstance(value, tuple) and len(value) == length and all(isinstance(v, float) for v in value):
        return tuple(value)
    return None


def _number(props: Dict[str, SceneProp], key: str) -> Optional[float]:
    value = props[key].value if key in props else None
    return value if isinstance(value, float) else None
