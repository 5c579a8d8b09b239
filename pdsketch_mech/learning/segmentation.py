"""Segmenting a recording by contact modes, with hysteresis.

Each frame's raw graph (`contact_modes.py`) is turned into boolean signals — per object:
squeezed, touched by the robot; per pair: support, touching — and every signal is
*debounced*: a run shorter than MIN_DURATION_S is flipped to its neighbours' value. The robot's
mode per frame is then

    (held object or none, objects pushed: by the held object, or by the hand if it is empty)

and a segment is a maximal run of one mode. Two more filters keep the segments physical:
- a push must move what it pushes (PUSH_MIN_MOVE or PUSH_MIN_TURN over the run): a finger
  brushing an object on its way to a grasp, or the held tool grazing something, is contact
  without a push and does not make a segment; a held object that moves must carry what it
  touches along its own way (`_carried`), or what moved was moved by physics;
- a held object resting on something (the normal says "support") is being put down, not
  pushing: that contact belongs to the place that follows.
Segments still shorter than MIN_DURATION_S after this are merged into the previous one.

Why these numbers (measured on the six committed recordings, 60 Hz):
- MIN_DURATION_S 0.15 s (9 frames): contact flicker lasts 1-6 frames — a finger grazing the
  weight as the gripper opens after a release (5 frames), a fingertip touching the plate
  during an approach (2), a single finger arriving 3 frames before the other one at a grasp,
  resting contacts with zero force while the scene settles. Every real phase of a demo lasts
  longer than 0.5 s.
- PUSH_MIN_MOVE 5 mm / PUSH_MIN_TURN 3 degrees: what a touch must move the touched object by
  to be a push; the scripted pushes move objects by 8-40 cm.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Dict, FrozenSet, Hashable, List, Optional, Sequence, Tuple

import numpy as np

from ..world.recording import Recording
from .contact_modes import Bodies, FrameGraph, bodies_of, frame_graphs

MIN_DURATION_S = 0.15
PUSH_MIN_MOVE = 0.005
PUSH_MIN_TURN = math.radians(3.0)


@dataclass(frozen=True)
class Mode:
    """The robot's contact mode: what the hand holds and what the hand (or the held object) pushes."""

    held: Optional[int]
    pushed: FrozenSet[int] = frozenset()

    def describe(self, names: Sequence[str]) -> str:
        pushed = ", ".join(names[i] for i in sorted(self.pushed))
        if self.held is None:
            return f"hand pushes {pushed}" if pushed else "free"
        held = names[self.held]
        return f"holds {held}, {held} pushes {pushed}" if pushed else f"holds {held}"


@dataclass(frozen=True)
class Segment:
    start: int      # first frame
    end: int        # last frame (inclusive)
    mode: Mode


@dataclass
class Segmentation:
    """A recording cut into contact-mode segments, with the debounced graph of every frame."""

    recording: Recording
    bodies: Bodies
    graphs: List[FrameGraph]      # debounced
    segments: List[Segment]

    def time(self, frame: int) -> float:
        return float(self.recording.arrays["time"][frame])

    def supports_of(self, obj: int, frame: int) -> List[int]:
        return sorted(y for x, y in self.graphs[frame].support if x == obj)


def min_frames(recording: Recording) -> int:
    rate = float(recording.header.get("rate_hz", 60.0))
    return max(1, int(round(MIN_DURATION_S * rate)))


def debounce(signal: np.ndarray, shortest: int) -> np.ndarray:
    """`signal` (booleans) with every run shorter than `shortest` frames flipped, shortest
    runs first, so a flicker inside a long run disappears and two long runs keep their edge."""
    out = np.asarray(signal, dtype=bool).copy()
    while True:
        runs = _runs(out)
        if len(runs) <= 1:
            return out
        short = [(end - start + 1, start, end) for start, end, _ in runs if end - start + 1 < shortest]
        if not short:
            return out
        _, start, end = min(short)
        out[start:end + 1] = ~out[start:end + 1]


def _runs(values: Sequence[Hashable]) -> List[Tuple[int, int, Hashable]]:
    """(first, last, value) of each maximal run of equal values."""
    runs, start = [], 0
    for i in range(1, len(values) + 1):
        if i == len(values) or values[i] != values[start]:
            runs.append((start, i - 1, values[start]))
            start = i
    return runs


def debounced_graphs(raw: List[FrameGraph], shortest: int) -> List[FrameGraph]:
    """Every relation of the raw graphs debounced on its own."""
    n = len(raw)
    keys: Dict[Tuple[str, Hashable], np.ndarray] = {}

    def signal(kind: str, key: Hashable) -> np.ndarray:
        if (kind, key) not in keys:
            keys[(kind, key)] = np.zeros(n, dtype=bool)
        return keys[(kind, key)]

    for f, g in enumerate(raw):
        for o in g.robot_touch:
            signal("touch", o)[f] = True
        for o in g.squeezed:
            signal("squeeze", o)[f] = True
        for pair in g.support:
            signal("support", pair)[f] = True
        for pair in g.touching:
            signal("touching", pair)[f] = True
    smooth = {k: debounce(v, shortest) for k, v in keys.items()}
    out = []
    for f in range(n):
        on: Dict[str, set] = {"touch": set(), "squeeze": set(), "support": set(), "touching": set()}
        for (kind, key), values in smooth.items():
            if values[f]:
                on[kind].add(key)
        out.append(FrameGraph(frozenset(on["touch"]), frozenset(on["squeeze"]), frozenset(on["support"]),
                              frozenset(on["touching"])))
    return out


def frame_mode(graph: FrameGraph) -> Mode:
    """The robot's mode in one (debounced) frame."""
    if graph.squeezed:
        held = min(graph.squeezed)   # two squeezed objects cannot happen with one gripper; be deterministic
        pushed = {b if a == held else a for a, b in graph.touching if held in (a, b)}
        # What the held object rests on is where it is being put down, not something it pushes.
        pushed -= {y for x, y in graph.support if x == held}
        return Mode(held, frozenset(pushed))
    return Mode(None, frozenset(graph.robot_touch))


def _moved(poses: np.ndarray, obj_column: int, start: int, end: int) -> bool:
    """Whether the object moved by PUSH_MIN_MOVE or turned by PUSH_MIN_TURN during [start, end]."""
    track = poses[start:end + 1, obj_column]
    shift = np.linalg.norm(track[:, :3] - track[0, :3], axis=1).max()
    q0 = track[0, 3:]
    turn = (2 * np.arccos(np.clip(np.abs(track[:, 3:] @ q0), 0.0, 1.0))).max()
    return bool(shift >= PUSH_MIN_MOVE or turn >= PUSH_MIN_TURN)


def _carried(poses: np.ndarray, obj_column: int, held_column: int, start: int, end: int) -> bool:
    """Whether a held object moving by PUSH_MIN_MOVE carried the object it touches along: the
    object moved at least PUSH_MIN_MOVE the way the held one did, or turned PUSH_MIN_TURN while
    moving that way. A chock lifted away from a block leaning on it, which then slides the
    other way down a slope, pushes nothing (the block's fall is physics, said by a `:then`)."""
    held = poses[end, held_column, :3] - poses[start, held_column, :3]
    if np.linalg.norm(held) < PUSH_MIN_MOVE:
        return True   # a tool turned or held still: its own motion says nothing
    along = float(np.dot(poses[end, obj_column, :3] - poses[start, obj_column, :3], held / np.linalg.norm(held)))
    track = poses[start:end + 1, obj_column, 3:]
    turn = float((2 * np.arccos(np.clip(np.abs(track @ track[0]), 0.0, 1.0))).max())
    return along >= PUSH_MIN_MOVE or (along > 0 and turn >= PUSH_MIN_TURN)


def segment(recording: Recording) -> Segmentation:
    """Debounce the recording's contact graphs and cut it where the robot's mode changes."""
    if recording.frames < 2:
        raise ValueError("the recording has fewer than two frames")
    bodies = bodies_of(recording)
    shortest = min_frames(recording)
    graphs = debounced_graphs(frame_graphs(recording, bodies), shortest)
    modes = [frame_mode(g) for g in graphs]
    poses = np.asarray(recording.arrays["poses"], dtype=float)
    # Pushes that move nothing are brushes: drop the touched object from those runs.
    for start, end, mode in _runs(modes):
        if mode.pushed:
            # poses columns follow the header's `objects`, which are bodies 1..n in order
            kept = frozenset(o for o in mode.pushed if _moved(poses, o - 1, start, end)
                             and (mode.held is None or _carried(poses, o - 1, mode.held - 1, start, end)))
            if kept != mode.pushed:
                for f in range(start, end + 1):
                    modes[f] = Mode(mode.held, kept)
    runs = _runs(modes)
    # A run still too short is the seam between two modes (e.g. one finger arrives before
    # the other): it joins the run before it (the first run joins the one after it).
    merged: List[List] = []
    for start, end, mode in runs:
        if merged and (end - start + 1 < shortest or merged[-1][2] == mode):
            merged[-1][1] = end
        else:
            merged.append([start, end, mode])
    if len(merged) > 1 and merged[0][1] - merged[0][0] + 1 < shortest:
        merged[1][0] = merged[0][0]
        merged.pop(0)
    segments = [Segment(s, e, m) for s, e, m in merged]
    return Segmentation(recording, bodies, graphs, segments)
