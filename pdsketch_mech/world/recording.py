"""Demonstration recordings: the simulated world observed at a fixed rate, raw data only.

A recording is two files side by side:
- `NAME.npz`: arrays (joint positions, finger positions and gripper opening, the pose of
  every scene body, every contact point PyBullet reports: bodies, links, positions, normal,
  distance, normal force), one row per frame or per contact;
- `NAME.json`: the header: schema version, the scene's problem text, task/split/seed, rate,
  the bodies (names, PyBullet ids, assets), what each array holds, whether the goal held at
  the end.

Nothing in it names an operator or a phase of the script: segmenting the demonstration into
basis operations is the learner's job (`learn extract`), from these contacts alone.

A `Recorder` registers itself as a world observer (`World.observers`, called after every
physics step) and captures a frame every `steps_per_frame` steps (4 at 240 Hz: 60 Hz).
Files are written atomically (temporary names, then renames) and never overwritten unless
asked to.
"""
from __future__ import annotations

import io
import json
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Dict, List, Tuple

import numpy as np
import pybullet as p

from .robot import ARM_JOINTS, FINGER_JOINTS

if TYPE_CHECKING:
    from .world import World

SCHEMA = "pdsketch_mech.demo/1"
PHYSICS_HZ = 240.0
STEPS_PER_FRAME = 4

ARRAYS = {
    "time": "float64 (frames,): simulated seconds since the recording started",
    "step": "int64 (frames,): physics steps since the recording started",
    "joints": "float64 (frames, 7): Panda arm joint positions (rad), joints 0-6",
    "fingers": "float64 (frames, 2): finger joint positions (m), joints 9 and 10",
    "gripper_opening": "float64 (frames,): distance between the fingers (m), the sum of the two",
    "poses": "float64 (frames, objects, 7): each scene object's link-frame pose, x y z qx qy qz qw "
             "(world frame, metres), objects in the header's `objects` order",
    "contact_offsets": "int64 (frames + 1,): frame i's contacts are rows offsets[i]:offsets[i+1] of the contact_* arrays",
    "contact_bodies": "int16 (contacts, 2): bodies A and B as indices into the header's `bodies`",
    "contact_links": "int16 (contacts, 2): link indices on A and B (-1: the base)",
    "contact_position_a": "float32 (contacts, 3): contact point on A (world frame)",
    "contact_position_b": "float32 (contacts, 3): contact point on B (world frame)",
    "contact_normal": "float32 (contacts, 3): contact normal on B, pointing from B towards A",
    "contact_distance": "float32 (contacts,): signed distance (m); negative is penetration, PyBullet also "
                        "reports points a few millimetres apart",
    "contact_force": "float32 (contacts,): normal force (N) applied in the last physics step",
}


class RecordingExists(FileExistsError):
    pass


class Recorder:
    """Captures `world` every `steps_per_frame` physics steps while attached."""

    def __init__(self, world: "World", steps_per_frame: int = STEPS_PER_FRAME):
        self.world = world
        self.steps_per_frame = steps_per_frame
        self.objects: List[str] = list(world.bodies)
        # Body index 0 is the robot; then the scene objects in scene order.
        self.body_ids: List[int] = [world.robot] + [world.bodies[n].id for n in self.objects]
        self._index = {body: i for i, body in enumerate(self.body_ids)}
        self._steps = 0
        self._frames: Dict[str, List[Any]] = {k: [] for k in ("step", "joints", "fingers", "poses")}
        self._contacts: List[List[tuple]] = []

    # ------------------------------------------------------------------ capturing
    def start(self) -> "Recorder":
        """Capture the world as it is now (frame 0) and every `steps_per_frame` steps from now on."""
        self._capture()
        self.world.observers.append(self._observe)
        return self

    def stop(self) -> None:
        """Stop observing; the last state is captured if it fell between two frames."""
        if self._observe in self.world.observers:
            self.world.observers.remove(self._observe)
        if self._frames["step"] and self._frames["step"][-1] != self._steps:
            self._capture()

    def __enter__(self) -> "Recorder":
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    def _observe(self, world: "World") -> None:
        self._steps += 1
        if self._steps % self.steps_per_frame == 0:
            self._capture()

    def _capture(self) -> None:
        world, client = self.world, self.world.client
        states = p.getJointStates(world.robot, list(ARM_JOINTS) + list(FINGER_JOINTS), physicsClientId=client)
        self._frames["step"].append(self._steps)
        self._frames["joints"].append([s[0] for s in states[:len(ARM_JOINTS)]])
        self._frames["fingers"].append([s[0] for s in states[len(ARM_JOINTS):]])
        self._frames["poses"].append([tuple(pos) + tuple(orn) for pos, orn in (world.pose(n) for n in self.objects)])
        rows = []
        for c in p.getContactPoints(physicsClientId=client):
            a, b = self._index.get(c[1]), self._index.get(c[2])
            if a is None or b is None:
                continue
            rows.append((a, b, c[3], c[4], c[5], c[6], c[7], c[8], c[9]))
        self._contacts.append(rows)

    @property
    def frames(self) -> int:
        return len(self._frames["step"])

    # ------------------------------------------------------------------ output
    def arrays(self) -> Dict[str, np.ndarray]:
        step = np.array(self._frames["step"], dtype=np.int64)
        fingers = np.array(self._frames["fingers"], dtype=np.float64).reshape(-1, len(FINGER_JOINTS))
        rows = [row for frame in self._contacts for row in frame]
        offsets = np.concatenate([[0], np.cumsum([len(frame) for frame in self._contacts])]).astype(np.int64)

        def column(i, dtype, width=None):
            data = np.array([r[i] for r in rows], dtype=dtype)
            return data.reshape(-1, width) if width else data

        return {
            "time": step / PHYSICS_HZ,
            "step": step,
            "joints": np.array(self._frames["joints"], dtype=np.float64).reshape(-1, len(ARM_JOINTS)),
            "fingers": fingers,
            "gripper_opening": fingers.sum(axis=1),
            "poses": np.array(self._frames["poses"], dtype=np.float64).reshape(-1, len(self.objects), 7),
            "contact_offsets": offsets,
            "contact_bodies": np.array([(r[0], r[1]) for r in rows], dtype=np.int16).reshape(-1, 2),
            "contact_links": np.array([(r[2], r[3]) for r in rows], dtype=np.int16).reshape(-1, 2),
            "contact_position_a": column(4, np.float32, 3),
            "contact_position_b": column(5, np.float32, 3),
            "contact_normal": column(6, np.float32, 3),
            "contact_distance": column(7, np.float32),
            "contact_force": column(8, np.float32),
        }

    def header(self, **fields: Any) -> Dict[str, Any]:
        """The JSON header; `fields` (problem text, task, seed, goal result...) are added."""
        world = self.world
        bodies = [{"index": 0, "name": "robot", "pybullet_id": world.robot, "kind": "robot",
                   "links": {str(j): p.getJointInfo(world.robot, j, physicsClientId=world.client)[12].decode()
                             for j in range(p.getNumJoints(world.robot, physicsClientId=world.client))}}]
        for i, name in enumerate(self.objects, 1):
            body = world.bodies[name]
            bodies.append({"index": i, "name": name, "pybullet_id": body.id, "kind": "fixed" if body.fixed else "movable",
                           "urdf": os.path.relpath(body.urdf, _repo_root()) if body.urdf else "", "scale": body.scale})
        header: Dict[str, Any] = {
            "schema": SCHEMA,
            "physics_hz": PHYSICS_HZ,
            "steps_per_frame": self.steps_per_frame,
            "rate_hz": PHYSICS_HZ / self.steps_per_frame,
            "frames": self.frames,
            "contacts": int(sum(len(f) for f in self._contacts)),
            "duration_s": (self._frames["step"][-1] if self.frames else 0) / PHYSICS_HZ,
            "robot": {"body": 0, "arm_joints": list(ARM_JOINTS), "finger_joints": list(FINGER_JOINTS),
                      "base_pose": [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]},
            "bodies": bodies,
            "objects": self.objects,
            "arrays": ARRAYS,
        }
        header.update(fields)
        return header


def _repo_root() -> str:
    return os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def recording_paths(path: str) -> Tuple[str, str]:
    """(`X.npz`, `X.json`) for `X`, `X.npz` or `X.json`."""
    base = path
    for suffix in (".npz", ".json"):
        if path.endswith(suffix):
            base = path[:-len(suffix)]
    return base + ".npz", base + ".json"


def save_recording(path: str, arrays: Dict[str, np.ndarray], header: Dict[str, Any], force: bool = False) -> Tuple[str, str]:
    """Write `path`.npz and `path`.json atomically; refuse to replace an existing recording
    unless `force`. Returns the two paths."""
    npz, js = recording_paths(path)
    if not force:
        for existing in (npz, js):
            if os.path.exists(existing):
                raise RecordingExists(f"{existing} exists (use --force to replace it)")
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    suffix = f".tmp{os.getpid()}"
    with open(npz + suffix, "wb") as handle:
        handle.write(buffer.getvalue())
    with open(js + suffix, "w", encoding="utf-8", newline="\n") as handle:
        json.dump(header, handle, indent=1)
        handle.write("\n")
    os.replace(npz + suffix, npz)
    os.replace(js + suffix, js)
    return npz, js


@dataclass
class Recording:
    header: Dict[str, Any]
    arrays: Dict[str, np.ndarray]

    @property
    def frames(self) -> int:
        return len(self.arrays["step"])

    @property
    def objects(self) -> List[str]:
        return list(self.header["objects"])

    def body_name(self, index: int) -> str:
        return self.header["bodies"][index]["name"]

    def contacts(self, frame: int) -> Dict[str, np.ndarray]:
        """The contact rows of `frame`, as {array name without `contact_`: rows}."""
        lo, hi = self.arrays["contact_offsets"][frame], self.arrays["contact_offsets"][frame + 1]
        return {k[len("contact_"):]: v[lo:hi] for k, v in self.arrays.items()
                if k.startswith("contact_") and k != "contact_offsets"}


def load_recording(path: str) -> Recording:
    """Read a recording (`X`, `X.npz` or `X.json`); ValueError for an unknown schema."""
    npz, js = recording_paths(path)
    with open(js, encoding="utf-8") as handle:
        header = json.load(handle)
    if header.get("schema") != SCHEMA:
        raise ValueError(f"{js}: unknown recording schema {header.get('schema')!r} (expected {SCHEMA})")
    with np.load(npz) as data:
        arrays = {k: data[k] for k in data.files}
    return Recording(header, arrays)
