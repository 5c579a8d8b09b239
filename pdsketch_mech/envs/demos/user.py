"""A user's demonstration, performed and recorded in the scene of a problem file.

Two forms, one API: a demonstration file of hand commands (`NAME.demo.json`, demo_file.py),
or a Python file defining `demonstrate(hand)` that calls the same `hand.Hand` methods (and
may set `PROBLEM = "scene.pddl"`; default: the file's name with `.pddl`). With a seed, the
scene is perturbed first: every movable object standing on a fixed one (or on nothing) is
shifted and turned about z at random, what stands on it moving along.
"""
from __future__ import annotations

import importlib.util
import math
import os
import traceback
from dataclasses import dataclass, replace
from typing import Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np
import pybullet as p

from ...lang.errors import PddlError
from ...lang.nodes import Problem, SceneEntry, SceneProp
from ...lang.parser import parse_file, parse_text
from ...lang.scene import build_scene
from ...lang.writer import write_problem
from ...world.build import build_world
from ...world.world import World
from .demo_file import DemoFileError, HandCommand, check_names, default_stem, execute, read_demo_file
from .hand import Hand, scene_boxes
from .motion import DemoError
from .run import DemoResult, perform

SHIFT = 0.02                 # metres: the largest shift of a perturbed object, along x and along y
TURN = 10.0                  # degrees: the largest turn about z
DRAWS = 20                   # perturbations tried before giving up on a crowded scene


@dataclass
class UserDemo:
    path: str
    problem_path: str
    name: str
    description: str
    act: Callable[[Hand], None]
    text: str                 # the demonstration file's text, or the script's
    check: Callable[[Sequence[str]], None] = lambda objects: None   # DemoFileError for a name not in the scene
    steps: Optional[int] = None   # how many steps a demonstration file has (a script's are unknown)


def load_user_demo(path: str, on_step: Optional[Callable[[HandCommand], None]] = None) -> UserDemo:
    """A demonstration file or Python script; DemoFileError (one located line) if malformed."""
    if not os.path.isfile(path):
        raise DemoFileError(f"{path}: error: no such file")
    if path.endswith(".py"):
        return _load_script(path)
    demo = read_demo_file(path)

    def act(hand: Hand) -> None:
        execute(demo, hand, on_step)
    return UserDemo(path, demo.problem_path, demo.name, demo.description, act, demo.text,
                    lambda objects: check_names(demo, objects), len(demo.steps))


def _load_script(path: str) -> UserDemo:
    with open(path, encoding="utf-8") as handle:
        source = handle.read()
    spec = importlib.util.spec_from_file_location(f"_demo_{default_stem(path).replace('-', '_')}", path)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)   # the user's own script, run as they asked
    except Exception as exc:  # noqa: BLE001 -- any failure of the user's code is reported, located
        raise DemoFileError(f"{_script_place(path, exc)}: error: the script failed to load: "
                            f"{type(exc).__name__}: {exc}") from None
    demonstrate = getattr(module, "demonstrate", None)
    if not callable(demonstrate):
        raise DemoFileError(f"{path}: error: a Python demonstration defines demonstrate(hand)")
    problem = getattr(module, "PROBLEM", default_stem(path) + ".pddl")
    description = (module.__doc__ or "").strip().split("\n\n")[0]

    def act(hand: Hand) -> None:
        try:
            demonstrate(hand)
        except DemoError as exc:
            raise DemoFileError(f"{_script_place(path, exc)}: error: {exc}") from None
        except Exception as exc:  # noqa: BLE001 -- a bug in the user's script, located in it
            raise DemoFileError(f"{_script_place(path, exc)}: error: the script failed: "
                                f"{type(exc).__name__}: {exc}") from None
    return UserDemo(path, os.path.join(os.path.dirname(path), problem), getattr(module, "NAME", default_stem(path)),
                    description, act, source)


def _script_place(path: str, exc: BaseException) -> str:
    """`path:LINE` of the deepest frame of the script in `exc`'s traceback."""
    line = None
    for frame in traceback.extract_tb(exc.__traceback__):
        if os.path.abspath(frame.filename) == os.path.abspath(path):
            line = frame.lineno
    if line is None and isinstance(exc, SyntaxError) and exc.lineno:
        line = exc.lineno
    return f"{path}:{line}" if line else path


def load_problem(demo: UserDemo) -> Problem:
    """The scene problem the demonstration is performed in; PddlError/DemoFileError if unusable."""
    if not os.path.isfile(demo.problem_path):
        raise DemoFileError(f"{demo.path}: error: problem: {demo.problem_path}: no such file "
                            "(\"problem\" names the scene's problem file, relative to the demonstration)")
    problem = parse_file(demo.problem_path)
    if not isinstance(problem, Problem):
        raise DemoFileError(f"{demo.problem_path}: error: a domain, not a problem")
    if not problem.scene:
        raise DemoFileError(f"{demo.problem_path}: error: the problem has no :scene to perform the demonstration in")
    demo.check([o.name for o in build_scene(problem)])
    return problem


# ---------------------------------------------------------------------- perturbation
def perturbed(problem: Problem, seed: int, shift: float = SHIFT, turn: float = TURN) -> Problem:
    """`problem` with its movable objects moved at random (see the module's docstring): the
    first of `DRAWS` draws whose scene builds; the problem itself if none does."""
    objects = {o.name: o for o in build_scene(problem)}
    roots = [o.name for o in objects.values() if not o.fixed
             and (o.support is None or objects.get(o.support) is None or objects[o.support].fixed)]
    rng = np.random.default_rng(seed)
    for _ in range(DRAWS):
        moves = {name: (rng.uniform(-shift, shift, 2), math.radians(rng.uniform(-turn, turn))) for name in roots}
        candidate = _moved(problem, objects, moves)
        try:
            build_world(candidate, visual=False).close()
            return candidate
        except PddlError:
            continue
    return problem


def _root(name: str, objects) -> str:
    while objects[name].support in objects and not objects[objects[name].support].fixed:
        name = objects[name].support
    return name


def _moved(problem: Problem, objects, moves: Dict[str, Tuple[np.ndarray, float]]) -> Problem:
    entries: List[SceneEntry] = []
    for entry in problem.scene:
        obj = objects[entry.name]
        root = _root(entry.name, objects) if not obj.fixed else None
        if root not in moves:
            entries.append(entry)
            continue
        (dx, dy), yaw = moves[root]
        pivot = np.asarray(objects[root].position[:2])
        c, s = math.cos(yaw), math.sin(yaw)
        xy = pivot + np.array([[c, -s], [s, c]]) @ (np.asarray(obj.position[:2]) - pivot) + (dx, dy)
        position = (float(xy[0]), float(xy[1])) + (() if obj.rest else (float(obj.position[2]),))
        turned = p.multiplyTransforms((0, 0, 0), p.getQuaternionFromEuler((0, 0, yaw)), (0, 0, 0), obj.orientation)[1]
        props = [q for q in entry.props if q.key not in (":position", ":quat", ":rpy", ":rpy-deg")]
        props += [SceneProp(":position", position), SceneProp(":quat", tuple(float(v) for v in turned))]
        entries.append(replace(entry, props=tuple(props)))
    return parse_text(write_problem(replace(problem, scene=tuple(entries))), file="<perturbed>")


# ---------------------------------------------------------------------- performing
def perform_user_demo(demo: UserDemo, problem: Problem, seed: Optional[int] = None, record: bool = True) -> DemoResult:
    """Perform `demo` in `problem`'s scene (perturbed with `seed`, if given) and record it;
    a failed step is in the result's `error` (one located line)."""
    if seed is not None:
        problem = perturbed(problem, seed)
    boxes = scene_boxes(build_scene(problem))

    def act(world: World) -> None:
        demo.act(Hand(world, boxes, seed or 0))
    return perform(problem, act, record, errors=(DemoError, DemoFileError))

