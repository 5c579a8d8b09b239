"""The demonstration API: what a demonstration may tell the robot's hand to do.

Demonstration files (`demo_file.py`) are executed by calling these methods, and a Python
demonstration (`def demonstrate(hand):`) calls them itself. Every motion is simulated step by
step (`motion.Driver`): free motions are planned around obstacles, straight moves and pushes
follow a line with physics on. Places are points of objects' bounding boxes (`anchors.py`),
read when the command runs, so a demonstration works on perturbed poses and other assets.

A command that cannot be done raises `DemoError` saying why; nothing is teleported.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import pybullet as p

from .anchors import WORLD_WORDS, AnchorError, ObjectBox, anchor_local, face_normal, object_box, offset_vector
from .motion import DemoError, Driver, frame_quat

if TYPE_CHECKING:
    from ...world.world import World

Vector = Sequence[float]
Offset = Union[None, Sequence[float], Mapping[str, float]]
PHYSICS_HZ = 240.0
WAYPOINT = 0.01          # metres between a straight motion's waypoints (world.motion.cartesian_path)
MOVED = 0.005            # metres (or about 3 degrees) an object must move for `until moves`
TOUCH = 0.002            # metres: closer than this is touching


class Hand:
    """The robot's hand in a demonstration's world.

    `boxes`: each object's bounding box in its own frame (lo, hi), from its asset."""

    def __init__(self, world: "World", boxes: Mapping[str, Tuple[Vector, Vector]], seed: int = 0):
        self.world = world
        self.boxes = dict(boxes)
        self.driver = Driver(world, seed)

    # ------------------------------------------------------------------ places
    def box(self, name: str) -> ObjectBox:
        """`name`'s bounding box where the object is now."""
        if name not in self.world.bodies:
            raise DemoError(f"'{name}' is not an object of the scene")
        lo, hi = self.boxes[name]
        return object_box(self.world.pose(name), lo, hi)

    def point(self, name: Optional[str] = None, at: str = "center", offset: Offset = None,
              xyz: Optional[Vector] = None) -> np.ndarray:
        """A world point: `xyz` (world), or the point `at` of `name`'s box (`center`, faces,
        edges, corners: "far top"), moved by `offset` (`[dx, dy, dz]` world, or
        `{"far": 0.005, "up": 0.02}` along faces' outward normals)."""
        try:
            if name is None:
                base = np.zeros(3) if xyz is None else np.asarray(xyz, dtype=float)
                return base + offset_vector(offset, None)
            box = self.box(name)
            return box.to_world(anchor_local(at, box)) + offset_vector(offset, box)
        except AnchorError as exc:
            raise DemoError(str(exc)) from None

    def direction(self, spec: Union[str, Vector, Mapping]) -> np.ndarray:
        """A unit world direction: `up`/`down`, `[x, y, z]`, `{"object": NAME, "face": WORD}`
        (its outward normal) or `{"from": POINT, "to": POINT}`; `"horizontal": true` drops z."""
        if isinstance(spec, str):
            if spec not in WORLD_WORDS:
                raise DemoError(f"unknown direction '{spec}' (up, down, [x, y, z], an object's face, from/to)")
            vector = np.asarray(WORLD_WORDS[spec])
        elif isinstance(spec, Mapping):
            if "face" in spec:
                try:
                    vector = face_normal(spec["face"], self.box(spec["object"]))
                except AnchorError as exc:
                    raise DemoError(str(exc)) from None
            else:
                vector = self.place(spec["to"]) - self.place(spec["from"])
            if spec.get("horizontal"):
                vector = np.array([vector[0], vector[1], 0.0])
        else:
            vector = np.asarray(spec, dtype=float)
        norm = float(np.linalg.norm(vector))
        if norm < 1e-9:
            raise DemoError("the direction has no length")
        return vector / norm

    def place(self, spec: Union[Vector, Mapping]) -> np.ndarray:
        """A point from its file form: `[x, y, z]` or `{"object", "at", "offset"}`."""
        if isinstance(spec, Mapping):
            return self.point(spec.get("object"), spec.get("at", "center"), spec.get("offset"))
        return self.point(xyz=spec)

    # ------------------------------------------------------------------ gripper
    def open(self) -> None:
        """Open the fingers fully."""
        self.driver.open()
        self.check_fingers_free("after the fingers opened")

    def close(self) -> None:
        """Close the empty fingers (to push with the fingertips)."""
        self.driver.close()

    def grasp(self, name: str, fingers: int = 2) -> None:
        """Close the fingers on `name`, which then moves with the hand; at least `fingers`
        fingers must touch it."""
        self.box(name)
        if self.world.attachment is not None:
            raise DemoError(f"the hand already holds '{self.world.attachment.name}'")
        try:
            self.driver.grasp(name, fingers)
        except DemoError as exc:
            raise DemoError(f"the fingers do not hold '{name}': {exc}") from None

    def release(self) -> None:
        """Let go of what the hand holds and open the fingers; they must come free of
        everything (fingers wedged against a bowl's walls would carry it off on the next lift)."""
        if self.world.attachment is None:
            raise DemoError("the hand holds nothing to release")
        self.driver.release()
        self.check_fingers_free("after the fingers opened")

    def check_fingers_free(self, when: str) -> None:
        """DemoError if both fingers press on one object while the hand holds nothing."""
        from ...operators.execution import fingers_touching
        if self.world.attachment is not None:
            return
        for name in self.world.movable():
            if fingers_touching(self.world, name) == 2:
                raise DemoError(f"{when}, both fingers still press on '{name}': the hand would carry it off; "
                                "let go where the fingers have room to open")

    # ------------------------------------------------------------------ motions
    def move_to(self, point: Vector, approach: Vector = (0.0, 0.0, -1.0), closing: Optional[Vector] = None,
                back: float = 0.08, ignore: Sequence[str] = (), near: Optional[str] = None) -> None:
        """Bring the gripper's fingertip centre to `point`, its fingers pointing along
        `approach` and closing along `closing` (either way): a collision-free planned motion
        to `back` metres short of it, then a straight move along `approach`. Objects in
        `ignore` may be touched. Without `closing`, the fingers close across the narrowest
        side of `near` (or along world y)."""
        approach = np.asarray(approach, dtype=float) / np.linalg.norm(approach)
        closing = self._closing(approach, closing, near)
        orientations = [frame_quat(approach, closing), frame_quat(approach, -closing)]
        self.driver.approach(np.asarray(point, dtype=float), orientations, back=max(back, 0.0), ignore=tuple(ignore))

    def _closing(self, approach: np.ndarray, closing: Optional[Vector], near: Optional[str]) -> np.ndarray:
        if closing is not None:
            vector = np.asarray(closing, dtype=float)
            vector = vector - approach * float(np.dot(vector, approach))
            if np.linalg.norm(vector) < 1e-6:
                raise DemoError("the closing direction is along the approach direction")
            return vector / np.linalg.norm(vector)
        candidates = []
        if near is not None:
            box = self.box(near)
            for axis in range(3):
                vector = box.rotation[:, axis] - approach * float(np.dot(box.rotation[:, axis], approach))
                if np.linalg.norm(vector) > 0.7:
                    candidates.append((float(box.hi[axis] - box.lo[axis]), axis, vector / np.linalg.norm(vector)))
        if candidates:
            return min(candidates, key=lambda c: (c[0], c[1]))[2]
        vector = np.array([0.0, 1.0, 0.0]) - approach * approach[1]
        if np.linalg.norm(vector) < 1e-6:
            vector = np.array([1.0, 0.0, 0.0]) - approach * approach[0]
        return vector / np.linalg.norm(vector)

    def line(self, direction: Vector, distance: Optional[float] = None, until_moves: Optional[str] = None,
             until_touches: Optional[str] = None, speed: float = 0.15) -> float:
        """Move the gripper straight along `direction` at `speed` m/s, orientation kept: for
        `distance` metres, or until `until_moves` moves / `until_touches` is touched by the
        hand or what it holds (then `distance` is the most it may go, default 0.5 m).
        Returns the distance gone."""
        watch = until_moves or until_touches
        if watch is not None:
            self.box(watch)
        limit = distance if distance is not None else 0.5
        steps = max(1, int(round(WAYPOINT / max(speed, 1e-3) * PHYSICS_HZ)))
        start = np.asarray(self.world.tcp_pose()[0])
        stop = None
        if until_moves is not None:
            stop = self._moved(until_moves)
        elif until_touches is not None:
            stop = lambda: self.touching(until_touches)   # noqa: E731
        if stop is not None and stop():
            what = f"'{watch}' is already touched" if until_touches else f"'{watch}' is already moving"
            raise DemoError(f"{what} before the motion starts")
        stopped = self.driver.line(direction, limit, steps=steps, stop=stop)
        gone = float(np.linalg.norm(np.asarray(self.world.tcp_pose()[0]) - start))
        if watch is not None and not stopped:
            if until_moves:
                raise DemoError(f"'{watch}' did not move while the gripper went {gone:.2f} m (at most {limit:.2f})")
            raise DemoError(f"neither the hand nor what it holds touched '{watch}' while the gripper went {gone:.2f} m "
                            f"(at most {limit:.2f}); to stop when an object pushed along reaches it, use "
                            f"{{\"moves\": \"{watch}\"}}")
        return gone

    def distance_to(self, point: Vector, direction: Vector) -> float:
        """How far the gripper must go along `direction` to come level with `point` (the
        plane through it, across the direction)."""
        ahead = float(np.dot(np.asarray(point, dtype=float) - np.asarray(self.world.tcp_pose()[0]),
                             np.asarray(direction, dtype=float) / np.linalg.norm(direction)))
        if ahead <= 0:
            raise DemoError(f"the gripper is already {-ahead:.3f} m past that point along the direction")
        return ahead

    def _moved(self, name: str):
        body = self.world.bodies[name].id
        pos0, orn0 = p.getBasePositionAndOrientation(body, physicsClientId=self.world.client)

        def moved() -> bool:
            pos, orn = p.getBasePositionAndOrientation(body, physicsClientId=self.world.client)
            turned = 2 * np.arccos(min(1.0, abs(float(np.dot(orn, orn0)))))
            return float(np.linalg.norm(np.subtract(pos, pos0))) > MOVED or turned > 0.05
        return moved

    def touching(self, name: str) -> bool:
        """Whether the hand, or what it holds, touches `name` (the last physics step's contacts)."""
        world = self.world
        target = world.bodies[name].id
        movers = [world.robot] + ([world.bodies[world.attachment.name].id] if world.attachment else [])
        return any(c[8] < TOUCH for mover in movers if mover != target
                   for c in p.getContactPoints(mover, target, physicsClientId=world.client))

    def lift(self, distance: float) -> None:
        """Raise the gripper `distance` metres (straight up, or by a planned motion there)."""
        self.driver.up(distance)

    def lower(self, distance: float, speed: float = 0.15) -> None:
        """Lower the gripper straight down `distance` metres."""
        self.line((0.0, 0.0, -1.0), distance, speed=speed)

    def wait(self, seconds: Optional[float] = None) -> None:
        """Let the physics run `seconds`, or until every object is at rest."""
        if seconds is None:
            self.driver.settle()
        else:
            self.driver.settle(int(round(seconds * PHYSICS_HZ)))

    def put(self, held_point: str, at: Vector, offset: Offset = None, back: float = 0.05,
            approach: Vector = (0.0, 0.0, -1.0), ignore: Sequence[str] = (), turn: float = 0.0) -> None:
        """Carry what the hand holds so that its point `held_point` (`bottom`, `-x top`, ...)
        comes to `at` (a world point), coming in along `approach` for the last `back` metres
        (from above by default): turned as it is now, then by `turn` degrees about the
        vertical. `offset` moves the target along the held object's faces (as they face
        after the turn), or by a world vector."""
        if self.world.attachment is None:
            raise DemoError("the hand holds nothing to put")
        held = self.world.attachment.name
        tcp, orn = self.world.tcp_pose()
        spin = p.getQuaternionFromEuler((0.0, 0.0, np.radians(turn)))
        now = self.box(held)
        # The held object turned about the vertical through the gripper frame: the grip is kept.
        turned_orn = p.multiplyTransforms((0, 0, 0), spin, (0, 0, 0), self.world.pose(held)[1])[1]
        turned_pos = np.asarray(tcp) + np.asarray(p.multiplyTransforms((0, 0, 0), spin,
                                                                       tuple(now.position - np.asarray(tcp)),
                                                                       (0, 0, 0, 1))[0])
        box = object_box((turned_pos, turned_orn), now.lo, now.hi)
        try:
            point_now = box.to_world(anchor_local(held_point, box))
            shift = offset_vector(offset, box)
        except AnchorError as exc:
            raise DemoError(str(exc)) from None
        target = np.asarray(at, dtype=float) + shift
        approach = np.asarray(approach, dtype=float) / np.linalg.norm(approach)
        goal = np.asarray(tcp) + (target - point_now)
        goal_orn = p.multiplyTransforms((0, 0, 0), spin, (0, 0, 0), orn)[1]
        self.driver.approach_poses([(tuple(goal), tuple(goal_orn))], back=max(back, 0.0), ignore=tuple(ignore),
                                   direction=approach)

    @property
    def holding(self) -> Optional[str]:
        """The object the hand holds, if any."""
        return self.world.attachment.name if self.world.attachment else None


def scene_boxes(objects) -> Dict[str, Tuple[np.ndarray, np.ndarray]]:
    """Each scene object's bounding box in its own frame, scaled, from its asset."""
    from ...world.asset_index import asset_info

    boxes = {}
    for obj in objects:
        info = asset_info(obj.asset)["aabb"]
        scale = np.asarray(obj.scale, dtype=float)
        boxes[obj.name] = (np.asarray(info["min"]) * scale, np.asarray(info["max"]) * scale)
    return boxes
