"""A saved plan (`plan --json`), checked against its problem and domain before replay.

Replay trusts every name and number it is given, so a plan from another problem, a
misspelt action or a NaN joint angle used to end in a traceback halfway through a
simulation. `load_plan` checks the whole document first — its JSON, its shape, each step's
action, arity, objects and parameter values (the schema of `serialize.from_json`, finite
numbers, 7 joints a waypoint) — and reports the first problem as one located line,
`PLAN.json:LINE:COL: error: step 2 (grasp): ...`. Pure Python: nothing here needs PyBullet.
"""
from __future__ import annotations

import json
import math
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

from ..lang.errors import PddlError, did_you_mean, escape
from ..lang.loader import LoadedDomain
from ..lang.nodes import Action, Loc, Problem
from ..lang.source import read_text
from ..world.values import OPERATOR_VALUES as EXECUTED

Path = Tuple[Union[str, int], ...]  # keys and indices from the document's root to a value

# What `execute.run_step` executes, and the kinds of value (`serialize.to_json`) each operator uses.
OPERATOR_VALUES = {name: tuple(kind.__name__.lower() for kind in kinds) for name, kinds in EXECUTED.items()}
# The basis domain's value types and the kind of value (`serialize.to_json`) each holds.
VALUE_KINDS = {"grasp": "grasp", "placement": "placement", "contact": "contact", "traj": "trajectory",
               "conf": "trajectory"}
TRAJECTORY_KINDS = ("free", "grasp", "place", "held", "push")
JOINTS = 7
# Which simulation of motions (operators/execution.py) a plan was found with: its values hold
# under that one (a push amplifies any change of physics), so it is raised when that changes.
# 1: every contact motion simulated throughout; 2: free tails and free finger moves teleported.
EXECUTION_MODEL = 2
MAX_JOINT = 2 * math.pi  # radians: every Panda joint limit is within


class _Invalid(Exception):
    """A problem at `path` in the document (turned into a located PddlError)."""

    def __init__(self, path: Path, message: str):
        super().__init__(message)
        self.path, self.message = path, message


def plan_document(status: str, reason: str, time_s: float, seed: int, plan: List[Dict[str, Any]],
                  stats: Dict[str, Any], problem: str) -> Dict[str, Any]:
    """The `plan --json` document (docs/commands.md), for classical and manipulation plans
    alike; `problem` (its name) lets replay refuse the plan for another problem."""
    return {"status": status, "reason": reason, "time_s": round(time_s, 6), "seed": seed,
            "problem": problem, "execution_model": EXECUTION_MODEL, "plan": plan, "stats": stats}


def stale_model_note(document: Any) -> Optional[str]:
    """Why a decoded plan may not replay here: it was found with another execution model
    (plans saved before they said were model 1); None if it was not."""
    model = document.get("execution_model", 1) if isinstance(document, dict) else 1
    if model == EXECUTION_MODEL:
        return None
    shown = model if isinstance(model, int) and not isinstance(model, bool) else "unknown"
    return (f"the plan was found with execution model {escape(str(shown))}, and this version simulates motions "
            f"with model {EXECUTION_MODEL}: plan again to replay it here")


def load_plan(path: str, domain: LoadedDomain, problem: Problem) -> List[Dict[str, Any]]:
    """The steps of the plan saved at `path`, valid for `problem`; else a located PddlError."""
    if problem.scene is None:
        raise PddlError(f"problem '{problem.name}' has no :scene to replay a plan in", problem.loc)
    text = read_text(path)
    try:
        document = json.loads(text)
    except json.JSONDecodeError as exc:
        raise PddlError(f"not valid JSON: {exc.msg}", Loc(path, exc.lineno, exc.colno)) from None
    except (ValueError, RecursionError) as exc:  # a 5,000-digit integer; arrays nested 100,000 deep
        raise PddlError(f"not a plan written by `plan --json`: {exc}", file=path) from None
    try:
        return _Checker(domain, problem).document(document)
    except _Invalid as invalid:
        raise PddlError(invalid.message, Loc(path, *locate(text, invalid.path))) from None


def check_plan(document: Any, domain: LoadedDomain, problem: Problem) -> List[Dict[str, Any]]:
    """The steps of a decoded `plan --json` document (e.g. what `api.Planner.plan` returned),
    valid for `problem`; else a PddlError naming the first problem and where it is."""
    if problem.scene is None:
        raise PddlError(f"problem '{problem.name}' has no :scene to replay a plan in", problem.loc)
    try:
        return _Checker(domain, problem).document(document)
    except _Invalid as invalid:
        where = "".join(f"[{key!r}]" for key in invalid.path)
        raise PddlError(f"plan{where}: {invalid.message}") from None


class _Checker:
    """Checks a decoded document; raises `_Invalid` at the first problem."""

    def __init__(self, domain: LoadedDomain, problem: Problem):
        self.types = domain.types
        self.actions: Dict[str, Action] = {a.name: a for a in domain.domain.actions}
        self.mechanisms = {m.name for m in domain.domain.mechanisms}
        self.objects = {c.name: c.type for c in domain.domain.constants}
        self.objects.update((o.name, o.type) for o in problem.objects)
        self.scene = {entry.name for entry in problem.scene or ()}
        self.problem = problem

    def document(self, document: Any) -> List[Dict[str, Any]]:
        if not isinstance(document, dict) or not isinstance(document.get("plan"), list):
            raise _Invalid((), "not a plan written by `plan --json`: expected an object with a \"plan\" list")
        made_for = document.get("problem")   # absent in plans saved before it was recorded
        if made_for is not None and made_for != self.problem.name:
            where = f" ({self.problem.loc.file})" if self.problem.loc and self.problem.loc.file else ""
            raise _Invalid(("problem",), f"the plan was made for problem '{escape(str(made_for))}', not "
                                         f"'{self.problem.name}'{where}")
        for index, step in enumerate(document["plan"]):
            self.step(("plan", index), step)
        return document["plan"]

    def step(self, at: Path, step: Any) -> None:
        number = at[-1] + 1
        if not isinstance(step, dict) or not isinstance(step.get("name"), str):
            raise _Invalid(at, f"step {number}: expected an object with a \"name\", \"args\" and \"params\"")
        name = step["name"]
        where = f"step {number} ({name})"
        action = self._action(at + ("name",), name, where)
        args, params = step.get("args"), step.get("params")
        if not isinstance(args, list) or not all(isinstance(a, str) for a in args):
            raise _Invalid(at + ("args",) if "args" in step else at, f"{where}: \"args\" must be a list of names")
        if not isinstance(params, dict):
            raise _Invalid(at + ("params",) if "params" in step else at,
                           f"{where}: \"params\" must be an object (placeholder -> value)")
        if step.get("mechanism") is not None and not isinstance(step["mechanism"], str):
            raise _Invalid(at + ("mechanism",), f"{where}: \"mechanism\" must be a name or null")
        if len(args) != len(action.parameters):
            raise _Invalid(at + ("args",), f"{where}: '{name}' takes {len(action.parameters)} arguments, "
                                           f"got {len(args)}")
        for index, (arg, param) in enumerate(zip(args, action.parameters)):
            if not self.types.is_value(param.type):
                self._object(at + ("args", index), arg, param.type, f"{where}: argument {index + 1}")
            elif arg not in params:
                raise _Invalid(at + ("args", index), f"{where}: argument {index + 1} ({arg}) has no value in "
                                                     "\"params\"")
        for key, value in params.items():
            self.value(at + ("params", key), value, f"{where}: parameter '{key}'")
        kinds = set()
        for arg, param in zip(args, action.parameters):
            if self.types.is_value(param.type):
                kind, wanted = params[arg]["type"], VALUE_KINDS.get(param.type)
                if wanted is not None and kind != wanted:
                    raise _Invalid(at + ("params", arg, "type"), f"{where}: parameter '{arg}' is a {kind}, but "
                                                                 f"'{name}' takes a {wanted} there")
                kinds.add(kind)
        missing = [k for k in OPERATOR_VALUES[name] if k not in kinds]
        if missing:
            raise _Invalid(at + ("args",), f"{where}: no {missing[0]} among the arguments")

    def _action(self, at: Path, name: str, where: str) -> Action:
        if name in self.mechanisms:
            raise _Invalid(at, f"{where}: '{name}' is a mechanism; a saved plan lists its basis steps")
        action = self.actions.get(name)
        if action is None:
            raise _Invalid(at, f"{where}: unknown action '{name}'{did_you_mean(name, self.actions)}")
        if name not in OPERATOR_VALUES:
            raise _Invalid(at, f"{where}: '{name}' has no operator in the simulator; replay runs "
                               f"{', '.join(OPERATOR_VALUES)}")
        return action

    def _object(self, at: Path, name: Any, type_: Optional[str], what: str) -> None:
        """`name` is a scene object (of type `type_` when given)."""
        if not isinstance(name, str):
            raise _Invalid(at, f"{what} must be an object name")
        if name not in self.objects:
            raise _Invalid(at, f"{what}: unknown object '{name}'{did_you_mean(name, self.objects)} "
                               "(is the plan for another problem?)")
        if type_ is not None and not self.types.is_subtype(self.objects[name], type_):
            raise _Invalid(at, f"{what}: '{name}' is of type '{self.objects[name]}', not '{type_}'")
        if name not in self.scene:
            raise _Invalid(at, f"{what}: object '{name}' has no scene entry")

    # -- parameter values, as `serialize.to_json` writes them
    def value(self, at: Path, value: Any, what: str) -> None:
        if not isinstance(value, dict) or not isinstance(value.get("type"), str):
            raise _Invalid(at, f"{what} must be an object with a \"type\"")
        fields = _FIELDS.get(value["type"])
        if fields is None:
            raise _Invalid(at + ("type",), f"{what} has unknown type '{value['type']}'; expected "
                                           f"{', '.join(_FIELDS)}")
        for key, check in fields.items():
            if key not in value:
                raise _Invalid(at, f"{what} ({value['type']}) has no \"{key}\"")
            check(self, at + (key,), value[key], f"{what}: \"{key}\"")

    def _name(self, at: Path, value: Any, what: str) -> None:
        self._object(at, value, None, what)

    def _optional_name(self, at: Path, value: Any, what: str) -> None:
        if value is not None:
            self._object(at, value, None, what)

    def _pose(self, at: Path, value: Any, what: str) -> None:
        if not (isinstance(value, list) and len(value) == 2):
            raise _Invalid(at, f"{what} must be a pose [[x, y, z], [qx, qy, qz, qw]]")
        self._vector(at + (0,), value[0], what, 3)
        self._unit(at + (1,), value[1], f"{what}: the quaternion", 4)

    def _vector3(self, at: Path, value: Any, what: str) -> None:
        self._vector(at, value, what, 3)

    def _unit(self, at: Path, value: Any, what: str, length: int = 3) -> None:
        """A unit vector (a direction, a normal, a quaternion), as the planner writes them."""
        self._vector(at, value, what, length)
        if not math.isclose(math.sqrt(sum(v * v for v in value)), 1.0, abs_tol=1e-3):
            raise _Invalid(at, f"{what} must have length 1")

    def _vector(self, at: Path, value: Any, what: str, length: int, bound: float = math.inf) -> None:
        if not isinstance(value, list) or len(value) != length:
            raise _Invalid(at, f"{what} must be a list of {length} numbers")
        for index, number in enumerate(value):
            if not _finite(number) or abs(number) > bound:
                wanted = "a finite number" if bound == math.inf else f"a joint angle in [-{bound:.4g}, {bound:.4g}]"
                raise _Invalid(at + (index,), f"{what}: entry {index + 1} is {_show(number)}, not {wanted}")

    def _waypoints(self, at: Path, value: Any, what: str) -> None:
        if not isinstance(value, list):
            raise _Invalid(at, f"{what} must be a list of waypoints of {JOINTS} joint angles")
        for index, waypoint in enumerate(value):
            self._vector(at + (index,), waypoint, f"{what} waypoint {index + 1}", JOINTS, MAX_JOINT)

    def _points(self, at: Path, value: Any, what: str) -> None:
        if not isinstance(value, list):
            raise _Invalid(at, f"{what} must be a list of points")
        for index, point in enumerate(value):
            self._vector(at + (index,), point, f"{what} point {index + 1}", 3)

    def _width(self, at: Path, value: Any, what: str) -> None:
        if not (_finite(value) and value >= 0):
            raise _Invalid(at, f"{what} is {_show(value)}, not a finite number >= 0")

    def _distance(self, at: Path, value: Any, what: str) -> None:
        if value is not None and not _finite(value):
            raise _Invalid(at, f"{what} is {_show(value)}, not a finite number or null")

    def _kind(self, at: Path, value: Any, what: str) -> None:
        if value not in TRAJECTORY_KINDS:
            raise _Invalid(at, f"{what} is {_show(value)}, not one of {', '.join(TRAJECTORY_KINDS)}")


_FIELDS = {
    "grasp": {"object": _Checker._name, "in_object": _Checker._pose, "width": _Checker._width,
              "points": _Checker._points},
    "placement": {"object": _Checker._name, "support": _Checker._name, "pose": _Checker._pose,
                  "support_normal": _Checker._unit},
    "contact": {"pusher": _Checker._optional_name, "target": _Checker._name, "support": _Checker._name,
                "pusher_pose": _Checker._pose, "direction": _Checker._unit, "point": _Checker._vector3,
                "normal": _Checker._unit},
    "trajectory": {"kind": _Checker._kind, "approach": _Checker._waypoints, "final": _Checker._waypoints,
                   "push_distance": _Checker._distance},
}


def _finite(value: Any) -> bool:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:  # an integer too large for a float
        return False


def _show(value: Any) -> str:
    text = json.dumps(value) if not isinstance(value, float) else repr(value)
    return text if len(text) <= 24 else text[:16] + "..."


# ----------------------------------------------------------------------------- locating a value
_DECODER = json.JSONDecoder()
_WHITESPACE = " \t\n\r"


def locate(text: str, path: Sequence[Union[str, int]]) -> Tuple[int, int]:
    """Line and column (1-based) of the value at `path` in the JSON `text`, or of the deepest
    container on the way there that exists."""
    pos = _skip(text, 0)
    for key in path:
        found = _child(text, pos, key)
        if found is None:
            break
        pos = found
    return text.count("\n", 0, pos) + 1, pos - text.rfind("\n", 0, pos)


def _child(text: str, pos: int, key: Union[str, int]) -> Optional[int]:
    """Where the member `key` of the object (or item `key` of the array) at `pos` starts; the
    last one if a key repeats, as `json.loads` keeps the last."""
    opening = text[pos]
    if opening not in "{[" or isinstance(key, str) != (opening == "{"):
        return None
    found, index = None, 0
    pos = _skip(text, pos + 1)
    while text[pos] not in "}]":
        if opening == "{":
            name, pos = json.decoder.scanstring(text, pos + 1)
            pos = _skip(text, _skip(text, pos) + 1)  # past the ':'
        else:
            name, index = index, index + 1
        if name == key:
            found = pos
        _, pos = _DECODER.raw_decode(text, pos)
        pos = _skip(text, pos)
        if text[pos] == ",":
            pos = _skip(text, pos + 1)
    return found


def _skip(text: str, pos: int) -> int:
    while pos < len(text) and text[pos] in _WHITESPACE:
        pos += 1
    return pos
