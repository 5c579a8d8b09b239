"""The generic grasp and placement samplers: what they yield meets their definitions."""
import gc
import weakref

import numpy as np
import pytest
import pybullet as p
import trimesh
from scipy.spatial import Delaunay
from scipy.spatial.transform import Rotation

from pdsketch_mech.envs.tasks import LEDGE_HEIGHT
from pdsketch_mech.lang.scene import SceneObject
from pdsketch_mech.samplers.budget import SamplerBudget
from pdsketch_mech.samplers.mesh import Mesh
from pdsketch_mech.samplers.geometry import body_mesh, body_parts, pose_matrix, world_mesh
from pdsketch_mech.samplers.grasp import antipodal_pairs, sample_grasps, world_grasp_pose
from pdsketch_mech.samplers.placement import RISE, fixed_holders, rest_on_relief, sample_placements
from pdsketch_mech.world.asset_index import assets_root, resolve_asset
from pdsketch_mech.world.collision import CollisionChecker
from pdsketch_mech.world.robot import MAX_OPENING
from pdsketch_mech.world.world import World

ASSETS = assets_root()
DOWN = tuple(Rotation.from_euler("xyz", [np.pi, 0, 0]).as_quat())
COS15 = np.cos(np.radians(15))


def table_world(*objects, fixed=()):
    """Table top at z = 0, `objects` ((name, asset, x, y)) resting on it, `fixed` ((name,
    asset, (x, y, z))) bolted down where given."""
    world = World()
    world.add_object(SceneObject("table", "table", (0.6, 0, 0), fixed=True), resolve_asset("table", ASSETS))
    for name, asset, position in fixed:
        world.add_object(SceneObject(name, asset, position, fixed=True), resolve_asset(asset, ASSETS))
    for name, asset, x, y in objects:
        world.add_object(SceneObject(name, asset, (x, y, 0.5)), resolve_asset(asset, ASSETS))
        world.rest_on(name, "table", (x, y))
    return world


def hold(world, name, rng):
    """Grasp `name` top-down at its centre and lift it 15 cm."""
    centre = np.array(world.pose(name)[0])
    q = world.kinematics.ik(centre, DOWN, rng)
    world.set_arm(q)
    world.attach(name)
    world.set_arm(world.kinematics.ik(centre + [0, 0, 0.15], DOWN, rng, seed=q))


def record_ik(world):
    """Wrap the world's IK: the list gets (position, orientation, answer) of every call."""
    calls = []
    ik = world.kinematics.ik

    def recorded(position, orientation, *args, **kwargs):
        answer = ik(position, orientation, *args, **kwargs)
        calls.append((np.array(position, dtype=float), np.array(orientation, dtype=float), answer))
        return answer
    world.kinematics.ik = recorded
    return calls


def solution_for(calls, pose):
    """The sampler's recorded IK answer for `pose`."""
    for position, orientation, answer in calls:
        if answer is not None and np.allclose(position, pose[0], atol=1e-9) \
                and np.allclose(orientation, pose[1], atol=1e-9):
            return answer
    raise AssertionError(f"no IK solution was found for {pose}")


def tcp_at(world, q, pose):
    position, orientation = world.kinematics.fk(q)
    return (np.linalg.norm(np.subtract(position, pose[0])) < 0.005
            and (Rotation.from_quat(orientation) * Rotation.from_quat(pose[1]).inv()).magnitude() < 0.05)


def surface_normal(mesh, point):
    closest, distance, face = trimesh.proximity.closest_point(trimesh.Trimesh(mesh.vertices, mesh.faces), [point])
    return float(distance[0]), mesh.face_normals[face[0]]


def test_block_grasps_are_reachable_antipodal_pairs():
    rng = np.random.default_rng(0)
    with table_world(("block", "block/0", 0.5, 0.0)) as world:
        mesh = body_mesh(world, "block")
        rotation = pose_matrix(world.pose("block"))[:3, :3]
        calls = record_ik(world)
        grasps = [g for g, _ in zip(sample_grasps(world, "block", rng), range(3))]
        assert len(grasps) == 3
        for grasp in grasps:
            p1, p2 = np.array(grasp.points)
            d1, n1 = surface_normal(mesh, p1)
            d2, n2 = surface_normal(mesh, p2)
            assert d1 < 1e-3 and d2 < 1e-3
            assert np.dot(n1, n2) < -COS15
            assert abs(grasp.width - np.linalg.norm(p2 - p1)) < 1e-9 and 0.005 <= grasp.width <= 0.075
            frame = pose_matrix(grasp.in_object)
            assert np.allclose(frame[:3, 3], (p1 + p2) / 2, atol=1e-6)
            assert np.dot(frame[:3, 1], (p2 - p1) / grasp.width) > 0.9999   # y: the closing axis
            assert (rotation @ frame[:3, 2])[2] <= 0.3                        # not from below
            target = world_grasp_pose(world, grasp)
            pre = (tuple(pose_matrix(target)[:3, 3] - 0.08 * pose_matrix(target)[:3, 2]), target[1])
            q, q_pre = solution_for(calls, target), solution_for(calls, pre)
            assert tcp_at(world, q, target) and tcp_at(world, q_pre, pre)
            with world.saved():
                world.set_fingers(MAX_OPENING / 2)
                assert not CollisionChecker(world).collides(q) and not CollisionChecker(world).collides(q_pre)


def test_antipodal_pairs_of_a_two_part_hook_lie_on_its_outer_surface():
    # The hook's crook overlaps the end of its shaft: the faces there are inside the solid
    # and must neither be sampled nor stop a ray (a false 2 cm pair across the corner).
    with table_world(("hook", "l-stick/0", 0.5, 0.0)) as world:
        parts = body_parts(world, "hook").split(only_watertight=False)
        pairs = [pair for pair in antipodal_pairs(body_mesh(world, "hook"), 400, np.random.default_rng(5)) if pair]
        assert len(pairs) > 100
        points = np.array([point for p1, _, p2, _ in pairs for point in (p1, p2)])
        depth = np.max([trimesh.proximity.signed_distance(part, points) for part in parts], axis=0)
        assert np.all(depth < 1e-3)                                           # positive: inside a part
        assert all(0.005 <= np.linalg.norm(p2 - p1) <= 0.075 and np.dot(n1, n2) < -COS15
                   for p1, n1, p2, n2 in pairs)


def test_pairs_across_non_parallel_faces_are_not_antipodal():
    # A 4 cm long prism with a 30 degree apex: only its parallel end caps are antipodal.
    section = np.array([[0, 0], [0.03, 0], [0.03, 0.03 * np.tan(np.radians(30))]])
    hull = trimesh.Trimesh(np.concatenate([np.c_[section, np.zeros(3)], np.c_[section, np.full(3, 0.04)]])).convex_hull
    wedge = Mesh(hull.vertices, hull.faces, hull.facets)
    pairs = [pair for pair in antipodal_pairs(wedge, 400, np.random.default_rng(6)) if pair]
    assert pairs and all(abs(n1[2]) > 0.999 and abs(np.linalg.norm(p2 - p1) - 0.04) < 1e-6
                         for p1, n1, p2, _ in pairs)


def test_grasp_proposals_draw_antipodal_pairs_from_one_pool_per_shape():
    """Every proposal's points come from the shape's pool (grasp.antipodal_pool), wherever the
    object lies; a point's partner is found once, the first time a proposal draws it, and is
    the one a ray cast with all the pool's points at once finds."""
    import pdsketch_mech.samplers.grasp as grasp
    with table_world(("block", "block/0", 0.5, 0.0)) as world:
        mesh = body_mesh(world, "block")
        grasp._antipodal_pool.cache_clear()
        first = list(grasp.propose_grasps(world, "block", np.random.default_rng(0), 120))
        world.set_pose("block", ((0.45, 0.1, world.pose("block")[0][2]), world.pose("block")[1]))
        second = list(grasp.propose_grasps(world, "block", np.random.default_rng(1), 120))
        pool = grasp.antipodal_pool(mesh)
        assert first and second and 0 < pool.rays <= 240  # not the whole pool
        pooled = {tuple(np.round(p, 9)) for p in pool.p1[pool.has_pair]}
        assert all(tuple(np.round(g.points[0], 9)) in pooled for g in first + second)
        rays = pool.rays
        drawn = np.flatnonzero(pool.known)
        pool.pairs(drawn)
        assert pool.rays == rays  # known points cast no ray again
        assert pool.size == SamplerBudget().grasp_pool_points
        eager = list(grasp.antipodal_pairs(mesh, pool.size, np.random.default_rng(0)))
        p1s, p2s = pool.pairs(np.arange(pool.size))
        expected = [pair for pair in eager if pair is not None]
        assert len(p1s) == len(expected) > 0
        assert np.array_equal(p1s, [pair[0] for pair in expected]) and np.array_equal(p2s, [pair[2] for pair in expected])


def test_grasp_proposals_in_one_scene_share_the_rays_cast_under_the_gripper():
    """A learned sampler fills its batch with several calls in one scene: the support heights
    the first call cast are the later calls' too, and give the same grasps as casting anew;
    once something moves they are cast again."""
    import pdsketch_mech.samplers.grasp as grasp
    with table_world(("plate", "plate/1", 0.5, 0.0), ("block", "block/0", 0.45, 0.25)) as world:
        first = list(grasp.propose_grasps(world, "block", np.random.default_rng(0), 120))
        (heights,) = [h for _, h in grasp._HEIGHTS[world].values()]
        rays = heights.rays
        again = list(grasp.propose_grasps(world, "block", np.random.default_rng(0), 120))
        assert rays > 0 and heights.rays == rays and first and again == first
        grasp._HEIGHTS[world].clear()
        assert list(grasp.propose_grasps(world, "block", np.random.default_rng(0), 120)) == first
        world.set_pose("block", ((0.4, 0.25, world.pose("block")[0][2]), world.pose("block")[1]))
        list(grasp.propose_grasps(world, "block", np.random.default_rng(0), 120))
        assert len(grasp._HEIGHTS[world]) == 2
    released = weakref.ref(world)   # what is kept per world does not keep the world alive
    del world, heights
    gc.collect()
    assert released() is None


def test_same_seed_gives_the_same_grasps():
    with table_world(("block", "block/0", 0.5, 0.0)) as world:
        runs = [[g for g, _ in zip(sample_grasps(world, "block", np.random.default_rng(7)), range(2))]
                for _ in range(2)]
        assert len(runs[0]) == 2 and runs[0] == runs[1]


def test_flat_plate_has_no_grasp_but_a_block_does():
    # The plate's antipodal pairs are through its 6 mm floor or its low rim: the fingers
    # would have to go under the plate, into the table.
    with table_world(("plate", "plate/0", 0.5, 0.0), ("block", "block/0", 0.45, 0.25)) as world:
        assert list(sample_grasps(world, "plate", np.random.default_rng(1), max_attempts=300)) == []
        assert next(sample_grasps(world, "block", np.random.default_rng(1), max_attempts=300), None) is not None


def penetration(world, a, b):
    points = p.getClosestPoints(world.bodies[a].id, world.bodies[b].id, 0.01, physicsClientId=world.client)
    return -min((c[8] for c in points), default=0.01)


@pytest.mark.parametrize("asset", ["block/0", "calculator/2"])  # a cube, and a wedge with no face opposite its slope
def test_placements_on_the_table_rest_on_a_face(asset):
    rng = np.random.default_rng(2)
    with table_world(("thing", asset, 0.5, 0.0)) as world:
        hold(world, "thing", rng)
        calls = record_ik(world)
        placements = [pl for pl, _ in zip(sample_placements(world, "thing", "table", rng), range(3))]
        assert len(placements) == 3
        for placement in placements:
            assert placement.support_normal == (0.0, 0.0, 1.0)
            tcp = p.multiplyTransforms(*placement.pose, *world.held_tcp_in_object())
            assert tcp_at(world, solution_for(calls, tcp), tcp)
            with world.saved():
                world.set_pose("thing", placement.pose)
                vertices = world_mesh(world, "thing").convex_hull.vertices
                assert 0.0 <= vertices[:, 2].min() <= 0.003
                assert penetration(world, "thing", "table") <= 0.001
                down = vertices[vertices[:, 2] < vertices[:, 2].min() + 0.001]   # a face down, not an edge
                spread = np.linalg.svd(down[:, :2] - down[:, :2].mean(axis=0), compute_uv=False)
                assert len(down) >= 3 and spread.min() > 0.002


def test_placements_rest_on_faces_the_object_does_not_tip_from():
    # Half of a banana's hull (its curved back) would roll it over: its centre of mass must
    # lie over the face it rests on.
    rng = np.random.default_rng(10)
    with table_world(("banana", "banana/0", 0.5, 0.0)) as world:
        hold(world, "banana", rng)
        com = np.array(world.bodies["banana"].inertial[0])
        placements = [pl for pl, _ in zip(sample_placements(world, "banana", "table", rng), range(4))]
        assert len(placements) == 4
        for placement in placements:
            matrix = pose_matrix(placement.pose)
            with world.saved():
                world.set_pose("banana", placement.pose)
                vertices = world_mesh(world, "banana").convex_hull.vertices
            down = vertices[vertices[:, 2] < vertices[:, 2].min() + 0.001][:, :2]
            assert Delaunay(down).find_simplex((matrix[:3, :3] @ com + matrix[:3, 3])[:2]) >= 0


def test_placements_in_a_bowl_do_not_sink_into_its_wall():
    rng = np.random.default_rng(8)
    with table_world(("block", "block/0", 0.45, -0.15), ("bowl", "bowl/0", 0.5, 0.15)) as world:
        hold(world, "block", rng)
        placements = list(sample_placements(world, "block", "bowl", rng, max_attempts=200))
        assert len(placements) >= 5
        for placement in placements:
            with world.saved():
                world.set_pose("block", placement.pose)
                assert penetration(world, "block", "bowl") <= 0.001


def test_a_box_too_long_for_a_plates_floor_may_rest_on_its_rim():
    # A 12 cm box fits the floor of a 22 cm plate only near its centre; a weight for a lever
    # must get further out, resting on the rim (tilted once released). Such placements are
    # raised clear of the plate; none sinks into it.
    rng = np.random.default_rng(3)
    with table_world(("box", "box/0", 0.45, -0.2), ("plate", "plate/0", 0.55, 0.1)) as world:
        hold(world, "box", rng)
        placements = list(sample_placements(world, "box", "plate", rng, max_attempts=300))
        assert len(placements) >= 10
        lowest = []
        for placement in placements:
            with world.saved():
                world.set_pose("box", placement.pose)
                assert penetration(world, "box", "plate") <= 0.001
                lowest.append(world_mesh(world, "box").vertices[:, 2].min())
        floor = min(lowest)
        assert any(z > floor + 0.004 for z in lowest)       # on the rim
        assert all(z < floor + RISE + 0.003 for z in lowest)


def test_relief_lifts_an_object_off_its_support_but_not_off_anything_else():
    rng = np.random.default_rng(4)
    with table_world(("box", "box/0", 0.45, -0.2), ("plate", "plate/0", 0.55, 0.1),
                     ("block", "block/0", 0.62, -0.12)) as world:
        hold(world, "box", rng)
        (x, y, z), quaternion = next(sample_placements(world, "box", "plate", rng)).pose
        with world.saved():
            raised = rest_on_relief(world, "box", "plate", ((x, y, z - 0.005), quaternion), z)  # 5 mm into the plate
            assert raised is not None and raised[0][2] >= z - 0.001
            world.set_pose("box", raised)
            assert penetration(world, "box", "plate") <= 0.001
            assert rest_on_relief(world, "box", "plate", ((0.62, -0.12, z), quaternion), z) is None  # in the block


def test_an_object_longer_than_a_cradled_plate_lies_across_the_cradle():
    # A 26 cm spoon on a 24 cm plate sunk in a fixed ledge: lying flat, its ends reach over
    # the ledge's wall and curb. The fixed body the plate rests on is relief, so the spoon is
    # raised onto it (without that, only placements standing the spoon on its end were left).
    rng = np.random.default_rng(5)
    with table_world(("spoon", "spoon/2", 0.4, -0.25), fixed=(("ledge", "ledge/2", (0.55, 0.1, 0.0)),)) as world:
        world.add_object(SceneObject("plate", "plate/2", (0.55, 0.1, 0.5)), resolve_asset("plate/2", ASSETS))
        world.set_pose("plate", ((0.55, 0.1, LEDGE_HEIGHT), (0.0, 0.0, 0.0, 1.0)))  # in the cradle
        hold(world, "spoon", rng)
        placements = list(sample_placements(world, "spoon", "plate", rng, max_attempts=150))
        lying = on_ledge = 0
        for placement in placements:
            with world.saved():
                world.set_pose("spoon", placement.pose)
                assert penetration(world, "spoon", "plate") <= 0.0015
                assert penetration(world, "spoon", "ledge") <= 0.0015
                long_axis = Rotation.from_quat(placement.pose[1]).apply([1.0, 0.0, 0.0])
                lying += abs(long_axis[2]) < 0.5
                on_ledge += penetration(world, "spoon", "ledge") > -0.002
        assert lying >= 20 and on_ledge >= 20


def test_only_the_fixed_bodies_a_support_rests_on_are_its_relief():
    # The plate's cradle may hold up a long object put on the plate; a slope bolted to the
    # table does not prop up an object put on the table. (The table holds the slope up, but
    # lies below every point of it: `rest_on_relief` takes a holder's parts above the point.)
    with table_world(fixed=(("ledge", "ledge/2", (0.55, 0.1, 0.0)), ("slope", "slope/2", (0.5, -0.3, 0.0)))) as world:
        world.add_object(SceneObject("plate", "plate/2", (0.55, 0.1, 0.5)), resolve_asset("plate/2", ASSETS))
        world.set_pose("plate", ((0.55, 0.1, LEDGE_HEIGHT), (0.0, 0.0, 0.0, 1.0)))
        assert fixed_holders(world, "plate") == ["ledge"]
        assert fixed_holders(world, "table") == []


def test_a_thin_sheet_held_at_its_centre_is_not_laid_flat():
    # The fingertips reach 7 mm past the gripper frame, below a 3 mm sheet: laid flat, they
    # would go into the table. On its edge, the hand is well clear of it.
    rng = np.random.default_rng(9)
    with table_world(("sheet", "document/0", 0.5, 0.0)) as world:
        hold(world, "sheet", rng)
        calls = record_ik(world)
        placements = [pl for pl, _ in zip(sample_placements(world, "sheet", "table", rng, max_attempts=150), range(2))]
        assert placements
        for placement in placements:
            assert abs(pose_matrix(placement.pose)[2, 2]) < 0.99
            q = solution_for(calls, p.multiplyTransforms(*placement.pose, *world.held_tcp_in_object()))
            with world.saved():
                assert not CollisionChecker(world, check_held=False).collides(q)


def test_placements_on_a_slope_follow_its_incline():
    rng = np.random.default_rng(3)
    with table_world(("block", "block/0", 0.45, -0.1), fixed=[("slope", "slope/1", (0.55, 0.2, 0.0))]) as world:
        hold(world, "block", rng)
        placements = [pl for pl, _ in zip(sample_placements(world, "block", "slope", rng), range(3))]
        assert len(placements) == 3
        for placement in placements:
            normal = np.array(placement.support_normal)
            assert abs(np.degrees(np.arccos(normal[2])) - 20.0) < 1.0
            with world.saved():
                world.set_pose("block", placement.pose)
                vertices = world_mesh(world, "block").vertices
                slope = world_mesh(world, "slope")
                facing = slope.face_normals @ normal > 0.9999   # the board's top and the wedge's under it
                top = np.max(slope.triangles_center[facing] @ normal)
                heights = vertices @ normal - top
                assert 0.0 <= heights.min() <= 0.003                          # lying on the incline
                assert np.sum(heights < 0.003) >= 4                           # on a whole face


def test_samplers_stop_after_max_attempts_when_nothing_is_reachable():
    with table_world(fixed=[("far", "slope/0", (1.5, 0.0, 0.0))]) as world:
        world.add_object(SceneObject("block", "block/0", (0.5, 0.0, 0.5)), resolve_asset("block/0", ASSETS))
        world.rest_on("block", "table", (0.5, 0.0))
        hold(world, "block", np.random.default_rng(4))
        calls = record_ik(world)
        assert list(sample_placements(world, "block", "far", np.random.default_rng(4), max_attempts=15)) == []
        assert calls == []  # the reach bound rejects every placement before any IK solve
        world.detach()
        world.add_object(SceneObject("far-block", "block/0", (1.5, 0.0, 0.2)), resolve_asset("block/0", ASSETS))
        world.rest_on("far-block", "far", (1.5, 0.0))
        calls.clear()
        assert list(sample_grasps(world, "far-block", np.random.default_rng(4), max_attempts=15)) == []
        assert calls == []  # the reach bound rejects every candidate before any IK solve
