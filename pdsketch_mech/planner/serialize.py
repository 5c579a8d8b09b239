"""Sampled values <-> JSON, so a plan's continuous parameters can be saved and replayed."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Dict, List, Sequence

import numpy as np

from ..world.values import Contact, Grasp, Placement, Trajectory

if TYPE_CHECKING:
    from .skeleton import Step


def _pose(pose) -> list:
    return [list(map(float, pose[0])), list(map(float, pose[1]))]


def _unpose(data) -> tuple:
    return tuple(data[0]), tuple(data[1])


def to_json(value: object) -> Dict[str, Any]:
    if isinstance(value, Grasp):
        return {"type": "grasp", "object": value.object, "in_object": _pose(value.in_object), "width": value.width,
                "points": [list(map(float, p)) for p in value.points]}
    if isinstance(value, Placement):
        return {"type": "placement", "object": value.object, "support": value.support, "pose": _pose(value.pose),
                "support_normal": list(map(float, value.support_normal))}
    if isinstance(value, Contact):
        return {"type": "contact", "pusher": value.pusher, "target": value.target, "support": value.support,
                "pusher_pose": _pose(value.pusher_pose), "direction": list(map(float, value.direction)),
                "point": list(map(float, value.point)), "normal": list(map(float, value.normal))}
    if isinstance(value, Trajectory):
        # Full precision: replay must execute exactly what the planner executed.
        return {"type": "trajectory", "kind": value.kind, "approach": value.approach.tolist(),
                "final": value.final.tolist(), "push_distance": value.push_distance}
    raise TypeError(f"cannot serialise {type(value).__name__}")


def plan_entries(steps: Sequence["Step"], values: Sequence[Dict[str, object]]) -> List[Dict[str, Any]]:
    """A refined skeleton as the `plan` entries of the JSON document (what `replay` reads).
    A placeholder a later step draws again (two pushes from one optimistic contact) is another
    value: it is named apart there (`#contact4`, then `#contact4.2`)."""
    drawn: Dict[str, int] = {}
    entries = []
    for step, step_values in zip(steps, values):
        names = {}
        for name in step_values:
            drawn[name] = drawn.get(name, 0) + 1
            names[name] = name if drawn[name] == 1 else f"{name}.{drawn[name]}"
        entries.append({"name": step.name, "args": [names.get(a, a) for a in step.args], "mechanism": step.mechanism,
                        "params": {names[name]: to_json(value) for name, value in step_values.items()}})
    return entries


def from_json(data: Dict[str, Any]) -> object:
    kind = data.get("type")
    if kind == "grasp":
        return Grasp(data["object"], _unpose(data["in_object"]), data["width"], tuple(map(tuple, data["points"])))
    if kind == "placement":
        return Placement(data["object"], data["support"], _unpose(data["pose"]), tuple(data["support_normal"]))
    if kind == "contact":
        return Contact(data["pusher"], data["target"], data["support"], _unpose(data["pusher_pose"]),
                       tuple(data["direction"]), tuple(data["point"]), tuple(data["normal"]))
    if kind == "trajectory":
        final = np.array(data["final"]).reshape(-1, 7)
        return Trajectory(data["kind"], np.array(data["approach"]).reshape(-1, 7), final,
                          push_distance=data["push_distance"])
    raise ValueError(f"unknown parameter type {kind!r}")
