"""The generic placement sampler P(O1, O2, T_o2) (paper Appendix "Samplers for Generic Operations").

A resting face (a facet of the held object's convex hull, normal n1) is put against a
surface point p2 of the support whose normal n2 points up (n2 . z > up_cos, so slopes
count): n1 is turned onto -n2 with a random twist about n2, and the object is lowered to
`GAP` above the plane through p2. The candidate must not sink into anything, and the arm
holding it there (and at a pre-place pose above) must be reachable and collision-free.
"""
from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING, Iterator, List, Optional, Sequence, Tuple

import numpy as np
import pybullet as p

from ..world.collision import CollisionChecker, PENETRATION, body_penetration
from ..world.contacts import read_contacts
from ..world.values import Placement, Pose
from .budget import SamplerBudget
from .geometry import matrix_pose, pose_matrix, rotation_between, rotvec_matrices, sample_surface, solid_mesh
from .interface import SampleRequest, Sampler
from .mesh import Mesh

if TYPE_CHECKING:
    from ..world.world import World

GAP = 0.002          # metres between the resting face and the support plane
PRE_PLACE = 0.08     # metres above the placement (world z)
SINK = 0.001         # deeper penetration of the object at the placement pose rejects it
RISE = 0.03          # metres a placement may be raised onto relief (rest_on_relief)
# How many raises and IK restarts a placement may cost: budget.py (SamplerBudget.placement_*).

Facet = Tuple[np.ndarray, np.ndarray, float]  # outward normal, centre, area (object frame)


@lru_cache(maxsize=128)
def resting_facets(urdf: str, scale: float, com: Tuple[float, float, float]) -> Tuple[List[Facet], np.ndarray]:
    """The convex hull's facets the object can rest on (its centre of mass projects inside
    them: it would tip over from the others), and the hull's vertices."""
    hull = solid_mesh(urdf, scale).convex_hull
    grouped = {int(f) for facet in hull.facets for f in facet}
    groups = [np.asarray(f) for f in hull.facets] + [np.array([f]) for f in range(len(hull.faces)) if f not in grouped]
    facets: List[Facet] = []
    for faces in groups:
        normal = hull.face_normals[faces[0]]
        areas = hull.area_faces[faces]
        centre = (hull.triangles_center[faces] * areas[:, None]).sum(axis=0) / areas.sum()
        # Project the centre of mass onto the facet plane and test it against its triangles.
        foot = np.asarray(com) - np.dot(np.asarray(com) - centre, normal) * normal
        bary = _barycentric(hull.triangles[faces], foot)
        stable = bool(np.any(np.all(bary >= -1e-6, axis=1)))
        if stable:
            facets.append((normal, centre, float(areas.sum())))
    return facets, np.asarray(hull.vertices)


def _barycentric(triangles: np.ndarray, point: np.ndarray) -> np.ndarray:
    """(n, 3) barycentric coordinates of `point` in each of `triangles` (n, 3, 3), in its plane."""
    v0, v1, v2 = triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0], point - triangles[:, 0]
    d00, d01, d11 = (v0 * v0).sum(1), (v0 * v1).sum(1), (v1 * v1).sum(1)
    d20, d21 = (v2 * v0).sum(1), (v2 * v1).sum(1)
    denominator = d00 * d11 - d01 * d01
    v = (d11 * d20 - d01 * d21) / denominator
    w = (d00 * d21 - d01 * d20) / denominator
    return np.stack([1.0 - v - w, v, w], axis=1)


def up_surface(world: "World", support: str, up_cos: float) -> Optional[Mesh]:
    """The support's faces (world frame) whose normal is within acos(up_cos) of +z."""
    body = world.bodies[support]
    mesh = solid_mesh(body.urdf, body.scale).transformed(pose_matrix(world.pose(support)))
    up = np.nonzero(mesh.face_normals[:, 2] > up_cos)[0]
    return mesh.submesh(up) if len(up) else None


def object_pose(normal: np.ndarray, centre: np.ndarray, vertices: np.ndarray, point: np.ndarray,
                support_normal: np.ndarray, twist: float) -> np.ndarray:
    """4x4 object pose with its facet (`normal`, `centre`) against the plane through `point`
    with normal `support_normal`, `GAP` above it, twisted by `twist` about that normal."""
    rotation = rotvec_matrices(twist * support_normal) @ rotation_between(normal, -support_normal)
    lowest = float(np.min((vertices - centre) @ rotation.T @ support_normal))  # ~0: the facet is on the hull
    matrix = np.eye(4)
    matrix[:3, :3] = rotation
    matrix[:3, 3] = point + (GAP - lowest) * support_normal - rotation @ centre
    return matrix


def rest_on_relief(world: "World", obj: str, support: str, pose: Pose, surface_z: float,
                   holders: Sequence[str] = (), budget: SamplerBudget = SamplerBudget()) -> Optional[Pose]:
    """`pose`, raised (world z, at most RISE, in at most `budget.placement_rise_steps`
    raises) until `obj` no longer sinks into `support` or into `holders` above `surface_z`,
    or None if it sinks into anything else or needs more.
    A resting face is put on the plane through one surface point of the support (at height
    `surface_z`); where the support is not flat under the whole face (a dish's rim under a
    box's end, a bowl's wall) the object rests on that relief instead, tilted once released
    -- the only way a weight gets far out on a plate. `holders`, the fixed bodies the support
    rests on, are relief where they rise above that point: a spoon longer than a plate lies
    across the plate and the wall of the plate's cradle. Not where they lie below it (a box
    on a slope is not propped on the table at its foot), and no other body (a box put on the
    table is not propped against a slope bolted to it). Leaves `obj` there."""
    position, orientation = np.asarray(pose[0], dtype=float), tuple(pose[1])
    relief = {world.bodies[name].id: surface_z - GAP for name in holders}
    relief[world.bodies[support].id] = -np.inf
    for _ in range(budget.placement_rise_steps):
        world.set_pose(obj, (tuple(position), orientation))
        depth = body_penetration(world, obj, relief)
        if depth is None:
            return None
        if depth <= SINK:
            return tuple(float(v) for v in position), orientation
        position[2] += depth + GAP
        if position[2] - pose[0][2] > RISE:
            return None
    return None


def fixed_holders(world: "World", support: str) -> List[str]:
    """The fixed bodies `support` rests on now (a plate's cradle): relief for `rest_on_relief`."""
    return [name for name in read_contacts(world).supports_of(support) if world.bodies[name].fixed]


def placement_configurations(world: "World", placement: Placement, rng: np.random.Generator,
                             budget: SamplerBudget = SamplerBudget()) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """(pre-place, place) arm configurations holding the object at `placement.pose` with the
    current grasp, or None if either has no IK or collides. Only the held object may touch
    the support: the arm may not, and neither may touch anything else. (How deep the object
    sinks into the support is not checked here: `rest_on_relief` checks the exact pose for that.)"""
    kin, held = world.kinematics, world.attachment
    if held is None or held.name != placement.object:
        raise ValueError(f"placing '{placement.object}' requires holding it")
    tcp = p.multiplyTransforms(*placement.pose, *world.held_tcp_in_object())
    if not world.within_reach(pose_matrix(tcp)):  # spares IK's failing restarts (~10 ms)
        return None
    q = kin.ik(tcp[0], tcp[1], rng, seed=world.arm(), restarts=budget.placement_ik_restarts)
    if q is None:
        return None
    held_id, support_id = world.bodies[held.name].id, world.bodies[placement.support].id
    with world.saved():
        if CollisionChecker(world, check_held=False).collides(q):  # the arm against everything
            return None
        # Contacts of that detection are still current: the held object may touch the support
        # (the IK tolerance may lower it past the gap) but nothing else.
        for contact in p.getContactPoints(bodyA=held_id, physicsClientId=world.client):
            if contact[8] < -PENETRATION and contact[2] not in (world.robot, support_id):
                return None
        above = (tcp[0][0], tcp[0][1], tcp[0][2] + PRE_PLACE)
        q_pre = kin.ik(above, tcp[1], rng, seed=q)
        if q_pre is None or CollisionChecker(world).collides(q_pre):
            return None
    return q_pre, q


class PlacementSampler(Sampler[Placement]):
    """P(O1, O2, T_o2): the stream's inputs are the held object and the support. Proposals
    do not sink into anything; verifying asks IK and the collision checker. A visit verifies
    `SamplerBudget.proposals` proposals at most."""

    def propose(self, world: "World", request: SampleRequest, rng: np.random.Generator,
                budget: int) -> Iterator[Placement]:
        obj, support = request.objects()[:2]
        return propose_placements(world, obj, support, rng, max_draws=budget, budget=self.sampler_budget)

    def verify(self, world: "World", request: SampleRequest, candidate: Placement,
               rng: np.random.Generator) -> Optional[Placement]:
        feasible = placement_configurations(world, candidate, rng, self.sampler_budget) is not None
        return candidate if feasible else None


def propose_placements(world: "World", obj: str, support: str, rng: np.random.Generator, max_draws: int,
                       up_cos: float = 0.85, budget: SamplerBudget = SamplerBudget()) -> Iterator[Placement]:
    """Poses of the held `obj` resting on `support`'s upward faces that sink into nothing
    (no IK); examines at most `max_draws` (surface point, facet, twist) draws."""
    if world.attachment is None or world.attachment.name != obj:
        raise ValueError(f"placing '{obj}' requires holding it")
    body = world.bodies[obj]
    facets, vertices = resting_facets(body.urdf, body.scale, tuple(float(v) for v in body.inertial[0]))
    if not facets:
        return
    weights = np.array([f[2] for f in facets])
    weights /= weights.sum()
    surface, surface_at, holders = None, None, []
    for _ in range(max_draws):
        if world.pose(support) != surface_at:  # the caller may move things between yields
            surface_at = world.pose(support)
            surface = up_surface(world, support, up_cos)
            holders = fixed_holders(world, support)
        if surface is None:
            return
        points, normals = sample_surface(surface, 1, rng)
        point, support_normal = points[0], normals[0]
        normal, centre, _ = facets[int(rng.choice(len(facets), p=weights))]
        matrix = object_pose(normal, centre, vertices, point, support_normal, rng.uniform(-np.pi, np.pi))
        # The only check of the object against the support itself (a point on a bowl's floor
        # by its wall would otherwise put the object in the wall).
        with world.saved():
            pose = rest_on_relief(world, obj, support, matrix_pose(matrix), float(point[2]), holders, budget)
        if pose is None:
            continue
        yield Placement(obj, support, pose, tuple(float(v) for v in support_normal))


def sample_placements(world: "World", obj: str, support: str, rng: np.random.Generator,
                      max_attempts: Optional[int] = None, deadline: float = float("inf"),
                      budget: SamplerBudget = SamplerBudget()) -> Iterator[Placement]:
    """Collision-free, reachable placements of the held `obj` on `support`'s upward faces;
    stops after `max_attempts` proposals (default `budget.sample_attempts`) or at
    `deadline` (time.perf_counter())."""
    request = SampleRequest("sample-placement", (obj, support), ("?x", "?s"), deadline=deadline)
    limit = budget.sample_attempts if max_attempts is None else max_attempts
    return PlacementSampler(budget).draw(world, request, rng, budget=limit)
