"""Points and directions written relative to objects, read off the world as it is now.

A demonstration names places the way a person would: "the top of `box`", "5 mm beyond the far
face of `target`", "the handle's -x end, 5 cm in". Each object's bounding box (its asset's, in
its own frame, scaled) has six faces; a face is named by its own axis (`+x`, `-z`, ...) or by
where it looks now: `top`/`bottom` (world up/down), `far`/`near` (the robot's forward and
backward), `left`/`right` (the robot's left and right). So the same words pick the right faces
of a perturbed, turned or swapped object.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Iterable, Optional, Sequence, Tuple

import numpy as np
import pybullet as p

AXIS_WORDS = {"+x": (0, 1), "-x": (0, -1), "+y": (1, 1), "-y": (1, -1), "+z": (2, 1), "-z": (2, -1)}
SEEN_WORDS = ("top", "bottom", "far", "near", "left", "right")
FACE_WORDS = tuple(AXIS_WORDS) + SEEN_WORDS
WORLD_WORDS = {"up": (0.0, 0.0, 1.0), "down": (0.0, 0.0, -1.0)}
# The robot's base stands at the origin facing +x (world/robot.py); its frame is the world's.
ROBOT_DIRECTIONS = {"top": (0, 0, 1), "bottom": (0, 0, -1), "far": (1, 0, 0), "near": (-1, 0, 0),
                    "left": (0, 1, 0), "right": (0, -1, 0)}


class AnchorError(ValueError):
    """A point or direction that cannot be resolved (an unknown word, two words for one axis)."""


@dataclass(frozen=True)
class ObjectBox:
    """An object's bounding box in its own frame, and its pose now."""
    lo: np.ndarray
    hi: np.ndarray
    position: np.ndarray
    rotation: np.ndarray        # world <- object

    @property
    def centre_local(self) -> np.ndarray:
        return (self.lo + self.hi) / 2

    @property
    def centre(self) -> np.ndarray:
        return self.position + self.rotation @ self.centre_local

    def to_world(self, local: Sequence[float]) -> np.ndarray:
        return self.position + self.rotation @ np.asarray(local, dtype=float)


def object_box(pose: Tuple[Sequence[float], Sequence[float]], lo: Sequence[float], hi: Sequence[float]) -> ObjectBox:
    rotation = np.array(p.getMatrixFromQuaternion(pose[1])).reshape(3, 3)
    return ObjectBox(np.asarray(lo, dtype=float), np.asarray(hi, dtype=float), np.asarray(pose[0], dtype=float),
                     rotation)


def seen_direction(word: str) -> np.ndarray:
    """The world direction a word seen from the robot means (unit): `top`/`bottom` are world
    up/down, `far`/`near` the robot's forward/backward (its base's +x/-x), `left`/`right` its
    +y/-y. The same face whichever way the object lies from the robot."""
    return np.asarray(ROBOT_DIRECTIONS[word], dtype=float)


def face(word: str, box: ObjectBox) -> Tuple[int, int]:
    """(local axis, sign) of the face `word` names: its own axis, or the one whose outward
    normal points most nearly where the word looks now."""
    if word in AXIS_WORDS:
        return AXIS_WORDS[word]
    if word not in SEEN_WORDS:
        raise AnchorError(f"unknown face '{word}' (faces: {', '.join(FACE_WORDS)}, or 'center')")
    towards = box.rotation.T @ seen_direction(word)
    axis = int(np.argmax(np.abs(towards)))
    return axis, 1 if towards[axis] > 0 else -1


def face_normal(word: str, box: ObjectBox) -> np.ndarray:
    """The world outward normal of face `word`."""
    axis, sign = face(word, box)
    return sign * box.rotation[:, axis]


def anchor_local(words: str, box: ObjectBox) -> np.ndarray:
    """The point of the box `words` names, in the object's frame: `center`, one face
    (its centre), two faces (the middle of their shared edge) or three (a corner)."""
    local = box.centre_local.copy()
    half = (box.hi - box.lo) / 2
    taken: Dict[int, str] = {}
    for word in split_words(words):
        if word in ("center", "centre"):
            continue
        axis, sign = face(word, box)
        if axis in taken:
            raise AnchorError(f"'{taken[axis]}' and '{word}' name faces across the same axis of the box")
        taken[axis] = word
        local[axis] += sign * half[axis]
    return local


def offset_vector(offset, box: Optional[ObjectBox]) -> np.ndarray:
    """A displacement: `[dx, dy, dz]` (world, metres) or `{word: metres, ...}`, each word a
    face of the object (along its outward normal) or `up`/`down`."""
    if offset is None:
        return np.zeros(3)
    if isinstance(offset, (list, tuple)):
        return np.asarray(offset, dtype=float)
    total = np.zeros(3)
    for word, metres in offset.items():
        if word in WORLD_WORDS:
            total += float(metres) * np.asarray(WORLD_WORDS[word])
        elif box is None:
            raise AnchorError(f"offset '{word}' names a face, but the point belongs to no object")
        else:
            total += float(metres) * face_normal(word, box)
    return total


def split_words(words: str) -> Iterable[str]:
    return words.replace(",", " ").split()


def check_words(words: str) -> Optional[str]:
    """Why `words` is no anchor (before any world exists), or None."""
    seen: Dict[str, str] = {}
    for word in split_words(words):
        if word in ("center", "centre"):
            continue
        if word not in FACE_WORDS:
            return f"unknown face '{word}' (faces: {', '.join(FACE_WORDS)}, or 'center')"
        group = {"top": "z", "bottom": "z", "far": "fn", "near": "fn", "left": "lr", "right": "lr"}.get(word, word[1])
        if group in seen:
            return f"'{seen[group]}' and '{word}' name faces across the same axis"
        seen[group] = word
    return None
