"""Demonstration files: a JSON list of hand commands (docs/demonstrations.md), checked before
anything is simulated and then executed through the demonstration API (`hand.Hand`).

    {"format": 1, "problem": "scene.pddl", "steps": [
        {"do": "open"},
        {"do": "move", "to": {"object": "box", "at": "top"}},
        {"do": "grasp", "object": "box"}, ...]}

Every error names the file, the line and column of the step, the step's number and kind, and
the field: `pivot.demo.json:12:5: error: step 4 (grasp): object: 'taget' is not an object of
the scene (did you mean 'target'?)`.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from numbers import Real
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

from ...lang.errors import did_you_mean
from .anchors import FACE_WORDS, WORLD_WORDS, check_words
from .hand import Hand
from .motion import DemoError

FORMAT = 1
SUFFIX = ".demo.json"
TOP_FIELDS = {"format", "problem", "name", "description", "steps"}


class DemoFileError(ValueError):
    """A demonstration file that is malformed, or a step that failed: one located line."""


@dataclass(frozen=True)
class HandCommand:
    number: int          # 1-based
    kind: str
    fields: Dict[str, Any]
    line: int
    column: int


@dataclass
class DemoFile:
    path: str
    problem_path: str
    name: str
    description: str
    steps: List[HandCommand] = field(default_factory=list)
    text: str = ""

    def where(self, step: Optional[HandCommand] = None) -> str:
        return f"{self.path}:{step.line}:{step.column}" if step else self.path


def default_stem(path: str) -> str:
    """`pivot` for `pivot.demo.json` (or `pivot.json`)."""
    base = os.path.basename(path)
    for suffix in (SUFFIX, ".json", ".py"):
        if base.endswith(suffix):
            return base[:-len(suffix)]
    return base


# ---------------------------------------------------------------------- reading
def read_demo_file(path: str) -> DemoFile:
    """Parse and check the file's structure (objects are checked against the scene by
    `check_names`); DemoFileError with one located line."""
    try:
        with open(path, encoding="utf-8") as handle:
            text = handle.read()
    except (OSError, UnicodeDecodeError) as exc:
        raise DemoFileError(f"{path}: error: cannot read it ({exc})") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise DemoFileError(f"{path}:{exc.lineno}:{exc.colno}: error: not JSON: {json_hint(text, exc)}") from None
    if not isinstance(data, dict):
        raise DemoFileError(f"{path}:1:1: error: a demonstration is a JSON object with \"format\" and \"steps\"")
    unknown = sorted(set(data) - TOP_FIELDS)
    if unknown:
        raise DemoFileError(f"{path}: error: unknown field '{unknown[0]}'{did_you_mean(unknown[0], TOP_FIELDS)} "
                            f"(fields: {', '.join(sorted(TOP_FIELDS))})")
    if data.get("format") != FORMAT:
        got = "it is missing" if "format" not in data else f"got {json.dumps(data['format'])}"
        raise DemoFileError(f"{path}: error: format: expected \"format\": {FORMAT} (the only format there is); {got}")
    stem = default_stem(path)
    problem = data.get("problem", stem + ".pddl")
    for key in ("problem", "name", "description"):
        if key in data and not isinstance(data[key], str):
            raise DemoFileError(f"{path}: error: {key}: expected a string")
    raw_steps = data.get("steps")
    if not isinstance(raw_steps, list) or not raw_steps:
        raise DemoFileError(f"{path}: error: steps: expected a non-empty list of steps")
    places = step_positions(text)
    demo = DemoFile(path, os.path.join(os.path.dirname(path), problem), data.get("name", stem),
                    data.get("description", ""), text=text)
    for number, raw in enumerate(raw_steps, 1):
        line, column = places[number - 1] if number - 1 < len(places) else (1, 1)
        step = HandCommand(number, str(raw.get("do")) if isinstance(raw, dict) else "?", raw if isinstance(raw, dict) else {},
                    line, column)
        problem_text = check_step(raw)
        if problem_text:
            raise DemoFileError(f"{demo.where(step)}: error: step {number} ({step.kind}): {problem_text}")
        demo.steps.append(step)
    return demo


def json_hint(text: str, exc: json.JSONDecodeError) -> str:
    """The parser's message, and the likely slip when it is a trailing comma."""
    before = text[:exc.pos].rstrip()
    if before.endswith(",") and text[exc.pos:exc.pos + 1] in ("]", "}"):
        return f"{exc.msg} (a comma before '{text[exc.pos]}'? JSON allows none after the last item)"
    return exc.msg


def step_positions(text: str) -> List[Tuple[int, int]]:
    """(line, column) where each element of the top-level `steps` list starts."""
    decoder = json.JSONDecoder()
    key = text.find('"steps"')
    start = text.find("[", key) if key >= 0 else -1
    found: List[Tuple[int, int]] = []
    if start < 0:
        return found
    index = start + 1
    while index < len(text):
        while index < len(text) and text[index] in " \t\r\n,":
            index += 1
        if index >= len(text) or text[index] == "]":
            break
        line = text.count("\n", 0, index) + 1
        column = index - (text.rfind("\n", 0, index) + 1) + 1
        found.append((line, column))
        try:
            _, index = decoder.raw_decode(text, index)
        except json.JSONDecodeError:
            break
    return found


# ---------------------------------------------------------------------- checking
Check = Callable[[Any], Optional[str]]


def _number(value: Any, low: float = float("-inf"), what: str = "a number") -> Optional[str]:
    if isinstance(value, bool) or not isinstance(value, Real):
        return f"expected {what}, got {json.dumps(value)}"
    if value < low:
        return f"expected {what}, got {value}"
    return None


def distance(value: Any) -> Optional[str]:
    return _number(value, 0.0, "a distance in metres (>= 0)")


def positive(value: Any) -> Optional[str]:
    problem = _number(value, 0.0, "a positive number")
    return problem or (None if value > 0 else "expected a positive number, got 0")


def number(value: Any) -> Optional[str]:
    return _number(value)


def name(value: Any) -> Optional[str]:
    return None if isinstance(value, str) and value else f"expected an object's name, got {json.dumps(value)}"


def names(value: Any) -> Optional[str]:
    if not isinstance(value, list):
        return "expected a list of object names"
    return next((name(v) for v in value if name(v)), None)


def vector(value: Any) -> Optional[str]:
    if not isinstance(value, list) or len(value) != 3 or any(_number(v) for v in value):
        return f"expected [x, y, z] (three numbers), got {json.dumps(value)}"
    return None


def anchor(value: Any) -> Optional[str]:
    if not isinstance(value, str):
        return f"expected face words such as \"top\" or \"far top\", got {json.dumps(value)}"
    return check_words(value)


def offset(value: Any) -> Optional[str]:
    if isinstance(value, list):
        return vector(value)
    if not isinstance(value, dict):
        return "expected [dx, dy, dz] or {\"far\": 0.005, \"up\": 0.02, ...}"
    for word, metres in value.items():
        if word not in FACE_WORDS and word not in WORLD_WORDS:
            return (f"unknown offset '{word}'{did_you_mean(word, FACE_WORDS + tuple(WORLD_WORDS))} "
                    f"(a face: {', '.join(FACE_WORDS)}; or up, down)")
        problem = _number(metres, what=f"metres for '{word}'")
        if problem:
            return problem
    return None


def point(value: Any) -> Optional[str]:
    if isinstance(value, list):
        return vector(value)
    if not isinstance(value, dict):
        return "expected [x, y, z] or {\"object\": NAME, \"at\": FACES, \"offset\": ...}"
    return _nested(value, {"object": (name, True), "at": (anchor, False), "offset": (offset, False)})


def direction(value: Any) -> Optional[str]:
    if isinstance(value, str):
        return None if value in WORLD_WORDS else f"unknown direction '{value}' (up, down, [x, y, z], {{object, face}}, {{from, to}})"
    if isinstance(value, list):
        problem = vector(value)
        return problem or (None if any(v != 0 for v in value) else "the direction [0, 0, 0] has no length")
    if not isinstance(value, dict):
        return "expected up, down, [x, y, z], {\"object\": NAME, \"face\": WORD} or {\"from\": POINT, \"to\": POINT}"
    if "face" in value or "object" in value:
        return _nested(value, {"object": (name, True), "face": (anchor, True), "horizontal": (boolean, False)})
    return _nested(value, {"from": (point, True), "to": (point, True), "horizontal": (boolean, False)})


def boolean(value: Any) -> Optional[str]:
    return None if isinstance(value, bool) else "expected true or false"


def until(value: Any) -> Optional[str]:
    if not isinstance(value, dict) or len(value) != 1 or next(iter(value)) not in ("moves", "touches"):
        return "expected {\"moves\": NAME} or {\"touches\": NAME}"
    return name(next(iter(value.values())))


def fingers(value: Any) -> Optional[str]:
    return None if value in (1, 2) and not isinstance(value, bool) else "expected 1 or 2"


def text(value: Any) -> Optional[str]:
    return None if isinstance(value, str) else "expected a string"


# kind -> {field: (check, required)}; every step may carry a "note" for the reader.
STEP_FIELDS: Dict[str, Dict[str, Tuple[Check, bool]]] = {
    "open": {},
    "close": {},
    "release": {},
    "grasp": {"object": (name, True), "fingers": (fingers, False)},
    "move": {"to": (point, True), "approach": (direction, False), "closing": (direction, False),
             "back": (distance, False), "ignore": (names, False)},
    "line": {"direction": (direction, True), "distance": (distance, False), "to": (point, False),
             "until": (until, False), "speed": (positive, False)},
    "lift": {"distance": (distance, True)},
    "lower": {"distance": (distance, True), "speed": (positive, False)},
    "wait": {"seconds": (distance, False)},
    "put": {"point": (anchor, False), "at": (point, True), "offset": (offset, False), "turn": (number, False),
            "back": (distance, False), "approach": (direction, False), "ignore": (names, False)},
}


def _fields(value: Dict[str, Any], spec: Dict[str, Tuple[Check, bool]], path: str = "") -> Optional[str]:
    for key in value:
        if key not in spec:
            return (f"{path}unknown field '{key}'{did_you_mean(key, spec)} "
                    f"(fields: {', '.join(spec) or 'none'})")
    for key, (check, required) in spec.items():
        if key not in value:
            if required:
                return f"{path}{key}: missing"
            continue
        problem = check(value[key])
        if problem:
            # A nested object's checks name their own field (".at: ..."): join the paths.
            return f"{path}{key}{problem}" if problem.startswith(".") else f"{path}{key}: {problem}"
    return None


def _nested(value: Dict[str, Any], spec: Dict[str, Tuple[Check, bool]]) -> Optional[str]:
    """`_fields` for an object inside a field: its problem names the inner field (".at: ...")."""
    problem = _fields(value, spec)
    if problem is None or problem.startswith("unknown field"):
        return problem
    return "." + problem


def check_step(raw: Any) -> Optional[str]:
    """Why `raw` is no step (its fields' shapes; names are checked against the scene later)."""
    if not isinstance(raw, dict):
        return "a step is an object such as {\"do\": \"open\"}"
    kind = raw.get("do")
    if not isinstance(kind, str) or kind not in STEP_FIELDS:
        known = ", ".join(STEP_FIELDS)
        if kind is None:
            return f"do: missing (one of {known})"
        return f"do: unknown command {json.dumps(kind)}{did_you_mean(str(kind), STEP_FIELDS)} (commands: {known})"
    spec = dict(STEP_FIELDS[kind], do=(text, True), note=(text, False))
    problem = _fields(raw, spec)
    if problem is None and kind == "line":
        given = [k for k in ("distance", "to") if k in raw]
        if not given and "until" not in raw:
            problem = ("give a distance, a point to go \"to\", or \"until\" {\"moves\": NAME} / "
                       "{\"touches\": NAME} (with a distance: the most it may go)")
        elif len(given) == 2:
            problem = "give a distance or a point to go \"to\", not both"
    return problem


def mentioned_names(value: Any, key: str = "") -> List[Tuple[str, str]]:
    """(field path, object name) for every object a step's field names."""
    found: List[Tuple[str, str]] = []
    if isinstance(value, dict):
        for k, v in value.items():
            path = f"{key}.{k}" if key else k
            if k in ("object", "moves", "touches") and isinstance(v, str):
                found.append((path, v))
            elif k == "ignore" and isinstance(v, list):
                found.extend((path, n) for n in v if isinstance(n, str))
            else:
                found.extend(mentioned_names(v, path))
    return found


def check_names(demo: DemoFile, objects: Sequence[str]) -> None:
    """Every object a step names is in the scene; DemoFileError naming the first that is not."""
    for step in demo.steps:
        for path, value in mentioned_names(step.fields):
            if value not in objects:
                raise DemoFileError(f"{demo.where(step)}: error: step {step.number} ({step.kind}): {path}: "
                                    f"'{value}' is not an object of the scene{did_you_mean(value, objects)} "
                                    f"(objects: {', '.join(objects)})")


# ---------------------------------------------------------------------- executing
def execute(demo: DemoFile, hand: Hand, on_step: Optional[Callable[[HandCommand], None]] = None) -> None:
    """Run every step through `hand`; a step that cannot be done raises DemoFileError
    naming it."""
    for step in demo.steps:
        if on_step is not None:
            on_step(step)
        try:
            run_step(hand, step)
        except DemoError as exc:
            raise DemoFileError(f"{demo.where(step)}: error: step {step.number} ({step.kind}): {exc}") from None


def run_step(hand: Hand, step: HandCommand) -> None:
    f, kind = step.fields, step.kind
    if kind in ("open", "close", "release"):
        getattr(hand, kind)()
    elif kind == "grasp":
        hand.grasp(f["object"], f.get("fingers", 2))
    elif kind == "move":
        target = f["to"]
        near = target.get("object") if isinstance(target, dict) else None
        hand.move_to(hand.place(target), hand.direction(f.get("approach", "down")),
                     hand.direction(f["closing"]) if "closing" in f else None, f.get("back", 0.08),
                     f.get("ignore", ()), near)
    elif kind == "line":
        stop, way = f.get("until", {}), hand.direction(f["direction"])
        length = hand.distance_to(hand.place(f["to"]), way) if "to" in f else f.get("distance")
        hand.line(way, length, stop.get("moves"), stop.get("touches"), f.get("speed", 0.15))
    elif kind == "lift":
        hand.lift(f["distance"])
    elif kind == "lower":
        hand.lower(f["distance"], f.get("speed", 0.15))
    elif kind == "wait":
        hand.wait(f.get("seconds"))
    elif kind == "put":
        hand.put(f.get("point", "bottom"), hand.place(f["at"]), f.get("offset"), f.get("back", 0.05),
                 hand.direction(f.get("approach", "down")), f.get("ignore", ()), f.get("turn", 0.0))
    else:  # check_step admits only the kinds above
        raise DemoError(f"unknown command {kind!r}")
