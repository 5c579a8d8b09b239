"""Following joint trajectories, checked: free-space segments are teleported only after every
configuration along them has been collision-checked, contact motions (pushes, lifts,
retreats, closing the fingers) run with the position controllers and physics on.

Execution never trusts a trajectory: a path that does not start where the arm is, or that
passes through anything, is refused with the reason. This is what makes `replay` a check
of a plan file, and the planner's own executions the same code path as replay's. A change
to how motions are simulated raises planner/plan_document.py's EXECUTION_MODEL.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, List, Optional, Sequence, Set

import numpy as np
import pybullet as p

from ..world.motion import cartesian_path, path_collision
from ..world.render import Camera, View, movable_boxes, render, scene_camera
from ..world.robot import ARM_JOINTS, FINGER_JOINTS
from ..world.world import REST_ANGULAR, REST_LINEAR

if TYPE_CHECKING:
    from ..world.snapshot import Snapshot
    from ..world.world import World

STEPS_PER_WAYPOINT = 8   # ~33 ms of simulated time per 1 cm waypoint: pushes move at ~0.3 m/s
SETTLE_AFTER_MOTION = 60
CLEARANCE = 0.01          # metres: a waypoint this clear of everything, with nothing moving, is teleported
START_TOLERANCE = 1e-3   # radians: a trajectory must start at the arm's configuration
CONTACT_DISTANCE = 2e-3  # metres: a finger this close to the object touches it
FINGER_STEPS = 120       # physics steps at most for the fingers to close or open
RETREAT_STEP = 0.01      # metres: how finely a retreat looks for the point where the way up is clear
LIFT_LEAVES = 0.02       # metres of a lift not checked: what it starts on, it leaves (a table)


class ExecutionError(Exception):
    """A motion that cannot be executed as given (the message says why)."""


class FrameRecorder:
    """Collects frames of an execution for a GIF: one every `every` waypoints, with `camera`,
    or by default with one that frames everywhere the movable objects went, from `view` (a
    block let go on a ramp ends where it slid to): the world's states are kept, and rendered
    by `finish` once the run is over, the camera fixed (a GIF's view does not move)."""

    def __init__(self, camera: Optional[Camera] = None, every: int = 4, view: View = View()):
        self.camera, self.every, self.view, self.frames = camera, every, view, []
        self._count = 0
        self._states: List["Snapshot"] = []
        self._boxes: List = []

    def tick(self, world: "World", force: bool = False) -> None:
        self._count += 1
        if force or self._count % self.every == 0:
            if self.camera is not None:
                self.frames.append(render(world, self.camera))
                return
            self._states.append(world.snapshot())
            self._boxes += movable_boxes(world)

    def finish(self, world: "World") -> None:
        """Render the kept states (the world is left in the last one)."""
        if not self._states:
            return
        camera = scene_camera(world, self.view, boxes=self._boxes or None)
        for state in self._states:
            world.restore(state)
            self.frames.append(render(world, camera))
        self._states, self._boxes = [], []


def _check_start(world: "World", path: Sequence[Sequence[float]], what: str) -> None:
    gap = float(np.max(np.abs(np.asarray(path[0], dtype=float) - world.arm())))
    if gap > START_TOLERANCE:
        raise ExecutionError(f"the {what} starts {gap:.3f} rad away from the arm's configuration")


def follow(world: "World", path: Sequence[Sequence[float]], what: str, ignore: Sequence[str] = (),
           recorder: Optional[FrameRecorder] = None) -> None:
    """Teleport the arm (and what it holds) along `path` once it is known collision-free."""
    if not len(path):
        return
    _check_start(world, path, what)
    hit = path_collision(world, path, ignore)
    if hit is not None:
        raise ExecutionError(f"the {what} collides with {hit}")
    for q in path:
        world.set_arm(q)
        if recorder:
            recorder.tick(world)
    world.reset_contact_caches()  # contacts cached before the teleport describe nothing real


def follow_dynamic(world: "World", path: Sequence[Sequence[float]], what: str,
                   recorder: Optional[FrameRecorder] = None) -> Set[str]:
    """Drive the arm along `path` with its position controllers, simulating contacts; returns
    the objects the hand, or what it holds, touched on the way. The path's free tail (a lift
    once clear, the rest of a retreat) is teleported along when nothing moves: physics there
    would only hold still what rests, at 8 steps a centimetre (`FreeTail`)."""
    touched: Set[str] = set()
    if not len(path):
        return touched
    _check_start(world, path, what)
    names = {body.id: name for name, body in world.bodies.items()}
    movers = [world.robot] + ([world.bodies[world.attachment.name].id] if world.attachment else [])
    tail, teleported = FreeTail(world, path), False
    for index, q in enumerate(path):
        teleported = teleported or tail.starts_at(index)
        if teleported:
            world.set_arm(q)
        else:
            world.arm_targets = np.asarray(q, dtype=float)
            world.step(STEPS_PER_WAYPOINT)
            for mover in movers:
                for contact in p.getContactPoints(bodyA=mover, physicsClientId=world.client):
                    if contact[2] in names and contact[8] < CONTACT_DISTANCE:
                        touched.add(names[contact[2]])
        if recorder:
            recorder.tick(world)
    if not teleported:  # the arm catches up with its last target, what it moved comes to rest
        world.step(SETTLE_AFTER_MOTION)
    if world.attachment:
        touched.discard(world.attachment.name)
    return touched


def _at_rest(world: "World") -> bool:
    """Every movable object slower than `World.settle`'s tolerances (a held one moves with the hand)."""
    held = world.attachment.name if world.attachment else None
    for name in world.movable():
        if name != held:
            linear, angular = p.getBaseVelocity(world.bodies[name].id, physicsClientId=world.client)
            if max(map(abs, linear)) > REST_LINEAR or max(map(abs, angular)) > REST_ANGULAR:
                return False
    return True


def _clear_of_everything(world: "World", links: Optional[Sequence[int]] = None) -> bool:
    """The robot (or only its `links`), and what it holds, at least CLEARANCE from every
    other body; with `links`, from the held one too (closest points, not contacts). The
    robot's base is bolted down: what it is near, no motion changes."""
    held = world.bodies[world.attachment.name].id if world.attachment else None
    robot, client = world.robot, world.client
    for body in world.bodies.values():
        if links is not None:
            if any(p.getClosestPoints(robot, body.id, CLEARANCE, linkIndexA=link, physicsClientId=client)
                   for link in links):
                return False
            continue
        if body.id == held:
            continue
        if any(point[3] != -1 for point in p.getClosestPoints(robot, body.id, CLEARANCE, physicsClientId=client)):
            return False
        if held is not None and p.getClosestPoints(held, body.id, CLEARANCE, physicsClientId=client):
            return False
    return True


class FreeTail:
    """Where a path's free tail starts: the first waypoint from which every later one keeps
    the arm, and what it holds, CLEARANCE from everything, found (scanning back from the end)
    when the world is first at rest, and forgotten when something moves. Teleporting along
    that tail is what physics would do there (to creep below the rest tolerances), and the
    arm ends exactly at the last waypoint instead of lagging behind it."""

    def __init__(self, world: "World", path: Sequence[Sequence[float]]):
        self.world, self.path = world, path
        self.first: Optional[int] = None

    def starts_at(self, index: int) -> bool:
        world = self.world
        if world.observers:  # a recording sees every physics step
            return False
        if not _at_rest(world):
            self.first = None
            return False
        if self.first is None:
            self.first = self._scan(index)
        return index >= self.first

    def _scan(self, index: int) -> int:
        world, client = self.world, self.world.client
        joints = p.getJointStates(world.robot, ARM_JOINTS, physicsClientId=client)
        held = world.bodies[world.attachment.name].id if world.attachment else None
        held_state = (p.getBasePositionAndOrientation(held, physicsClientId=client),
                      p.getBaseVelocity(held, physicsClientId=client)) if held is not None else None
        targets = world.arm_targets
        first = index
        for later in range(len(self.path) - 1, index - 1, -1):
            world.set_arm(self.path[later])
            if not _clear_of_everything(world):
                first = later + 1
                break
        _reset_joints(world, ARM_JOINTS, joints)
        world.arm_targets = targets
        if held_state is not None:
            (position, orientation), (linear, angular) = held_state
            p.resetBasePositionAndOrientation(held, position, orientation, physicsClientId=client)
            p.resetBaseVelocity(held, linear, angular, physicsClientId=client)
        return first


def move_straight(world: "World", direction: Sequence[float], distance: float, what: str,
                  recorder: Optional[FrameRecorder] = None) -> Set[str]:
    """Move the gripper straight along `direction` with physics on (a lift, a retreat)."""
    # IK here draws no random restarts (it is seeded with the current configuration), so
    # the same state always gives the same motion.
    path = cartesian_path(world, world.arm(), direction, distance, np.random.default_rng(0))
    if path is None:
        raise ExecutionError(f"no straight {what}")
    return follow_dynamic(world, path, what, recorder)


def back_out(world: "World", direction: Sequence[float], at_least: float, at_most: float,
             lift: Sequence[float], lift_distance: float, recorder: Optional[FrameRecorder] = None) -> Set[str]:
    """Retreat straight along `direction` by `at_least`, and on (up to `at_most`) to the
    first point from which a straight lift of `lift_distance` is collision-free, if there
    is one. A tool poked into a tunnel must come back out the way it went in: lifted
    inside, it jams against the roof and leaves the arm in collision (Poking: 579 of 730
    motion plans after a poke failed on a start configuration jammed in the tunnel)."""
    rng = np.random.default_rng(0)  # no random restarts: the same state, the same motion
    path = cartesian_path(world, world.arm(), direction, at_least, rng)
    if path is None:
        raise ExecutionError("no straight retreat")
    if not _lift_is_free(world, path[-1], lift, lift_distance, rng):
        # A centimetre at a time: a long straight line can fail at its far end (out of
        # reach, a wrist flip) when its first part would have done.
        further = [path[-1]]
        for _ in range(int(np.floor((at_most - at_least) / RETREAT_STEP))):
            step = cartesian_path(world, further[-1], direction, RETREAT_STEP, rng)
            if step is None:
                break
            further.append(step[-1])
            if _lift_is_free(world, further[-1], lift, lift_distance, rng):
                path = np.concatenate([path, further[1:]])
                break
    return follow_dynamic(world, path, "retreat", recorder)


def _lift_is_free(world: "World", q: Sequence[float], lift: Sequence[float], distance: float,
                  rng: np.random.Generator) -> bool:
    """Whether a straight lift from `q` hits nothing once it is LIFT_LEAVES on its way. A
    tool pushed along the table touches the table where its lift starts, and checking that
    first waypoint judged every lift of a low tool blocked: the retreat then stopped at its
    fixed back-off, inside the tunnel, and the lift jammed the tool against the roof (on
    Poking's test instances most pushes ended so, and every motion after them failed on a
    start configuration in collision). What a lift can hit, a roof, lies above that."""
    path = cartesian_path(world, q, lift, distance, rng)
    if path is None:
        return False
    # The waypoints are evenly spaced; the top one is checked however short the lift.
    leaves = min(int(np.ceil(LIFT_LEAVES / distance * (len(path) - 1))), len(path) - 1)
    return path_collision(world, path[leaves:]) is None


def set_fingers_dynamic(world: "World", half_width: float, recorder: Optional[FrameRecorder] = None) -> None:
    """Drive both fingers to `half_width` with physics until they stop (on an object or at the
    target); teleported there instead where nothing moves and they end clear of everything."""
    world.finger_target = half_width
    if not _teleport_fingers_free(world, half_width):
        previous = None
        for step in range(FINGER_STEPS):
            world.step()
            now = [s[0] for s in p.getJointStates(world.robot, FINGER_JOINTS, physicsClientId=world.client)]
            if previous is not None and step >= 10 and max(abs(a - b) for a, b in zip(now, previous)) < 1e-5:
                break
            previous = now
    if recorder:
        recorder.tick(world, force=True)


def _teleport_fingers_free(world: "World", half_width: float) -> bool:
    """Set the fingers to `half_width` if nothing records the run or moves and they are
    CLEARANCE from every body (the held one included) where they are and at `half_width`:
    they then sweep through free space. Else leave them (False)."""
    if world.observers or not _at_rest(world) or not _clear_of_everything(world, FINGER_JOINTS):
        return False
    joints = p.getJointStates(world.robot, FINGER_JOINTS, physicsClientId=world.client)
    world.set_fingers(half_width)
    if _clear_of_everything(world, FINGER_JOINTS):
        return True
    _reset_joints(world, FINGER_JOINTS, joints)
    world.finger_target = half_width
    return False


def _reset_joints(world: "World", joints: Sequence[int], states: Sequence[tuple]) -> None:
    """Put `joints` back to their `states` (getJointStates' positions and velocities)."""
    for joint, (position, velocity, _, _) in zip(joints, states):
        p.resetJointState(world.robot, joint, position, velocity, physicsClientId=world.client)


def fingers_touching(world: "World", obj: str) -> int:
    """How many of the two fingers touch `obj`."""
    body = world.bodies[obj].id
    return sum(bool([c for c in p.getContactPoints(world.robot, body, link, -1, physicsClientId=world.client)
                     if c[8] < CONTACT_DISTANCE]) for link in FINGER_JOINTS)


def robot_touches(world: "World", obj: str) -> bool:
    """Whether any link of the robot touches `obj` (contacts of the last simulated step)."""
    body = world.bodies[obj].id
    return any(c[8] < CONTACT_DISTANCE for c in p.getContactPoints(world.robot, body, physicsClientId=world.client))
