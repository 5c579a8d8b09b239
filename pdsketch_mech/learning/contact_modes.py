"""Per-frame contact-mode graphs read from a recording's raw data (contacts, poses, gripper).

For every recorded frame this computes, from the contact rows alone:
- which robot parts (left finger, right finger, any other link) touch each object;
- which object, if any, is *squeezed*: both fingers touch it from opposing sides while the
  gripper is not opening — the raw form of `holding`;
- object-object relations: `support(x, y)` when the contact normal on y points up towards x
  (the force y exerts on x has a +z component), otherwise `touching`.

Nothing here reads an object's name or category: bodies are the header's indices, the robot
is body 0, the finger links are the header's finger joints, and `fixed` comes from the
header's body kinds (the scene's static furniture). Debouncing these per-frame signals and
cutting segments is `segmentation.py`'s job.

Thresholds (and why; the first two are the world's own, imported from `world/contacts.py`):
- CONTACT_DISTANCE 2 mm: PyBullet also reports pairs inside its collision margin that do not
  touch; 2 mm is what the world's own contact graph (`world/contacts.py`) uses.
- SUPPORT_COS 0.7: a support normal within ~45 degrees of +z, as in `world/contacts.py`, so
  a 20-degree slope supports what lies on it while a side push (normal ~horizontal) does not.
  A pair's normal is averaged over its closest points, as there (`pair_normal_z`).
- SQUEEZE_COS -0.2: the two fingers' mean contact normals must point away from each other
  (the object is between them). Rim grasps on a flared plate give about -0.46; a closed hand
  pushing a face with both fingertips gives about +0.9.
- OPENING_TOLERANCE 0.5 mm over OPENING_LOOKBACK 2 frames: a gripper that is opening is
  releasing, neither holding nor pushing, even while the fingers still graze the object it
  let go of (after the Lever's release a finger touches the falling weight for 5 frames).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, FrozenSet, List, Tuple

import numpy as np

from ..world.contacts import CONTACT_DISTANCE, SUPPORT_COS, pair_normal_z
from ..world.recording import Recording

SQUEEZE_COS = -0.2
OPENING_TOLERANCE = 5e-4
OPENING_LOOKBACK = 2

Pair = Tuple[int, int]


@dataclass(frozen=True)
class FrameGraph:
    """The raw contact-mode graph of one frame (bodies as header indices, robot = 0)."""

    robot_touch: FrozenSet[int]            # objects any robot link touches
    squeezed: FrozenSet[int]               # objects between the closing fingers
    support: FrozenSet[Pair]               # (x, y): y pushes x up (x may be held: then it rests on y)
    touching: FrozenSet[Pair]              # (x, y) with x < y, touching without support


@dataclass(frozen=True)
class Bodies:
    """What the extractor knows about the recording's bodies, all from the header."""

    names: Tuple[str, ...]                 # for messages and the grounded steps only
    fixed: FrozenSet[int]
    fingers: Tuple[int, int]               # robot link indices of the two fingers

    @property
    def objects(self) -> List[int]:
        return list(range(1, len(self.names)))


def bodies_of(recording: Recording) -> Bodies:
    header = recording.header
    names = tuple(b["name"] for b in header["bodies"])
    fixed = frozenset(b["index"] for b in header["bodies"] if b.get("kind") == "fixed")
    fingers = tuple(int(j) for j in header["robot"]["finger_joints"])
    if len(fingers) != 2:
        raise ValueError(f"expected a two-finger gripper, the recording has finger joints {fingers}")
    return Bodies(names, fixed, (fingers[0], fingers[1]))


def frame_graphs(recording: Recording, bodies: Bodies) -> List[FrameGraph]:
    """The raw graph of every frame."""
    opening = np.asarray(recording.arrays["gripper_opening"], dtype=float)
    out = []
    for frame in range(recording.frames):
        before = opening[max(0, frame - OPENING_LOOKBACK)]
        opening_now = opening[frame] > before + OPENING_TOLERANCE
        out.append(_graph(recording.contacts(frame), bodies, opening_now))
    return out


def _graph(rows: Dict[str, np.ndarray], bodies: Bodies, gripper_opening: bool) -> FrameGraph:
    near = rows["distance"] < CONTACT_DISTANCE
    pairs, links, normals = rows["bodies"][near], rows["links"][near], rows["normal"][near].astype(float)
    distances = rows["distance"][near].astype(float)
    robot_touch = set()
    finger_normals: Dict[int, Dict[int, List[np.ndarray]]] = {}
    object_normals: Dict[Pair, List[Tuple[float, float]]] = {}   # (distance, normal z) per point
    for (a, b), (la, lb), n, d in zip(pairs.tolist(), links.tolist(), normals, distances):
        if a == b:
            continue
        if a == 0 or b == 0:
            obj, link = (b, la) if a == 0 else (a, lb)
            # The normal on B points from B towards A: orient it from the object towards the robot.
            towards_robot = n if a == 0 else -n
            if not gripper_opening:
                robot_touch.add(obj)
            if link in bodies.fingers:
                finger_normals.setdefault(obj, {}).setdefault(link, []).append(towards_robot)
            continue
        if a in bodies.fixed and b in bodies.fixed:
            continue  # furniture on furniture is scenery, never a mode
        # Normal z oriented from the lower index towards the higher one.
        z = float(n[2]) if a > b else -float(n[2])
        object_normals.setdefault((min(a, b), max(a, b)), []).append((float(d), z))
    squeezed = set()
    if not gripper_opening:
        for obj, by_link in finger_normals.items():
            if len(by_link) == 2:
                m1, m2 = (np.mean(v, axis=0) for v in by_link.values())
                cos = float(np.dot(m1, m2) / (np.linalg.norm(m1) * np.linalg.norm(m2) + 1e-12))
                if cos < SQUEEZE_COS:
                    squeezed.add(obj)
    support, touching = set(), set()
    for (lo, hi), points in object_normals.items():
        ds, zs = zip(*points)
        z = pair_normal_z(ds, zs)       # from lo towards hi: > 0 means hi is above lo
        if z > SUPPORT_COS:
            support.add((hi, lo))
        elif z < -SUPPORT_COS:
            support.add((lo, hi))
        else:
            touching.add((lo, hi))
    return FrameGraph(frozenset(robot_touch), frozenset(squeezed), frozenset(support), frozenset(touching))
