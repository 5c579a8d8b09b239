"""What a checkpoint's classifiers are, without torch: each parameter's inputs (ParamSpec),
the shape encoder's layout (EncoderConfig) and the sizes shared by both forward passes.

Training builds torch modules from these (model.py, pointnet.py); planning runs the same
network in numpy (forward.py) and never imports torch.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Dict, Tuple

from .encoding import VALUE_LAYOUT

HIDDEN = 64            # width of every MLP and of the head's input parts
SHAPE_PROJECTION = 32  # a shape's embedding as an object encoder reads it
POSE = 7               # translation + quaternion (x, y, z, w)
SIZE = 3               # half-extents

# Columns of a value that are world positions, per kind (start, stop): expressed in each
# object's frame as extra features. A grasp is already in its object's frame.
ANCHORS: Dict[str, Tuple[Tuple[int, int], ...]] = {
    "grasp": (), "placement": ((0, 3),), "contact": ((0, 3), (7, 10)), "trajectory": ((7, 10),), "push": (),
}
# Columns that are world directions (a contact's normal and push direction), turned into each
# object's frame as extra features by classifiers whose spec says `axes`: where a push goes
# relative to the tunnel around the block, not relative to the room. Checkpoints older than
# this have no `axes` and read only the anchors.
AXES: Dict[str, Tuple[Tuple[int, int], ...]] = {"contact": ((10, 13), (13, 16))}
# With `scaled`, a classifier also reads the value's positions divided by each object's
# half-extents: the anchors (in that object's frame) and a grasp's position (in its object's
# frame already): where a placement lands on the plate as a fraction of the plate's radius,
# where a grasp holds a tool as a fraction of its length. A test instance's novel variant is
# often the seen one resized (a 24 cm plate where self-play had 20 and 22 cm), and in
# object-relative units it is the same instance again.
OWN_FRAME_POSITIONS: Dict[str, Tuple[Tuple[int, int], ...]] = {"grasp": ((0, 3),)}
MIN_HALF_EXTENT = 0.005  # metres: a flat object's thin axis must not blow a position up


def framed_columns(spec: "ParamSpec") -> Tuple[Tuple[int, int, bool], ...]:
    """The value's columns seen in each context object's frame, (start, stop, is_point): the
    anchors (points: moved by the object's position, then turned) and, with `axes`, the
    directions (turned only)."""
    points = tuple((start, stop, True) for start, stop in ANCHORS[spec.kind])
    return points + (tuple((start, stop, False) for start, stop in AXES.get(spec.kind, ())) if spec.axes else ())


def scaled_columns(spec: "ParamSpec") -> Tuple[Tuple[int, int, bool], ...]:
    """The value's positions divided by each context object's half-extents, when the spec says
    `scaled`: (start, stop, framed), framed for an anchor (read in the object's frame first,
    as `framed_columns` has it), not for a position already in its object's frame."""
    if not spec.scaled:
        return ()
    return (tuple((start, stop, True) for start, stop in ANCHORS[spec.kind])
            + tuple((start, stop, False) for start, stop in OWN_FRAME_POSITIONS.get(spec.kind, ())))


def object_features(spec: "ParamSpec") -> int:
    """Per context object: pose, size, the value's `framed_columns` in that object's frame, and
    its `scaled_columns` in that object's half-extents."""
    return POSE + SIZE + 3 * len(framed_columns(spec)) + 3 * len(scaled_columns(spec))


def width(kind: str) -> int:
    return len(VALUE_LAYOUT[kind])


@dataclass(frozen=True)
class ParamSpec:
    """One classifier's inputs: the parameter, its kind, its parents (variable, kind) in the
    mechanism's order, and how many mechanism objects form the context."""

    variable: str
    kind: str
    parents: Tuple[Tuple[str, str], ...]
    objects: int
    outputs: int = 2    # 2: (used | verified, verifies), trained on proposals; 1: used, trained on values
    axes: bool = False  # the value's directions in each object's frame too (AXES)
    scaled: bool = False  # the value's positions in each object's half-extents too (scaled_columns)

    def to_json(self) -> dict:
        return {"variable": self.variable, "kind": self.kind, "parents": [list(p) for p in self.parents],
                "objects": self.objects, "outputs": self.outputs, "axes": self.axes,
                "scaled": self.scaled}

    @classmethod
    def from_json(cls, data: dict) -> "ParamSpec":
        return cls(data["variable"], data["kind"], tuple(tuple(p) for p in data["parents"]), int(data["objects"]),
                   int(data.get("outputs", 1)), bool(data.get("axes", False)), bool(data.get("scaled", False)))


@dataclass(frozen=True)
class EncoderConfig:
    """The PointNet++ encoder's shape; stored in a checkpoint's metadata."""

    centres: Tuple[int, int] = (64, 16)
    radii: Tuple[float, float] = (0.25, 0.5)
    neighbours: int = 16
    widths1: Tuple[int, ...] = (32, 32, 64)
    widths2: Tuple[int, ...] = (64, 64, 128)
    out: int = 128

    def to_json(self) -> dict:
        return asdict(self)

    @classmethod
    def from_json(cls, data: dict) -> "EncoderConfig":
        return cls(**{k: tuple(v) if isinstance(v, list) else v for k, v in data.items()})
