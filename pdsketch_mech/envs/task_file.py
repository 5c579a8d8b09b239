"""Task distributions as data files (`NAME.dist.json`, docs/distributions.md).

A distribution is derived from a problem file: its scene gives every object's asset, pose,
support and physical overrides, its goal the task's goal. The file says only what varies:

    {"format": 1, "problem": "push-to-edge.pddl",
     "objects": {"flat": {"assets": {"train": ["calculator/0", "document/0"], "test": ["calculator/2"]},
                          "shift": [0.05, 0.05], "turn": 15, "scale": [0.9, 1.1]}},
     "distractors": {"pool": ["apple/0", "block/1"], "count": [0, 2], "region": [[0.3, 0.7], [-0.4, -0.1]]}}

Without a problem, `objects` lists every object in full: the form `task_document` writes, in
which every built-in task can be written (and is checked to round-trip). Every error is one
line naming the file and, where it can, the line and the field.
"""
from __future__ import annotations

import json
import math
import os
import re
from dataclasses import replace
from typing import Any, Dict, List, Optional, Tuple

from ..lang.errors import PddlError, did_you_mean
from ..lang.nodes import Problem
from ..lang.parser import parse_file
from ..lang.scene import build_scene
from ..lang.writer import formula
from ..world.asset_index import asset_info, asset_names
from .spec import Align, Assets, Distractors, ObjectSpec, TaskSpec

FORMAT = 1
SUFFIX = ".dist.json"
MOVABLE_SHIFT = (0.05, 0.05)     # the paper's perturbation of movable objects: +-5 cm, +-15 degrees
MOVABLE_TURN = 15.0
TOP_FIELDS = ("format", "problem", "name", "title", "description", "goal", "objects", "distractors", "overlaps_ok",
              "demo")
OBJECT_FIELDS = ("assets", "xy", "z", "yaw", "tilt", "on", "frame", "surface", "fixed", "shift", "turn", "scale", "mass",
                 "friction", "align", "yaw_by_category", "match", "slides", "role")


class TaskFileError(ValueError):
    """A distribution file that cannot be used: one located line."""


def is_task_file(name: str) -> bool:
    return name.endswith(".json") or os.sep in name


# ---------------------------------------------------------------------- reading
def load_task_file(path: str) -> TaskSpec:
    """The distribution `path` declares; TaskFileError (one line) if it cannot be used."""
    try:
        with open(path, encoding="utf-8") as handle:
            text = handle.read()
    except (OSError, UnicodeDecodeError) as exc:
        raise TaskFileError(f"{path}: error: cannot read it ({exc.strerror if isinstance(exc, OSError) else exc})") \
            from None
    try:
        document = json.loads(text)
    except json.JSONDecodeError as exc:
        raise TaskFileError(f"{path}:{exc.lineno}:{exc.colno}: error: not JSON: {exc.msg}") from None
    return task_from_document(document, path, text)


def task_from_problem(path: str) -> TaskSpec:
    """The default distribution of a problem file, as if a distribution file named only it:
    its scene's movable objects shifted and turned as the paper perturbs them, fixed ones
    kept, every asset its own (docs/distributions.md)."""
    stem = os.path.basename(path)
    return task_from_document({"format": FORMAT, "problem": stem,
                               "description": f"the scene of {stem}, its movable objects shifted and turned"}, path)


def _where(path: str, text: str, key: Optional[str]) -> str:
    """`path:LINE:COL` of the first `"key":` in `text`, or `path`."""
    if key is None or not text:
        return path
    index = text.find(f'"{key}"')
    if index < 0:
        return path
    return f"{path}:{text.count(chr(10), 0, index) + 1}:{index - text.rfind(chr(10), 0, index)}"


def task_from_document(document: Any, path: str = "<distribution>", text: str = "") -> TaskSpec:
    """A TaskSpec from a parsed distribution file (module docstring)."""
    def error(message: str, key: Optional[str] = None) -> TaskFileError:
        return TaskFileError(f"{_where(path, text, key)}: error: {message}")

    if not isinstance(document, dict):
        raise error("a distribution is a JSON object with \"format\" and \"problem\" or \"objects\"")
    for key in document:
        if key not in TOP_FIELDS:
            raise error(f"unknown field '{key}'{did_you_mean(key, TOP_FIELDS)} (fields: {', '.join(TOP_FIELDS)})", key)
    if document.get("format") != FORMAT:
        raise error(f"format: expected \"format\": {FORMAT}, got {json.dumps(document.get('format'))}", "format")
    stem = os.path.basename(path)
    stem = stem[:-len(SUFFIX)] if stem.endswith(SUFFIX) else os.path.splitext(stem)[0]
    objects = document.get("objects", {})
    if not isinstance(objects, dict):
        raise error("objects: expected {NAME: {field: value, ...}, ...}", "objects")
    if "problem" in document:
        problem_path = os.path.join(os.path.dirname(path), str(document["problem"]))
        base, goal = _from_problem(problem_path, error)
    else:
        if not objects:
            raise error("give \"problem\" (the scene to vary) or every object in \"objects\"")
        base, goal = {}, None
    for name in objects:
        if base and name not in base:
            raise error(f"objects: '{name}' is not an object of the problem's scene{did_you_mean(name, base)} "
                        f"(objects: {', '.join(base)})", name)
    specs = []
    for name, fields in _ordered(base, objects).items():
        specs.append(_object(name, base.get(name), fields, error))
    names = [s.name for s in specs]
    for spec in specs:
        for field_name in ("on", "frame", "match"):
            other = getattr(spec, field_name)
            if other is None or other in names[:names.index(spec.name)]:
                continue
            if other not in names:
                raise error(f"objects: {spec.name}: {field_name}: '{other}' is not an object of the task"
                            f"{did_you_mean(other, names)}", spec.name)
            raise error(f"objects: {spec.name}: {field_name}: '{other}' must come before it in \"objects\"",
                        spec.name)
    goal = document.get("goal", goal)
    if not isinstance(goal, str) or not goal.strip():
        raise error("goal: expected the goal as PDDL text (default: the problem's)", "goal")
    return TaskSpec(str(document.get("name", stem)), str(document.get("title", document.get("name", stem))),
                    str(document.get("description", "")), tuple(specs), goal,
                    _distractors(document.get("distractors"), error), _pairs(document.get("overlaps_ok", []), error),
                    str(document.get("demo", "")), source=path)


def _from_problem(path: str, error) -> Tuple[Dict[str, ObjectSpec], str]:
    """Each scene object as it stands in the problem (movable ones perturbed as in the
    paper), and the problem's goal."""
    if not os.path.isfile(path):
        raise error(f"problem: {path}: no such file", "problem")
    try:
        problem = parse_file(path)
        scene = build_scene(problem) if isinstance(problem, Problem) else ()
    except PddlError as exc:
        raise TaskFileError(str(exc)) from None
    if not scene:
        raise error(f"problem: {path} has no :scene", "problem")
    supports = {atom.args[0].name: atom.args[1].name for atom in problem.init
                if atom.predicate == "support" and len(atom.args) == 2}
    specs: Dict[str, ObjectSpec] = {}
    for obj in scene:
        roll, pitch, yaw = _euler(obj.orientation)
        tilt = (0.0, 0.0) if abs(roll) < 1e-3 and abs(pitch) < 1e-3 else \
            (round(math.degrees(roll), 6), round(math.degrees(pitch), 6))
        on = obj.support or supports.get(obj.name)
        if on is None and abs(obj.position[2]) > 1e-3 and not obj.fixed:
            raise error(f"problem: scene object '{obj.name}' stands on nothing (give it :on SUPPORT)", "problem")
        shift, turn = ((0.0, 0.0), 0.0) if obj.fixed else (MOVABLE_SHIFT, MOVABLE_TURN)
        specs[obj.name] = ObjectSpec(obj.name, Assets((obj.asset,), (obj.asset,)), xy=obj.position[:2],
                                     z=float(obj.position[2]) if on is None else 0.0,
                                     yaw=round(math.degrees(yaw), 6), tilt=tilt, on=on, fixed=obj.fixed, noise_xy=shift, noise_yaw=turn,
                                     scale=(obj.scale[0], obj.scale[0]), mass=obj.mass, friction=obj.friction)
    for name, spec in list(specs.items()):
        if spec.on is not None and specs.get(spec.on) is not None and specs[spec.on].on is not None:
            # On something that itself stands on something: placed relative to it, moving with it.
            support = specs[spec.on]
            dx, dy = spec.xy[0] - support.xy[0], spec.xy[1] - support.xy[1]
            c, s = math.cos(math.radians(support.yaw)), math.sin(math.radians(support.yaw))
            specs[name] = replace(spec, xy=(c * dx + s * dy, -s * dx + c * dy), yaw=spec.yaw - support.yaw,
                                   frame=spec.on)
    return specs, formula(problem.goal)


def _euler(q: Tuple[float, float, float, float]) -> Tuple[float, float, float]:
    """Roll, pitch, yaw (radians) of a quaternion (x, y, z, w); no simulator imported for it."""
    x, y, z, w = q
    roll = math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2 * (w * y - z * x))))
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    return roll, pitch, yaw


def _ordered(base: Dict[str, ObjectSpec], objects: Dict[str, Any]) -> Dict[str, Any]:
    """Name -> fields, each object after what it stands on and is placed relative to."""
    names = list(base) or list(objects)
    pending = set(names)
    ordered: Dict[str, Any] = {}

    def visit(name: str) -> None:
        if name not in pending:
            return
        pending.discard(name)
        fields = objects.get(name, {})
        for other in (fields.get("on") if isinstance(fields, dict) else None,
                      base[name].on if name in base else None, base[name].frame if name in base else None):
            if isinstance(other, str):
                visit(other)
        ordered[name] = fields
    for name in names:
        visit(name)
    return ordered


def _object(name: str, base: Optional[ObjectSpec], fields: Any, error) -> ObjectSpec:
    if not isinstance(fields, dict):
        raise error(f"objects: {name}: expected {{field: value, ...}}", name)
    for key in fields:
        if key not in OBJECT_FIELDS:
            raise error(f"objects: {name}: unknown field '{key}'{did_you_mean(key, OBJECT_FIELDS)} "
                        f"(fields: {', '.join(OBJECT_FIELDS)})", name)
    if base is None and ("assets" not in fields or "xy" not in fields):
        raise error(f"objects: {name}: give its assets and xy (there is no problem to take them from)", name)

    def get(key: str, check, default):
        if key not in fields:
            return default
        value = fields[key]
        problem = check(value)
        if problem:
            raise error(f"objects: {name}: {key}: {problem}", name)
        return value

    assets = base.assets if base else None
    if "assets" in fields:
        assets = _assets(fields["assets"], lambda m: error(f"objects: {name}: assets: {m}", name))
    b = base or ObjectSpec(name, assets)
    align = b.align
    if "align" in fields:
        a = fields["align"]
        if not isinstance(a, dict) or a.get("side") not in ("+x", "-x", "+y", "-y") or _number(a.get("at")):
            raise error(f"objects: {name}: align: expected {{\"side\": \"+y\", \"at\": 0.5, \"fraction\": 0.38}}", name)
        align = Align(a["side"], float(a["at"]), float(a.get("fraction", 0.0)), float(a.get("noise", 0.005)))
    yaws = get("yaw_by_category", lambda v: None if isinstance(v, dict) and not any(_number(x) for x in v.values())
               else "expected {CATEGORY: degrees}", None)
    return ObjectSpec(
        name, assets,
        xy=tuple(float(v) for v in get("xy", _pair, b.xy)),
        z=float(get("z", _number, b.z)),
        yaw=float(get("yaw", _number, b.yaw)),
        tilt=tuple(float(v) for v in get("tilt", _tilt, b.tilt)),
        on=get("on", _name_or_null, b.on),
        frame=get("frame", _name_or_null, b.frame),
        surface=get("surface", _number_or_null, b.surface),
        fixed=bool(get("fixed", _bool, b.fixed)),
        noise_xy=tuple(float(v) for v in get("shift", _pair, b.noise_xy)),
        noise_yaw=float(get("turn", _number, b.noise_yaw)),
        scale=tuple(float(v) for v in get("scale", _scale_range, b.scale)),
        mass=get("mass", _number_or_null, b.mass),
        friction=get("friction", _number_or_null, b.friction),
        align=align,
        yaw_by_category=tuple((str(k), float(v)) for k, v in yaws.items()) if yaws is not None else b.yaw_by_category,
        match=get("match", _name_or_null, b.match),
        slides=bool(get("slides", _bool, b.slides)),
        role=str(get("role", lambda v: None if isinstance(v, str) else "expected a string", b.role)))


def _assets(value: Any, error) -> Assets:
    if isinstance(value, list):
        return Assets(*(2 * (_asset_list(value, error),)))
    if not isinstance(value, dict) or not value.get("train"):
        raise error("expected {\"train\": [ASSET, ...], \"test\": [ASSET, ...]} (held-out assets for dev and test; "
                    "with \"dev\": [...] too, test's are its own), or one list for every split")
    for key in value:
        if key not in ("train", "dev", "test"):
            raise error(f"unknown split '{key}'{did_you_mean(key, ('train', 'dev', 'test'))} (train, dev, test)")
    train = _asset_list(value["train"], lambda m: error(f"train: {m}"))
    test = _asset_list(value.get("test", value["train"]), lambda m: error(f"test: {m}"))
    if "dev" not in value:
        return Assets(train, test)
    dev = _asset_list(value["dev"], lambda m: error(f"dev: {m}"))
    return Assets(train, dev, test)


def _asset_list(names: Any, error) -> Tuple[str, ...]:
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise error("expected a non-empty list of asset names")
    for asset in names:
        try:
            asset_info(asset)
        except ValueError as exc:
            raise error(f"{exc}{did_you_mean(asset, asset_names())}") from None
    return tuple(names)


def _distractors(value: Any, error) -> Optional[Distractors]:
    if value is None:
        return None
    fields = ("pool", "count", "region")
    if not isinstance(value, dict) or set(value) != set(fields):
        raise error("distractors: expected {\"pool\": [ASSET, ...], \"count\": [MIN, MAX], "
                    "\"region\": [[X0, X1], [Y0, Y1]]} (on the table, whose top is at z = 0)", "distractors")
    pool = _asset_list(value["pool"], lambda m: error(f"distractors: pool: {m}", "distractors"))
    count = value["count"]
    if not (isinstance(count, list) and len(count) == 2 and all(isinstance(c, int) and c >= 0 for c in count)
            and count[0] <= count[1]):
        raise error("distractors: count: expected [MIN, MAX], whole numbers", "distractors")
    region = value["region"]
    if not (isinstance(region, list) and len(region) == 2 and not any(_pair(r) for r in region)):
        raise error("distractors: region: expected [[X0, X1], [Y0, Y1]] in metres", "distractors")
    return Distractors(pool, (count[0], count[1]), tuple((float(a), float(b)) for a, b in region))


def _pairs(value: Any, error) -> Tuple[Tuple[str, str], ...]:
    if not isinstance(value, list) or not all(isinstance(v, list) and len(v) == 2 for v in value):
        raise error("overlaps_ok: expected [[NAME, NAME], ...]", "overlaps_ok")
    return tuple((str(a), str(b)) for a, b in value)


def _number(value: Any) -> Optional[str]:
    return None if isinstance(value, (int, float)) and not isinstance(value, bool) else \
        f"expected a number, got {json.dumps(value)}"


def _number_or_null(value: Any) -> Optional[str]:
    return None if value is None else _number(value)


def _pair(value: Any) -> Optional[str]:
    if not isinstance(value, list) or len(value) != 2 or any(_number(v) for v in value):
        return f"expected two numbers, got {json.dumps(value)}"
    return None


def _tilt(value: Any) -> Optional[str]:
    return _pair(value) or (None if all(-180 <= v <= 180 for v in value)
                            else "expected [ROLL, PITCH] in degrees, each within -180..180")


def _scale_range(value: Any) -> Optional[str]:
    return _pair(value) or (None if 0 < value[0] <= value[1] else "expected [LOW, HIGH] with 0 < LOW <= HIGH")


def _name_or_null(value: Any) -> Optional[str]:
    return None if value is None or isinstance(value, str) else "expected an object's name or null"


def _bool(value: Any) -> Optional[str]:
    return None if isinstance(value, bool) else "expected true or false"


# ---------------------------------------------------------------------- writing
def dump_document(document: Dict[str, Any]) -> str:
    """JSON with one object field per line and short lists kept on one line."""
    text = json.dumps(document, indent=1)
    return re.sub(r"\[[^\[\]{}]*\]", lambda m: json.dumps(json.loads(m.group(0))), text) + "\n"


def task_document(task: TaskSpec) -> Dict[str, Any]:
    """The full form of `task` (every object in full, no problem): `task_from_document`
    gives the same TaskSpec back."""
    objects: Dict[str, Dict[str, Any]] = {}
    for spec in task.objects:
        assets = spec.assets
        fields: Dict[str, Any] = {"assets": {"train": list(assets.train), "dev": list(assets.dev),
                                             "test": list(assets.test_only)} if assets.test_only else
                                  {"train": list(assets.train), "test": list(assets.dev)},
                                  "xy": list(spec.xy), "yaw": spec.yaw, "on": spec.on, "fixed": spec.fixed,
                                  "shift": list(spec.noise_xy), "turn": spec.noise_yaw, "scale": list(spec.scale)}
        optional = {"z": spec.z or None, "tilt": list(spec.tilt) if any(spec.tilt) else None, "frame": spec.frame, "surface": spec.surface, "mass": spec.mass,
                    "friction": spec.friction,
                    "match": spec.match, "role": spec.role or None}
        fields.update({k: v for k, v in optional.items() if v is not None})
        if spec.align is not None:
            fields["align"] = {"side": spec.align.side, "at": spec.align.at, "fraction": spec.align.fraction,
                               "noise": spec.align.noise}
        if spec.yaw_by_category:
            fields["yaw_by_category"] = dict(spec.yaw_by_category)
        if spec.slides:
            fields["slides"] = True
        objects[spec.name] = fields
    document: Dict[str, Any] = {"format": FORMAT, "name": task.name, "title": task.title,
                                "description": task.description, "goal": task.goal, "objects": objects}
    if task.distractors is not None:
        d = task.distractors
        document["distractors"] = {"pool": list(d.pool), "count": list(d.count), "region": [list(r) for r in d.region]}
    if task.overlaps_ok:
        document["overlaps_ok"] = [list(pair) for pair in task.overlaps_ok]
    if task.demo:
        document["demo"] = task.demo
    return document


__all__: List[str] = ["TaskFileError", "is_task_file", "load_task_file", "task_document", "task_from_document",
                      "task_from_problem"]
