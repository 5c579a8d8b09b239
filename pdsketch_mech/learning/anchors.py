"""What a demonstration did, per value variable of its mechanism: the anchors its samplers
propose first (samplers/anchored.py has the format and the transfer).

Which variable a value is, and which sampler draws it, is read from the basis domain: the
stream whose certified fact a step's operator requires names its sampler (`grasp`,
`contact`, `push-motion`); its inputs name the objects. The values come from the recording
at the step's frames: the gripper frame (forward kinematics of the recorded joints), the
objects' poses, and the contact rows between pusher and target.
"""
from __future__ import annotations

import json
import math
import re
from typing import Dict, List, Mapping, Optional, Tuple

import numpy as np

from ..lang.nodes import Action, Atom, Domain, Stream
from ..samplers.anchored import SCHEMA, edge_distance, reach_frame
from ..samplers.geometry import body_mesh, matrix_pose, pose_matrix
from ..symbolic.normalize import dnf
from ..world.robot import Kinematics
from ..world.world import World
from .extract import Extraction

# Metres: a pushed object that moved less than this tells no direction (the push's own
# direction, away from the contact, is used instead).
STILL = 0.005


def value_streams(basis: Domain, operator: str) -> Dict[int, Tuple[Stream, Tuple[int, ...]]]:
    """Per value parameter of `operator` (its position), the stream that draws it and the
    positions of the operator's parameters that stream takes as inputs."""
    action: Action = next(a for a in basis.actions if a.name == operator)
    position = {p.name: i for i, p in enumerate(action.parameters)}
    by_fact = {}
    for stream in basis.streams:
        for conj in dnf(stream.certified, {}):
            for lit in conj:
                if isinstance(lit.atom, Atom):
                    by_fact[lit.atom.predicate] = (stream, lit.atom)
    found: Dict[int, Tuple[Stream, Tuple[int, ...]]] = {}
    for conj in dnf(action.precondition, {}):
        for lit in conj:
            if not (lit.positive and isinstance(lit.atom, Atom)) or lit.atom.predicate not in by_fact:
                continue
            stream, certified = by_fact[lit.atom.predicate]
            slots = {t.name: a.name for t, a in zip(certified.args, lit.atom.args)}   # stream var -> op param
            outputs = [slots.get(o.name) for o in stream.outputs]
            inputs = tuple(position[slots[i.name]] for i in stream.inputs if slots.get(i.name) in position)
            for out in outputs:
                if out in position and position[out] not in found:
                    found[position[out]] = (stream, inputs)
    return found


def demonstration_anchors(extraction: Extraction, basis: Domain, world: World) -> Dict[str, object]:
    """The anchors file's content for `extraction` (module docstring); `world`: the
    demonstration's scene (for the objects' shapes and the robot's shoulder)."""
    recording = extraction.segmentation.recording
    arrays = recording.arrays
    names = extraction.names
    roles = extraction.lifted.roles
    segments = extraction.segmentation.segments
    kinematics = Kinematics()
    variables: Dict[str, object] = {}
    try:
        for step, call in zip(extraction.explanation.steps, extraction.lifted.mechanism.actions):
            segment = segments[step.segment]
            for slot, (stream, inputs) in sorted(value_streams(basis, step.operator).items()):
                variable = call.args[slot].name
                objects = [step.objects[i] for i in inputs if i < len(step.objects)]
                sampler = stream.sampler or stream.name
                anchor = None
                if sampler == "grasp" and objects:
                    anchor = _grasp(world, kinematics, arrays, names, objects[0], step.frame, roles)
                elif sampler == "contact" and len(objects) >= 2:
                    anchor = _contact(world, kinematics, recording, names, _pusher(step), objects[-2],
                                      (segment.start, segment.end), roles)
                elif sampler == "push-motion":
                    anchor = _push(world, kinematics, extraction, step, (segment.start, segment.end))
                if anchor is not None:
                    variables[variable] = anchor
    finally:
        kinematics.close()
    return {"schema": SCHEMA, "mechanism": extraction.name, "source": extraction.source, "variables": variables}


def anchors_text(anchors: Mapping[str, object]) -> str:
    """The file's text: stable (sorted keys, rounded to 0.1 mm / 1e-4), a vector per line."""
    text = json.dumps(_rounded(anchors), indent=1, sort_keys=True)
    # A list of numbers on one line: [x, y, z] reads as a point, not as five lines.
    return re.sub(r"\[\s*(-?[\d.e-]+(?:,\s*-?[\d.e-]+)*)\s*\]",
                  lambda m: "[" + ", ".join(v.strip() for v in m.group(1).split(",")) + "]", text) + "\n"


def _rounded(value):
    if isinstance(value, float):
        return round(value, 4) + 0.0
    if isinstance(value, dict):
        return {k: _rounded(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_rounded(v) for v in value]
    return value


def _pose(arrays, body: int, frame: int) -> np.ndarray:
    row = np.asarray(arrays["poses"][frame][body - 1], dtype=float)   # columns: bodies 1..n
    return pose_matrix((tuple(row[:3]), tuple(row[3:])))


def _tcp(kinematics: Kinematics, arrays, frame: int) -> np.ndarray:
    return pose_matrix(kinematics.fk(np.asarray(arrays["joints"][frame], dtype=float)))


def _pusher(step) -> Optional[int]:
    """A push's pusher: the held tool (move-cont ?x ?y ?s), or None for the bare hand
    (transit-cont ?y ?s)."""
    return step.objects[0] if len(step.objects) >= 3 else None


def _pusher_pose(kinematics: Kinematics, arrays, pusher: Optional[int], frame: int) -> np.ndarray:
    """The pusher's pose at `frame`: the tool's, or the gripper frame's for the bare hand."""
    return _tcp(kinematics, arrays, frame) if pusher is None else _pose(arrays, pusher, frame)


def _box(world: World, name: str) -> List[List[float]]:
    lo, hi = body_mesh(world, name).bounds
    return [list(map(float, lo)), list(map(float, hi))]


def _relative(frame: np.ndarray, matrix: np.ndarray) -> List[List[float]]:
    position, orientation = matrix_pose(np.linalg.inv(frame) @ matrix)
    return [list(position), list(orientation)]


def _grasp(world, kinematics, arrays, names, obj: int, frame: int, roles) -> Optional[Dict[str, object]]:
    in_object = np.linalg.inv(_pose(arrays, obj, frame)) @ _tcp(kinematics, arrays, frame)
    position, orientation = matrix_pose(in_object)
    return {"kind": "grasp", "object": roles.get(obj, names[obj]), "in_object": [list(position), list(orientation)],
            "box": _box(world, names[obj])}


def _contact(world, kinematics, recording, names, pusher: Optional[int], target: int, span: Tuple[int, int],
             roles) -> Optional[Dict[str, object]]:
    """The pusher at the first frame it touches the target, and where and which way it pushed."""
    arrays = recording.arrays
    touch = _first_touch(recording, 0 if pusher is None else pusher, target, span)
    if touch is None:
        return None
    frame, point, normal = touch
    pusher_pose = _pusher_pose(kinematics, arrays, pusher, frame)
    target_pose = _pose(arrays, target, frame)
    moved = _pose(arrays, target, span[1])[:3, 3] - target_pose[:3, 3]
    moved[2] = 0.0
    direction = moved if np.linalg.norm(moved) > STILL else -np.array([normal[0], normal[1], 0.0])
    direction = direction / max(np.linalg.norm(direction), 1e-9)
    reach = reach_frame(world.shoulder, target_pose[:3, 3])

    def in_frame(f: np.ndarray) -> Dict[str, object]:
        inverse = np.linalg.inv(f)
        return {"pusher": _relative(f, pusher_pose), "point": list(inverse[:3, :3] @ point + inverse[:3, 3]),
                "direction": list(inverse[:3, :3] @ direction), "normal": list(inverse[:3, :3] @ normal)}
    return {"kind": "contact", "pusher": None if pusher is None else roles.get(pusher, names[pusher]),
            "target": roles.get(target, names[target]), "in_target": in_frame(target_pose),
            "in_reach": in_frame(reach), "box": _box(world, names[target])}


def _first_touch(recording, pusher: int, target: int, span: Tuple[int, int]
                 ) -> Optional[Tuple[int, np.ndarray, np.ndarray]]:
    """(frame, point on the target, its outward normal) where `pusher` (0: the robot) first
    touches `target` in the frames `span`, averaged over that frame's contact points."""
    for frame in range(span[0], span[1] + 1):
        rows = recording.contacts(frame)
        points, normals = [], []
        for (a, b), pa, pb, n in zip(rows["bodies"].tolist(), rows["position_a"], rows["position_b"], rows["normal"]):
            if {a, b} == {pusher, target}:
                # The normal on B points from B towards A: out of the target when it is B.
                points.append(pb if b == target else pa)
                normals.append(np.asarray(n, dtype=float) * (1.0 if b == target else -1.0))
        if points:
            normal = np.mean(normals, axis=0)
            return frame, np.mean(np.asarray(points, dtype=float), axis=0), normal / max(np.linalg.norm(normal), 1e-9)
    return None


def _push(world, kinematics, extraction: Extraction, step, span: Tuple[int, int]) -> Optional[Dict[str, object]]:
    """How far the pusher went along the push (first contact to the segment's end); where the
    target left its support, how far past the support's edge (the target may lie farther from
    the edge in another scene)."""
    arrays = extraction.segmentation.recording.arrays
    pusher, (target, support) = _pusher(step), step.objects[-2:]
    start, end = (_pusher_pose(kinematics, arrays, pusher, frame)[:3, 3] for frame in span)
    travel = end - start
    travel[2] = 0.0
    distance = float(np.linalg.norm(travel))
    if not (math.isfinite(distance) and distance > 0.0):
        return None
    anchor: Dict[str, object] = {"kind": "push", "distance": distance}
    seg = extraction.segmentation
    later = min(seg.recording.frames - 1, span[1] + int(round(float(seg.recording.header.get("rate_hz", 60.0)))))
    if support not in seg.supports_of(target, later):   # it came off its support: the edge is what mattered
        names = extraction.names
        edge = edge_distance(_pose(arrays, target, span[0])[:3, 3], travel / distance, _pose(arrays, support, span[0]),
                             body_mesh(world, names[support]).bounds)
        if edge is not None:
            anchor["past_edge"] = distance - edge
    return anchor
