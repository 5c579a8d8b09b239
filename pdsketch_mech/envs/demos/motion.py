"""Motions for scripted demonstrations, every one simulated step by step.

Nothing is teleported: free motions are planned (OMPL, `world.motion.plan_motion`) and then
followed by the arm's position controllers with physics on, one `World.step` at a time,
like straight Cartesian moves, pushes and the fingers. So a recorder observing the world
(`World.observers`) sees every step of the demonstration, contacts included.

The grasp is the world's: `World.attach` (a constraint keeping the object where the hand
holds it) and fingers closed on it (`operators/execution.set_fingers_dynamic`).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Callable, Optional, Sequence, Tuple

import numpy as np
import pybullet as p
from scipy.spatial.transform import Rotation

from ...operators.execution import fingers_touching, set_fingers_dynamic
from ...world.collision import CollisionChecker
from ...world.motion import cartesian_path, path_collision, plan_motion
from ...world.robot import CLOSED, MAX_OPENING, REACH, SHOULDER, WRIST

if TYPE_CHECKING:
    from ...world.world import World

STEPS_PER_WAYPOINT = 8      # free motions: 0.05 rad waypoints at ~1.5 rad/s
LINE_STEPS = 8              # straight moves: 1 cm waypoints at 0.3 m/s
PUSH_STEPS = 16             # pushes and pulls: 1 cm in 16 steps, 0.15 m/s
TRACKING = 2e-3             # radians: a motion ends when every joint is this close to its target
MAX_WAIT = 240              # physics steps to wait for the arm to get there
IK_TOLERANCE = dict(pos_tol=1e-3, ang_tol=1e-2)   # tighter than the world's default (5 mm): objects land where meant


class DemoError(RuntimeError):
    """The scripted demonstration cannot go on (no IK, no path, nothing grasped)."""


class Failure:
    """Why no attempt worked: the reason of the attempt that got furthest (a collision says
    more than an unreachable orientation)."""

    def __init__(self):
        self.stage, self.reason = -1, "nothing was tried"

    def note(self, stage: int, reason: str) -> None:
        if stage > self.stage:
            self.stage, self.reason = stage, reason

    def __str__(self) -> str:
        return self.reason


def frame_quat(approach: Sequence[float], closing: Sequence[float]) -> tuple:
    """The gripper frame's orientation (panda_grasptarget: z = approach, y = closing axis)."""
    z = np.asarray(approach, dtype=float)
    z /= np.linalg.norm(z)
    y = np.asarray(closing, dtype=float)
    y = y - z * float(np.dot(y, z))
    y /= np.linalg.norm(y)
    return tuple(float(v) for v in Rotation.from_matrix(np.column_stack([np.cross(y, z), y, z])).as_quat())


def top_down(closing_angle: float) -> tuple:
    """Pointing straight down, fingers closing along the horizontal direction `closing_angle` (rad)."""
    return frame_quat((0.0, 0.0, -1.0), (np.cos(closing_angle), np.sin(closing_angle), 0.0))


class Driver:
    """Moves the Panda of `world` for a script; every motion runs the physics."""

    def __init__(self, world: "World", seed: int = 0):
        self.world = world
        self.rng = np.random.default_rng(seed)
        self.seed = seed

    # ------------------------------------------------------------------ primitives
    def follow(self, path: Sequence[Sequence[float]], steps: int = STEPS_PER_WAYPOINT,
               stop: Optional[Callable[[], bool]] = None) -> bool:
        """Drive the joints through `path` with the position controllers, then wait until
        the arm is there (or blocked). `stop`, asked after every physics step, ends the
        motion where the arm is; returns whether it did."""
        world = self.world
        # The controllers' targets move smoothly from waypoint to waypoint, one physics step at
        # a time: stop-and-go targets would make a push touch and let go at every waypoint.
        for a, b in zip(path[:-1], path[1:]):
            a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
            for k in range(1, steps + 1):
                world.arm_targets = a + (b - a) * (k / steps)
                world.step()
                if stop is not None and stop():
                    world.arm_targets = world.arm()
                    return True
        if len(path):
            world.arm_targets = np.asarray(path[-1], dtype=float)
        for _ in range(MAX_WAIT // 4):
            if float(np.max(np.abs(world.arm() - world.arm_targets))) < TRACKING:
                break
            world.step(4)
        return False

    def approach(self, target: Sequence[float], orientations: Sequence[Sequence[float]], back: float = 0.08,
                 ignore: Sequence[str] = (), direction: Optional[Sequence[float]] = None) -> int:
        """Get the gripper frame to `target` by a planned free motion to `back` metres before
        it and a straight move along `direction` (default: the gripper's approach axis),
        trying `orientations` in order: the first whose end, start and straight line the arm
        can do without touching anything (fingers as they are; bodies in `ignore` may be
        touched). Returns the index of the orientation used."""
        return self.approach_poses([(target, orn) for orn in orientations], back, ignore, direction)

    def approach_poses(self, poses: Sequence, back: float = 0.08, ignore: Sequence[str] = (),
                       direction: Optional[Sequence[float]] = None, then: Optional[Tuple[Sequence[float], float]] = None,
                       tries: int = 4) -> int:
        """`approach` for a list of gripper poses (position, orientation) tried in order, each
        with up to `tries` IK solutions (from the current joints, then from random ones).
        `then` = (direction, distance): a straight move that must be possible from the pose
        (a pull that a wrist near its joint limit could not make)."""
        world, kin = self.world, self.world.kinematics
        checker = CollisionChecker(world, ignore)
        why = Failure()
        for index, (target, orn) in enumerate(poses):
            axis = np.array(p.getMatrixFromQuaternion(orn)).reshape(3, 3)[:, 2] if direction is None \
                else np.asarray(direction, dtype=float) / np.linalg.norm(direction)
            for attempt in range(tries):
                seed = world.arm() if attempt == 0 else kin.limits.sample(self.rng)
                q = kin.ik(target, orn, self.rng, seed=seed, **IK_TOLERANCE)
                if q is None:
                    why.note(0, self._unreachable(target, orn))
                    continue
                q_pre = kin.ik(np.asarray(target) - back * axis, orn, self.rng, seed=q, restarts=1, **IK_TOLERANCE)
                with world.saved():
                    hit = checker.hits(q) if checker.collides(q) else None
                    hit_pre = None if hit is not None or q_pre is None or not checker.collides(q_pre) \
                        else checker.hits(q_pre)
                # A collision at the pose itself first: no approach distance (`back`) mends it.
                if hit is not None:
                    why.note(2, f"there, {self._hitter()} would hit: {hit}")
                    continue
                if q_pre is None:
                    why.note(1, f"the arm cannot get {back:.2f} m before it to come in straight")
                    continue
                if hit_pre is not None:
                    why.note(2, f"{back:.2f} m before it, {self._hitter()} would hit: {hit_pre}")
                    continue
                path = cartesian_path(world, q_pre, axis, back, self.rng)
                if path is None:
                    why.note(3, "no straight approach to it exists (the wrist would flip on the way)")
                    continue
                blocked = path_collision(world, path, ignore)
                if blocked is not None:
                    why.note(3, f"on the straight approach, {self._hitter()} would hit {blocked}")
                    continue
                if then is not None and cartesian_path(world, path[-1], then[0], then[1], self.rng) is None:
                    why.note(4, f"from there the arm cannot go on {then[1]:.2f} m straight along "
                                f"{np.round(then[0], 2).tolist()}")
                    continue
                self.move_to_q(q_pre, ignore)
                self.follow(path, LINE_STEPS)
                return index
        raise DemoError(f"no way to approach the gripper pose at {np.round(poses[0][0], 3).tolist()}: {why}")

    def _unreachable(self, target: Sequence[float], orn: Sequence[float]) -> str:
        """Why no IK puts the gripper frame at `target` turned `orn`, by the rule docs state:
        the flange, WRIST behind the gripper frame along the fingers, within REACH of the shoulder."""
        base = p.getBasePositionAndOrientation(self.world.robot, physicsClientId=self.world.client)[0]
        shoulder = np.asarray(base) + (0.0, 0.0, SHOULDER)
        fingers = np.array(p.getMatrixFromQuaternion(orn)).reshape(3, 3)[:, 2]
        far = float(np.linalg.norm(np.asarray(target) - WRIST * fingers - shoulder))
        if far > REACH:
            return (f"the arm's flange ({WRIST:.2f} m behind the gripper point, along the fingers) would be "
                    f"{far:.2f} m from the robot's shoulder, beyond its reach ({REACH:.2f} m)")
        return "no arm configuration puts the gripper there turned that way"

    def _hitter(self) -> str:
        held = self.world.attachment.name if self.world.attachment else None
        return f"the arm or the held '{held}'" if held else "the arm"

    def place_held(self, poses: Sequence, back: float = 0.08, ignore: Sequence[str] = (),
                   then: Optional[Tuple[Sequence[float], float]] = None) -> int:
        """Lower the held object straight down onto the first of `poses` (link-frame poses of
        the object) the arm can reach that way; returns its index."""
        grip = self.world.held_tcp_in_object()
        tcp = [tuple(tuple(v) for v in p.multiplyTransforms(pos, orn, grip[0], grip[1])) for pos, orn in poses]
        return self.approach_poses(tcp, back, ignore, direction=(0.0, 0.0, -1.0), then=then)

    def move_to_q(self, q: Sequence[float], ignore: Sequence[str] = ()) -> None:
        """A collision-free planned motion to `q`, followed with physics."""
        result = plan_motion(self.world, self.world.arm(), q, ignore=ignore, seed=self.seed)
        if result.path is None:
            where = np.round(self.world.kinematics.fk(q)[0], 3).tolist()
            raise DemoError(f"no free motion to the gripper at {where}: {result.reason}")
        self.follow(result.path)

    def line(self, direction: Sequence[float], distance: float, steps: int = LINE_STEPS, planned: bool = False,
             stop: Optional[Callable[[], bool]] = None) -> bool:
        """The gripper straight along `direction` for `distance` metres, orientation kept
        (`planned`: if no straight motion exists, a planned one to the same end will do).
        `stop` (see `follow`) may end it earlier; returns whether it did."""
        remaining = distance
        while remaining > 1e-4:
            # A long line can fail where IK from one waypoint to the next jumps branches: then
            # go in shorter pieces, each solved afresh from where the arm actually is.
            piece = remaining
            path = cartesian_path(self.world, self.world.arm(), direction, piece, self.rng)
            while path is None and piece > 0.02:
                piece /= 2
                path = cartesian_path(self.world, self.world.arm(), direction, piece, self.rng)
            if path is None:
                piece = remaining
                path = self._joint_line(direction, piece)
            if path is None and planned:
                self._planned_line(direction, remaining)
                return False
            if path is None:
                position, orn = self.world.tcp_pose()
                end = np.asarray(position) + np.asarray(direction) / np.linalg.norm(direction) * remaining
                raise DemoError(f"no straight motion of {distance:.3f} m along {np.round(direction, 2).tolist()}: "
                                f"{self._unreachable(end, orn)} (keeping the gripper turned as it is, "
                                f"{remaining:.3f} m from its end)")
            if self.follow(path, steps, stop):
                return True
            remaining -= piece
        return False

    def _planned_line(self, direction: Sequence[float], distance: float) -> None:
        """Where no straight motion exists (a wrist at its limit): a planned free motion to the
        same end pose, solved with IK restarts."""
        kin, q0 = self.world.kinematics, self.world.arm()
        start, orn = kin.fk(q0)
        end = np.asarray(start) + np.asarray(direction, dtype=float) / np.linalg.norm(direction) * distance
        # What the hand or the held object touches now may be touched on the way off it.
        touching = self._touching()
        for _ in range(4):
            q1 = kin.ik(end, orn, self.rng, seed=kin.limits.sample(self.rng), **IK_TOLERANCE)
            if q1 is not None and plan_motion(self.world, q0, q1, ignore=touching, seed=self.seed).path is not None:
                self.move_to_q(q1, touching)
                return
        raise DemoError(f"no motion of {distance:.3f} m along {np.round(direction, 2).tolist()}")

    def _touching(self) -> Tuple[str, ...]:
        world = self.world
        names = {body.id: name for name, body in world.bodies.items()}
        movers = [world.robot] + ([world.bodies[world.attachment.name].id] if world.attachment else [])
        found = {names[c[2]] for mover in movers for c in p.getContactPoints(bodyA=mover, physicsClientId=world.client)
                 if c[2] in names and c[8] < 2e-3}
        if world.attachment:
            found.discard(world.attachment.name)
        return tuple(sorted(found))

    def _joint_line(self, direction: Sequence[float], distance: float, tolerance: float = 4e-3) -> Optional[np.ndarray]:
        """A joint-space interpolation to the end of the line (IK with restarts), if the
        gripper stays within `tolerance` of the line all along: where step-by-step IK fails."""
        kin, q0 = self.world.kinematics, self.world.arm()
        start, orn = kin.fk(q0)
        unit = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
        q1 = kin.ik(np.asarray(start) + unit * distance, orn, self.rng, seed=q0, **IK_TOLERANCE)
        if q1 is None:
            return None
        n = max(2, int(np.ceil(distance / 0.01)) + 1)
        path = np.array([q0 + (q1 - q0) * t for t in np.linspace(0.0, 1.0, n)])
        for q in path:
            offset = np.asarray(kin.fk(q)[0]) - np.asarray(start)
            if np.linalg.norm(offset - unit * float(np.dot(offset, unit))) > tolerance:
                return None
        return path

    def up(self, distance: float) -> None:
        """Lift the gripper `distance` metres: straight up, or by a planned motion to there."""
        self.line((0.0, 0.0, 1.0), distance, planned=True)


    # ------------------------------------------------------------------ gripper
    def open(self) -> None:
        set_fingers_dynamic(self.world, MAX_OPENING / 2)

    def close(self) -> None:
        """Close the empty hand (to push with the fingertips)."""
        set_fingers_dynamic(self.world, CLOSED)

    def grasp(self, obj: str, fingers: int = 2) -> None:
        """Hold `obj` where the hand is and close the fingers on it; at least `fingers` of
        them must touch it."""
        self.world.attach(obj)
        set_fingers_dynamic(self.world, CLOSED)
        touching = fingers_touching(self.world, obj)
        if touching < fingers:
            self.world.detach()
            raise DemoError(f"{'one finger' if touching else 'neither finger'} touches {obj} when closed")

    def release(self) -> None:
        self.world.detach()
        self.open()

    def settle(self, steps: Optional[int] = None) -> None:
        if steps is None:
            self.world.settle()
        else:
            self.world.step(steps)
