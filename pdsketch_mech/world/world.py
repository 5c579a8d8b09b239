"""`World`: one PyBullet client with the Panda and a problem's scene objects.

Every call passes `physicsClientId`, so worlds in one process (and across processes) never
share simulator state. Poses are those of the URDF link frame, whatever the inertial
frame: PyBullet reports a base's centre-of-mass frame, which we convert.

Grasping attaches the held object to the hand with a fixed constraint (`attachment.py`) and
closes the fingers on it: a constraint is deterministic and lets a held tool push other
objects hard, which pure finger friction in PyBullet does unreliably.
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass
from typing import Callable, Dict, Iterator, List, Optional, Sequence, Tuple

import numpy as np
import pybullet as p

from ..lang.scene import SceneObject
from .attachment import Attachment, compose, create_attachment, hand_inertial, held_pose, relative_pose, release
from .robot import (ARM_JOINTS, FINGER_JOINTS, HAND_LINK, HOME, MAX_OPENING, REACH, SHOULDER, TCP_LINK, WRIST,
                    Kinematics, Pose, disable_touching_self_pairs, load_mount, load_panda, rotation_angle)
from .snapshot import (Collider, Snapshot, collider_groups, reset_contact_caches, restore_snapshot, set_check_groups,
                       take_snapshot)

TIME_STEP = 1.0 / 240.0
GRIPPER_FORCE = 40.0
ARM_FORCE = 240.0


@dataclass
class Body:
    name: str
    id: int
    fixed: bool
    inertial: Pose  # the centre-of-mass frame in the link frame
    urdf: str = ""
    scale: float = 1.0


class SceneError(ValueError):
    """A scene that cannot be built (unknown asset, overlapping objects); names the object."""

    def __init__(self, name: str, message: str):
        self.object_name = name
        super().__init__(f"scene object '{name}': {message}")


REST_LINEAR, REST_ANGULAR = 2e-3, 2e-2  # m/s, rad/s: an object slower than these is at rest

class World:
    """A simulated tabletop: the Panda at `robot_base` and objects added from a scene."""

    def __init__(self, gui: bool = False, robot_base: Pose = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
                 visual: bool = True):
        """`visual=False` skips the meshes only a camera sees: a world that is never rendered
        (planning, self-play) loads in a fraction of the time, with the same physics."""
        self.client = p.connect(p.GUI if gui else p.DIRECT)
        self.visual = visual or gui
        p.setGravity(0, 0, -9.81, physicsClientId=self.client)
        p.setTimeStep(TIME_STEP, physicsClientId=self.client)
        # Solve contact pairs in a sorted order, not the broadphase's discovery order (which
        # depends on where links were when last detected: a restore must not depend on it).
        p.setPhysicsEngineParameter(deterministicOverlappingPairs=1, physicsClientId=self.client)
        self.robot = load_panda(self.client, robot_base, visual=self.visual)
        self.mount = load_mount(self.client, robot_base, visual=self.visual)
        self.kinematics = Kinematics(robot_base)
        self.bodies: Dict[str, Body] = {}
        self.attachment: Optional[Attachment] = None
        self.sim_steps = 0  # physics steps simulated, for statistics
        # Called with the world after every physics step (demonstration recording); see `step`.
        self.observers: List[Callable[["World"], None]] = []
        self.arm_targets = np.array(HOME)
        self.finger_target = MAX_OPENING / 2
        self.hand_com = hand_inertial(self.client, self.robot)
        # The base is bolted down: where the shoulder is never changes (within_reach's hot path).
        self.shoulder = np.array(compose(robot_base, ((0, 0, SHOULDER), (0, 0, 0, 1)))[0])  # the arm's first pivot
        self._colliders: Optional[Tuple[Collider, ...]] = None
        self._checking: Optional[int] = None  # the held body's id (-1: none) while check groups are on
        self.set_arm(HOME)
        self.set_fingers(MAX_OPENING / 2)
        self._hold_position()
        disable_touching_self_pairs(self.client, self.robot)
        self.reset_contact_caches()  # the canonical collision groups, from the start

    # ------------------------------------------------------------------ lifetime
    def close(self) -> None:
        if self.client >= 0:
            p.disconnect(self.client)
            self.kinematics.close()
            self.client = -1

    def __enter__(self) -> "World":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __reduce_ex__(self, protocol):
        # A World is a handle on a simulator in this process: a copy elsewhere would hold a
        # dead client id. Processes rebuild their own world from the problem text instead.
        raise TypeError("a World cannot be pickled (it wraps a PyBullet client of this process): "
                        "send the problem text and seed, and build the world where it is used")

    # ------------------------------------------------------------------ objects
    def add_object(self, obj: SceneObject, urdf: str) -> Body:
        """Load `obj` from `urdf` at its scene pose, with its physical overrides."""
        if obj.name in self.bodies:
            raise SceneError(obj.name, "is already in the world")
        scale = obj.scale[0]
        if any(abs(s - scale) > 1e-9 for s in obj.scale):
            raise SceneError(obj.name, "PyBullet scales URDFs uniformly; give one :scale factor")
        flags = p.URDF_USE_INERTIA_FROM_FILE | (0 if self.visual else p.URDF_IGNORE_VISUAL_SHAPES)
        body_id = p.loadURDF(urdf, obj.position, obj.orientation, useFixedBase=obj.fixed, globalScaling=scale,
                             flags=flags, physicsClientId=self.client)
        info = p.getDynamicsInfo(body_id, -1, physicsClientId=self.client)
        body = Body(obj.name, body_id, obj.fixed, (tuple(info[3]), tuple(info[4])), urdf, scale)
        self.bodies[obj.name] = body
        self._colliders = None
        # Sleeping bodies keep a deactivation timer that no snapshot can see or restore;
        # a resting object that may or may not be asleep makes restores inexact.
        changes = {"activationState": p.ACTIVATION_STATE_DISABLE_SLEEPING}
        if obj.mass is not None and not obj.fixed:
            changes["mass"] = obj.mass
        if obj.friction is not None:
            changes["lateralFriction"] = obj.friction
        p.changeDynamics(body_id, -1, physicsClientId=self.client, **changes)
        if obj.color is not None and self.visual:
            p.changeVisualShape(body_id, -1, rgbaColor=obj.color, physicsClientId=self.client)
        self.set_pose(obj.name, (obj.position, obj.orientation))
        self.reset_contact_caches()
        return body

    def mass(self, name: str) -> float:
        """The body's mass in kg as the simulator has it (a fixed body's is its file's)."""
        return float(p.getDynamicsInfo(self.bodies[name].id, -1, physicsClientId=self.client)[0])

    def movable(self) -> List[str]:
        return [name for name, body in self.bodies.items() if not body.fixed]

    def pose(self, name: str) -> Pose:
        """The link-frame pose of an object."""
        body = self.bodies[name]
        com = p.getBasePositionAndOrientation(body.id, physicsClientId=self.client)
        inv = p.invertTransform(*body.inertial)
        pos, orn = p.multiplyTransforms(com[0], com[1], inv[0], inv[1])
        return tuple(pos), tuple(orn)

    def set_pose(self, name: str, pose: Pose) -> None:
        body = self.bodies[name]
        pos, orn = p.multiplyTransforms(pose[0], pose[1], *body.inertial)
        p.resetBasePositionAndOrientation(body.id, pos, orn, physicsClientId=self.client)
        p.resetBaseVelocity(body.id, (0, 0, 0), (0, 0, 0), physicsClientId=self.client)

    def aabb(self, name: str) -> Tuple[np.ndarray, np.ndarray]:
        lo, hi = p.getAABB(self.bodies[name].id, -1, physicsClientId=self.client)
        return np.array(lo), np.array(hi)

    def rest_on(self, name: str, support: str, xy: Optional[Sequence[float]] = None,
                yaw: Optional[float] = None, gap: float = 1e-3) -> Pose:
        """Put `name` at `xy` (default: where it is) with its lowest point `gap` above the
        top of `support`'s bounding box; `yaw` (radians) turns it about z. For flat supports."""
        pos, orn = self.pose(name)
        if yaw is not None:
            orn = tuple(p.getQuaternionFromEuler((0.0, 0.0, yaw)))
        x, y = xy if xy is not None else pos[:2]
        self.set_pose(name, ((x, y, pos[2]), orn))
        # Bounding boxes include PyBullet's ~4 mm collision margin: use them to get close,
        # then the true closest distance to land `gap` above the support.
        z = pos[2] + self.aabb(support)[1][2] + 0.01 - self.aabb(name)[0][2]
        self.set_pose(name, ((x, y, z), orn))
        points = p.getClosestPoints(self.bodies[name].id, self.bodies[support].id, 0.1, physicsClientId=self.client)
        if points:
            z -= min(c[8] for c in points) - gap
        pose = ((x, y, z), orn)
        self.set_pose(name, pose)
        return pose

    # ------------------------------------------------------------------ robot
    def arm(self) -> np.ndarray:
        states = p.getJointStates(self.robot, ARM_JOINTS, physicsClientId=self.client)
        return np.array([s[0] for s in states])

    def set_arm(self, q: Sequence[float]) -> None:
        """Teleport the arm (and a held object) to `q`; motors then hold it there."""
        for j, value in zip(ARM_JOINTS, q):
            p.resetJointState(self.robot, j, float(value), 0.0, physicsClientId=self.client)
        self.arm_targets = np.array(q, dtype=float)
        if self.attachment is not None:
            self.set_pose(self.attachment.name, self.held_pose())

    def set_fingers(self, half_width: float) -> None:
        for j in FINGER_JOINTS:
            p.resetJointState(self.robot, j, half_width, 0.0, physicsClientId=self.client)
        self.finger_target = half_width

    def hand_pose(self) -> Pose:
        state = p.getLinkState(self.robot, HAND_LINK, computeForwardKinematics=True, physicsClientId=self.client)
        return tuple(state[4]), tuple(state[5])

    def tcp_pose(self) -> Pose:
        """The gripper frame (between the fingertips; z = approach, y = closing axis)."""
        state = p.getLinkState(self.robot, TCP_LINK, computeForwardKinematics=True, physicsClientId=self.client)
        return tuple(state[4]), tuple(state[5])

    def within_reach(self, tcp: np.ndarray) -> bool:
        """A cheap necessary condition for IK of a gripper-frame pose (4x4 matrix): the
        flange, WRIST behind it, lies within REACH of the shoulder. Spares the solver's
        ~0.1 s of failing restarts for poses far out of reach."""
        return bool(self.within_reach_all(tcp[None])[0])

    def within_reach_all(self, tcps: np.ndarray) -> np.ndarray:
        """`within_reach` for each of `tcps` (n, 4, 4) at once: (n,) booleans."""
        return np.linalg.norm(tcps[:, :3, 3] - WRIST * tcps[:, :3, 2] - self.shoulder, axis=1) < REACH

    def held_tcp_in_object(self) -> Optional[Pose]:
        """The current grasp as the gripper frame's pose in the held object's frame."""
        if self.attachment is None:
            return None
        return relative_pose(self.pose(self.attachment.name), self.tcp_pose())

    def held_pose(self) -> Pose:
        """Where the held object belongs given the hand's current pose."""
        return held_pose(self.hand_pose(), self.attachment)

    def _hold_position(self) -> None:
        p.setJointMotorControlArray(self.robot, ARM_JOINTS, p.POSITION_CONTROL, targetPositions=list(self.arm_targets),
                                    forces=[ARM_FORCE] * 7, physicsClientId=self.client)
        p.setJointMotorControlArray(self.robot, FINGER_JOINTS, p.POSITION_CONTROL,
                                    targetPositions=[self.finger_target] * 2, forces=[GRIPPER_FORCE] * 2,
                                    physicsClientId=self.client)

    def attach(self, name: str, in_hand: Optional[Pose] = None) -> Attachment:
        """Hold `name`: where it is now relative to the hand, or moved to `in_hand`."""
        if self.attachment is not None:
            raise RuntimeError(f"already holding '{self.attachment.name}'")
        hand = self.hand_pose()
        if in_hand is None:
            in_hand = relative_pose(hand, self.pose(name))
        else:
            self.set_pose(name, compose(hand, in_hand))
        body = self.bodies[name]
        self.attachment = create_attachment(self.client, self.robot, name, body.id, body.inertial, in_hand,
                                            self.hand_com)
        return self.attachment

    def detach(self) -> Optional[str]:
        if self.attachment is None:
            return None
        release(self.client, self.attachment)
        name, self.attachment = self.attachment.name, None
        return name

    # ------------------------------------------------------------------ physics
    def step(self, steps: int = 1) -> None:
        self.physics_groups()
        self._hold_position()
        for _ in range(steps):
            p.stepSimulation(physicsClientId=self.client)
            if self.attachment is not None:
                self._pin_held()
            self.sim_steps += 1
            for observer in self.observers:  # the world as it is after this step
                observer(self)

    def _pin_held(self) -> None:
        """Put the held object back exactly at its grasp, moving with the hand.

        The grasp constraint carries the object's forces to the arm (a pulled box resists),
        but PyBullet solves constraints softly: squeezing fingers and a turning wrist move
        the object several millimetres and degrees off the grasp within a second. Samplers
        and learned grasps assume the grasp holds, so after every step the object is
        re-pinned to the hand, with the hand's velocity at that point."""
        state = p.getLinkState(self.robot, HAND_LINK, computeLinkVelocity=1, computeForwardKinematics=True,
                               physicsClientId=self.client)
        body = self.bodies[self.attachment.name]
        self.set_pose(self.attachment.name, held_pose((state[4], state[5]), self.attachment))
        com = p.getBasePositionAndOrientation(body.id, physicsClientId=self.client)[0]
        # The velocity at the object's COM: v + w x r, r from the hand's COM (state[0]). Plain
        # floats: this runs after every physics step while something is held (np.cross: ~30 us).
        (vx, vy, vz), (wx, wy, wz) = state[6], state[7]
        rx, ry, rz = com[0] - state[0][0], com[1] - state[0][1], com[2] - state[0][2]
        linear = [vx + (wy * rz - wz * ry), vy + (wz * rx - wx * rz), vz + (wx * ry - wy * rx)]
        p.resetBaseVelocity(body.id, linear, list(state[7]), physicsClientId=self.client)

    def settle(self, max_steps: int = 480, linear_tol: float = REST_LINEAR, angular_tol: float = REST_ANGULAR,
               quiet_steps: int = 10) -> int:
        """Step until every movable object has been at rest for `quiet_steps` steps (or
        `max_steps` pass): the briefly-dynamic outcome of a release or a push. Returns the
        number of steps taken."""
        movable = [self.bodies[n].id for n in self.movable()]
        quiet = 0
        for step in range(1, max_steps + 1):
            self.step()
            moving = False
            for body_id in movable:
                lin, ang = p.getBaseVelocity(body_id, physicsClientId=self.client)
                if np.linalg.norm(lin) > linear_tol or np.linalg.norm(ang) > angular_tol:
                    moving = True
                    break
            quiet = 0 if moving else quiet + 1
            if quiet >= quiet_steps:
                return step
        return max_steps

    # ------------------------------------------------------------------ snapshots
    @property
    def colliders(self) -> Tuple[Collider, ...]:
        if self._colliders is None:
            fixed = {self.mount: True, **{b.id: b.fixed for b in self.bodies.values()}}
            self._colliders = collider_groups(self.robot, fixed, self.client)
        return self._colliders

    def snapshot(self) -> Snapshot:
        movable = [body.id for body in self.bodies.values() if not body.fixed]
        return take_snapshot(self.client, self.robot, movable, self.attachment, self.arm_targets, self.finger_target)

    def restore(self, snapshot: Snapshot) -> None:
        """Back to `snapshot`, canonically: simulating on gives what a fresh world that
        reached the same state would (snapshot.py)."""
        self._checking = None  # the restore puts the canonical groups back
        self.attachment = restore_snapshot(
            self.client, self.robot, snapshot, self.attachment, {n: b.id for n, b in self.bodies.items()},
            {n: b.inertial for n, b in self.bodies.items()}, self.hand_com, self.colliders)
        self.arm_targets = np.array(snapshot.arm_targets)
        self.finger_target = snapshot.finger_target

    def moved_since(self, snapshot: Snapshot, name: str, position_tol: float = 5e-3,
                    angle_tol: float = 0.03) -> bool:
        """Whether movable object `name` is more than `position_tol` metres or `angle_tol`
        radians from where `snapshot` had it (or is held now, and was not then)."""
        body_id = self.bodies[name].id
        if self.attachment is not None and self.attachment.name == name:
            return snapshot.held is None or snapshot.held[0] != name
        for state in snapshot.bodies:
            if state[0] == body_id:
                pos, orn = p.getBasePositionAndOrientation(body_id, physicsClientId=self.client)
                moved = float(np.linalg.norm(np.subtract(pos, state[1])))
                return moved > position_tol or rotation_angle(orn, state[2]) > angle_tol
        return False  # a fixed body never moves

    def reset_contact_caches(self) -> None:
        """Forget cached contacts (done by every restore; a fresh world calls it to match)."""
        reset_contact_caches(self.colliders, self.client)
        self._checking = None

    def check_groups(self) -> None:
        """Collision groups for checking arm configurations (snapshot.py `set_check_groups`):
        contacts between objects that are not the arm's are not computed until
        `physics_groups`, which stepping and reading the contact graph call."""
        held = self.bodies[self.attachment.name].id if self.attachment is not None else -1
        if self._checking != held:
            set_check_groups(self.colliders, self.robot, held, self.client)
            self._checking = held

    def physics_groups(self) -> None:
        """The canonical collision groups back, if checking changed them (and the contacts
        cached meanwhile forgotten, as a restore would)."""
        if self._checking is not None:
            self.reset_contact_caches()

    @contextlib.contextmanager
    def saved(self) -> Iterator["World"]:
        """Restore the world as it was when the block started, however it ends."""
        snapshot = self.snapshot()
        try:
            yield self
        finally:
            self.restore(snapshot)
