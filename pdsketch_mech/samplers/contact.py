"""The generic object-contact sampler C(O1, O2, T_o2, O_s, T_s) (paper Appendix "Samplers for
Generic Operations", "Object Contact (C)").

The pusher O1 is the held object, or the bare gripper when nothing is held. A contact pairs a
point p2 on the target's side (outward normal n2 nearly perpendicular to the support normal
n_s: we never push a target into its support) with a pose of the pusher `gap` away from p2
along n2, facing it: the push direction is -n2 projected onto the support plane. A held
tool's pose T puts one of its own side points p1 there (T p1 = p2 + gap n2, T n1 facing n2),
the tool held as it is now but turned about the support normal and lowered to slide just
above the support: a straight tool held diagonally pulls with its tip, a hook with its
crook. Proposals pass cheap tests (facing, the hand within reach, no penetration at the
contact and backed off); verifying asks IK and the collision checker for the arm at the
contact pose and at a pre-contact pose backed off along n2. Only shapes and poses are read,
never names or categories.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Iterator, Optional, Tuple

import numpy as np
import pybullet as p

from ..world.collision import CollisionChecker, body_penetrates
from ..world.robot import CLOSED
from ..world.values import Contact
from .budget import SamplerBudget
from .geometry import body_mesh, matrix_pose, pose_matrix, rotvec_matrices, sample_surface
from .mesh import Mesh
from .gripper import FINGER_HALF_WIDTH, FINGER_TIP, HAND_UNDERSIDE
from .interface import SampleRequest, Sampler

if TYPE_CHECKING:
    from ..world.world import World

SIDE_COS = 0.2          # |n2 . n_s| below this: a side of the target
FLARED_COS = 0.5        # ... or below this when no face qualifies (plates, bowls: rims at ~25 deg)
UP_COS = 0.2            # tool points whose normal keeps the tool's "up" within this
BACK = 0.02             # pre-contact: metres further back along n2 (a pull starts beyond the target: every cm costs reach)
PENETRATION = 1e-3      # deeper than this counts as penetrating (tool vs world)
FACING_COS = 0.3        # the tool point's normal must face the target's by at least this
SLIDE = 0.004           # metres between a held tool's underside and the target's support
MAX_TIP = 0.7           # radians a held tool may be tipped (its far end down) for a contact
# How many points, turns, poses and IK restarts a proposal or a verification spends:
# budget.py (SamplerBudget.contact_*).


@lru_cache(maxsize=128)
def _face_weights(mesh: Mesh) -> np.ndarray:
    """Sampling weights per face: half by area, half uniform over planar regions, so that
    small faces of a shape (the inside of a hook's crook) are not drowned by big ones."""
    area = mesh.area_faces
    region_area = area.copy()
    for facet, facet_area in zip(mesh.facets, mesh.facets_area):
        region_area[facet] = facet_area
    regions = len(mesh.faces) - sum(len(f) for f in mesh.facets) + len(mesh.facets)
    weights = 0.5 * area / area.sum() + 0.5 * area / np.maximum(region_area, 1e-12) / regions
    return weights / weights.sum()


def surface_points(mesh: Mesh, count: int, rng: np.random.Generator) -> Tuple[np.ndarray, np.ndarray]:
    """`count` surface points (mesh frame) with outward normals, drawn by `_face_weights`."""
    return sample_surface(mesh, count, rng, _face_weights(mesh))


def support_frame(world: "World", target: str, support: str) -> Tuple[np.ndarray, np.ndarray]:
    """(n_s, a point of the support surface): the mean contact normal from `support` to
    `target` and the mean contact point on the support; +z and the top of the support's
    bounding box under the target when they are not within 2 cm."""
    a, b, client = world.bodies[target].id, world.bodies[support].id, world.client
    world.physics_groups()
    p.performCollisionDetection(physicsClientId=client)
    # A target resting a hair above its support has no contact points: use the closest ones.
    contacts = p.getContactPoints(a, b, physicsClientId=client) or p.getClosestPoints(a, b, 0.02, physicsClientId=client)
    if contacts:
        normal = np.mean([c[7] for c in contacts], axis=0)  # on B (support), from B to A
        if np.linalg.norm(normal) > 1e-6:
            return normal / np.linalg.norm(normal), np.mean([c[6] for c in contacts], axis=0)
    lo, hi = world.aabb(target)
    return np.array([0.0, 0.0, 1.0]), np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, world.aabb(support)[1][2]])


def _arm_reaches(world: "World", gripper: np.ndarray, back: np.ndarray, rng: np.random.Generator,
                 checker: CollisionChecker, budget: SamplerBudget = SamplerBudget()) -> bool:
    """IK for the gripper frame `gripper` (4x4; `budget.contact_ik_restarts` restarts) and,
    seeded from it, for it moved by `back`, both free of collisions (the world's current
    fingers and held object)."""
    backed = gripper.copy()
    backed[:3, 3] += back
    if not (world.within_reach(gripper) and world.within_reach(backed)):
        return False
    pose = matrix_pose(gripper)
    q = world.kinematics.ik(pose[0], pose[1], rng, seed=world.arm(), restarts=budget.contact_ik_restarts)
    if q is None or checker.collides(q):
        return False
    q_pre = world.kinematics.ik(np.add(pose[0], back), pose[1], rng, seed=q)
    return q_pre is not None and not checker.collides(q_pre)


@dataclass(frozen=True, eq=False)
class ContactCandidate:
    """A proposed contact: pusher poses to try (4x4 world; a held tool's pose, or the
    gripper frame for each way round of the hand's yaw) and the gripper frames they need."""

    pushers: Tuple[np.ndarray, ...]
    grippers: Tuple[np.ndarray, ...]
    back: np.ndarray            # the pre-contact offset (world)
    point: np.ndarray           # on the target
    direction: np.ndarray       # the push direction
    normal: np.ndarray          # the target's outward normal at `point`


def _gripper_frames(p2: np.ndarray, d: np.ndarray, n_s: np.ndarray, level: float, top: float,
                    gap: float, rng: np.random.Generator) -> Tuple[np.ndarray, ...]:
    """Gripper frames (4x4, both ways round in random order) pushing at p2 with closed
    fingers, or () when the fingers would miss p2. Heights are along n_s above the support
    surface (`level`); `top` is the target's top."""
    h2 = float(np.dot(p2, n_s)) - level
    reach = FINGER_TIP + HAND_UNDERSIDE  # from the fingertips to the hand's underside
    # Fingertips hit the side between 1 cm above the support and 5 mm below the target's top,
    # high enough that the hand (wider than the fingers along d) passes over the target.
    lo, hi = max(0.01, top - reach + 0.005), top - 0.005
    if hi < lo:  # a flat target: as high as its top allows, at least halfway up
        lo = hi = max(top / 2, hi)
    tip = float(np.clip(h2 - 0.01, lo, hi))
    if not tip - 0.002 <= h2 <= tip + reach - 0.002:
        return ()  # the fingers would not touch the target at p2
    position = p2 - d * (gap + FINGER_HALF_WIDTH) + n_s * (tip + FINGER_TIP - h2)
    z = -n_s
    frames = []
    for sign in rng.permutation([1.0, -1.0]):
        x = sign * d
        frame = np.eye(4)
        frame[:3, :3] = np.column_stack([x, np.cross(z, x), z])
        frame[:3, 3] = position
        frames.append(frame)
    return tuple(frames)


def _tool_poses(world: "World", tool: str, tool_vertices: np.ndarray, p1: np.ndarray, n1: np.ndarray,
                p2: np.ndarray, n2: np.ndarray, n_s: np.ndarray, level: float, gap: float,
                tcp_in_tool: np.ndarray, rng: np.random.Generator,
                budget: SamplerBudget = SamplerBudget()) -> Tuple[np.ndarray, ...]:
    """Up to `budget.contact_poses_per_point` held-tool poses (4x4) that put tool point p1
    `gap` in front of target point p2, the tool turned about the support normal n_s from how
    it is held now, for half of them also tipped (up to MAX_TIP) so that p1's end of the tool
    goes down and the hand up, and lowered until its lowest point is SLIDE above the support.
    Of `budget.contact_yaws` turns (random offset), those pass where n1 faces the target,
    the hand is within reach, and the tool penetrates nothing at the contact nor backed
    off: a straight tool held diagonally pulls with its tip, a crook with its inner face,
    whatever the object (no face of the tool must match the target's); tipping a tool held
    from above moves the wrist back towards the robot, which is what a short tool needs to
    reach behind a far object."""
    now = pose_matrix(world.pose(tool))[:3, :3]
    n_yaws = budget.contact_yaws
    yaws = rng.uniform(0.0, 2 * np.pi) + np.arange(n_yaws) * 2 * np.pi / n_yaws
    turns = rotvec_matrices(yaws[:, None] * n_s) @ now          # (k, 3, 3)
    # Tip about the horizontal axis across the line from the hand to p1 (p1 goes down).
    reach = turns @ (p1 - tcp_in_tool[:3, 3])
    reach -= (reach @ n_s)[:, None] * n_s
    axis = np.cross(n_s, reach)
    axis /= np.maximum(np.linalg.norm(axis, axis=1), 1e-9)[:, None]
    tips = np.where(rng.random(n_yaws) < 0.5, rng.uniform(0.0, MAX_TIP, n_yaws), 0.0)
    turns = rotvec_matrices(tips[:, None] * axis) @ turns
    facing = (turns @ n1) @ n2
    lowest = np.min(np.einsum("kij,nj->kni", turns, tool_vertices) @ n_s, axis=1)  # (k,)
    poses = np.tile(np.eye(4), (n_yaws, 1, 1))
    poses[:, :3, :3] = turns
    offset = p2 + gap * n2 - turns @ p1                                           # (k, 3)
    # Slide the contact point along n_s so the tool's lowest point is SLIDE above the support.
    offset += ((level + SLIDE - lowest) - offset @ n_s)[:, None] * n_s
    poses[:, :3, 3] = offset
    keep = [k for k in rng.permutation(n_yaws) if facing[k] < -FACING_COS and world.within_reach(poses[k] @ tcp_in_tool)]
    found = []
    with world.saved():
        for k in keep:
            backed = poses[k].copy()
            backed[:3, 3] += n2 * BACK
            world.set_pose(tool, matrix_pose(poses[k]))
            if body_penetrates(world, tool, PENETRATION):
                continue
            world.set_pose(tool, matrix_pose(backed))
            if not body_penetrates(world, tool, PENETRATION):
                found.append(poses[k])
                if len(found) == budget.contact_poses_per_point:
                    break
    return tuple(found)


def _toward_robot(world: "World", target: str) -> Optional[np.ndarray]:
    """The horizontal unit vector from `target` towards the robot's shoulder if the hand cannot
    reach the target from above (else None)."""
    centre = np.asarray(world.pose(target)[0])
    above = np.eye(4)
    above[:3, :3] = np.diag([1.0, -1.0, -1.0])  # the gripper pointing down
    above[:3, 3] = centre
    if world.within_reach(above):
        return None
    toward = world.shoulder - centre
    toward[2] = 0.0
    return toward / max(np.linalg.norm(toward), 1e-9)


class ContactSampler(Sampler[ContactCandidate]):
    """C(O1, O2, T_o2, O_s, T_s): the stream's last two inputs are the target and its
    support; the pusher is what the hand holds (the bare gripper when it holds nothing)."""

    gap = 0.01   # metres between the pusher and the target at first contact

    def visit_budget(self, budget: SamplerBudget) -> int:
        return budget.contact_proposals

    def propose(self, world: "World", request: SampleRequest, rng: np.random.Generator,
                budget: int) -> Iterator[ContactCandidate]:
        target, support = request.objects()[-2:]
        return propose_contacts(world, target, support, rng, budget, self.gap, self.sampler_budget)

    def verify(self, world: "World", request: SampleRequest, candidate: ContactCandidate,
               rng: np.random.Generator) -> Optional[Contact]:
        tool = world.attachment.name if world.attachment is not None else None
        checker = CollisionChecker(world)
        with world.saved():
            if tool is None:
                world.set_fingers(CLOSED)
            for pusher, gripper in zip(candidate.pushers, candidate.grippers):
                if _arm_reaches(world, gripper, candidate.back, rng, checker, self.sampler_budget):
                    target, support = request.objects()[-2:]
                    return Contact(tool, target, support, matrix_pose(pusher),
                                   tuple(float(v) for v in candidate.direction),
                                   tuple(float(v) for v in candidate.point), tuple(float(v) for v in candidate.normal))
        return None


@dataclass
class ContactScene:
    """What contacts with `target` (resting on `support`) are made from, read once per batch:
    the support's normal and level, the target's top, which of its faces count as sides, and
    the held tool's side points (none for the bare gripper)."""

    world: "World"
    n_s: np.ndarray
    level: float
    top: float
    side_cos: float
    gap: float
    budget: SamplerBudget
    tool: Optional[str] = None
    tool_points: Optional[np.ndarray] = None
    tool_normals: Optional[np.ndarray] = None
    usable: Optional[np.ndarray] = None      # indices of the tool points on a side as it is held
    tool_vertices: Optional[np.ndarray] = None
    tcp_in_tool: Optional[np.ndarray] = None

    @staticmethod
    def read(world: "World", target: str, support: str, gap: float, budget: SamplerBudget,
             tool_points: Optional[Tuple[np.ndarray, np.ndarray]] = None) -> "ContactScene":
        """The scene as it is now; `tool_points` (points, normals in the tool's frame) are
        needed when the hand holds a tool."""
        n_s, support_point = support_frame(world, target, support)
        level = float(np.dot(support_point, n_s))
        target_mesh = body_mesh(world, target)
        target_pose = pose_matrix(world.pose(target))
        top = float(np.max((target_mesh.vertices @ target_pose[:3, :3].T + target_pose[:3, 3]) @ n_s)) - level
        tilt = np.abs(target_mesh.face_normals @ (target_pose[:3, :3].T @ n_s))
        scene = ContactScene(world, n_s, level, top, SIDE_COS if np.any(tilt < SIDE_COS) else FLARED_COS, gap, budget)
        if world.attachment is not None:
            scene.tool = world.attachment.name
            scene.tool_points, scene.tool_normals = tool_points
            # A tool point on a side of the tool as it is held (its up is kept).
            up = pose_matrix(world.pose(scene.tool))[:3, :3].T @ np.array([0.0, 0.0, 1.0])
            scene.usable = np.flatnonzero(np.abs(scene.tool_normals @ up) < UP_COS)
            scene.tool_vertices = np.asarray(body_mesh(world, scene.tool).vertices)
            scene.tcp_in_tool = pose_matrix(world.held_tcp_in_object())
        return scene

    def direction(self, n2: np.ndarray) -> Optional[np.ndarray]:
        """The push direction at a target point of outward normal `n2` (world): -n2 along the
        support; None where `n2` is not a side (never push a target into its support)."""
        if abs(float(np.dot(n2, self.n_s))) >= self.side_cos:
            return None
        d = -(n2 - np.dot(n2, self.n_s) * self.n_s)
        return d / np.linalg.norm(d)

    def candidate(self, p2: np.ndarray, n2: np.ndarray, d: np.ndarray,
                  rng: np.random.Generator) -> Optional[ContactCandidate]:
        """A contact at target point `p2` (world, normal `n2`, push direction `d`): the bare
        gripper's frames, or a random side point of the held tool put in front of it (None if
        none fits)."""
        if self.tool is None:
            frames = _gripper_frames(p2, d, self.n_s, self.level, self.top, self.gap, rng)
            return ContactCandidate(frames, frames, -d * BACK, p2, d, n2) if frames else None
        if not len(self.usable):
            return None
        i = int(rng.choice(self.usable))
        poses = _tool_poses(self.world, self.tool, self.tool_vertices, self.tool_points[i], self.tool_normals[i], p2,
                            n2, self.n_s, self.level, self.gap, self.tcp_in_tool, rng, self.budget)
        return ContactCandidate(poses, tuple(pose @ self.tcp_in_tool for pose in poses), n2 * BACK, p2, d, n2) \
            if poses else None


def held_tool_points(world: "World", rng: np.random.Generator,
                     budget: SamplerBudget) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """`budget.contact_tool_points` surface points of the held tool with their normals (its
    frame), None when the hand is empty."""
    if world.attachment is None:
        return None
    return surface_points(body_mesh(world, world.attachment.name), budget.contact_tool_points, rng)


def propose_contacts(world: "World", target: str, support: str, rng: np.random.Generator, max_points: int,
                     gap: float = 0.01, budget: SamplerBudget = SamplerBudget()) -> Iterator[ContactCandidate]:
    """Contacts of the held object (or the bare gripper) with the side of `target`, which
    rests on `support`, from geometry alone (no IK): examines at most `max_points` target
    points (one tool point each when a tool is held), `budget.contact_batch` at a time.
    A target the hand cannot reach from above is pulled more often than pushed further away
    (`budget.contact_pull_bias`): only a pull can bring it within reach."""
    target_mesh = body_mesh(world, target)
    tool_points = held_tool_points(world, rng, budget)
    toward = _toward_robot(world, target)
    bias = budget.contact_pull_bias
    examined = 0
    while examined < max_points:
        # Re-read the scene per batch: the caller may move things between yields.
        scene = ContactScene.read(world, target, support, gap, budget, tool_points)
        target_pose = pose_matrix(world.pose(target))
        count = min(budget.contact_batch, max_points - examined)
        examined += count
        local_points, local_normals = surface_points(target_mesh, count, rng)
        points = local_points @ target_pose[:3, :3].T + target_pose[:3, 3]
        normals = local_normals @ target_pose[:3, :3].T
        for p2, n2 in zip(points, normals):
            d = scene.direction(n2)
            if d is None:
                continue
            if toward is not None and rng.random() * (1 + bias) > 1 + bias * max(0.0, float(d @ toward)):
                continue
            candidate = scene.candidate(p2, n2, d, rng)
            if candidate is not None:
                yield candidate


def sample_contacts(world: "World", target: str, support: str, rng: np.random.Generator,
                    max_attempts: Optional[int] = None, gap: float = 0.01,
                    deadline: float = float("inf"), budget: SamplerBudget = SamplerBudget()) -> Iterator[Contact]:
    """Reachable, collision-free contacts of the held object (or the bare gripper) with the
    side of `target`, which rests on `support`; stops after `max_attempts` proposals
    (default `budget.sample_attempts`) or at `deadline` (time.perf_counter()). The world is
    left as found."""
    sampler = ContactSampler(budget)
    sampler.gap = gap
    request = SampleRequest("sample-contact", (target, support), ("?y", "?s"), deadline=deadline)
    limit = budget.sample_attempts if max_attempts is None else max_attempts
    return sampler.draw(world, request, rng, budget=limit)
