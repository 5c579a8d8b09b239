"""Grasps on overhangs: a flat object pushed 4-6 cm over a table edge the robot can reach
gets a valid, collision-free pinch grasp within 50 proposals of the generic sampler."""
import itertools

import numpy as np
import pytest

from pdsketch_mech.lang.scene import SceneObject
from pdsketch_mech.samplers.budget import SamplerBudget
from pdsketch_mech.samplers.grasp import propose_grasps, verify_grasp
from pdsketch_mech.world.asset_index import assets_root, resolve_asset
from pdsketch_mech.world.world import World

ASSETS = assets_root()


def overhanging(asset, overhang, y=0.0, table_x=0.75):
    """`asset` lying flat, its long side across the table's near edge (25 cm in front of the
    robot: within reach from below), overhanging by `overhang` metres."""
    world = World()
    world.add_object(SceneObject("table", "table", (table_x, 0, 0), fixed=True), resolve_asset("table", ASSETS))
    world.add_object(SceneObject("thing", asset, (0.5, y, 0.5)), resolve_asset(asset, ASSETS))
    world.rest_on("thing", "table", (0.5, y))
    lo, hi = world.aabb("thing")
    yaw = 0.0 if hi[0] - lo[0] > hi[1] - lo[1] else np.pi / 2
    world.rest_on("thing", "table", (0.5, y), yaw=yaw)
    edge = world.aabb("table")[0][0]
    shift = edge - overhang - world.aabb("thing")[0][0]   # its near side `overhang` past the edge
    world.rest_on("thing", "table", (world.pose("thing")[0][0] + shift, y), yaw=yaw)
    world.settle(max_steps=300)
    return world


def proposals_until_valid(world, seed, limit=50):
    rng = np.random.default_rng(seed)
    for count, grasp in enumerate(itertools.islice(
            propose_grasps(world, "thing", rng, SamplerBudget().grasp_points_per_proposal * limit), limit), 1):
        if verify_grasp(world, grasp, rng):
            return count
    return None


@pytest.mark.parametrize("asset", ["plate/0", "calculator/0", "caliper/0", "document/0"])
@pytest.mark.parametrize("overhang,y", [(0.04, 0.0), (0.06, 0.25)])
def test_an_overhanging_flat_object_gets_a_pinch_grasp_within_50_proposals(asset, overhang, y):
    with overhanging(asset, overhang, y) as world:
        edge = world.aabb("table")[0][0]
        assert world.aabb("thing")[0][0] < edge - overhang + 0.005 and world.pose("thing")[0][2] > -0.01
        counts = [proposals_until_valid(world, seed) for seed in range(3)]
    assert all(c is not None for c in counts), counts


def test_the_same_objects_lying_inside_the_table_get_no_grasp():
    with overhanging("document/0", -0.2) as world:   # 20 cm inside the edge
        assert proposals_until_valid(world, 0) is None


def test_the_support_height_map_agrees_with_single_rays_and_casts_each_node_once():
    """The grasp sampler's support test (samplers/support_heights.py) answers a point from its
    nearest grid node: but for points within a node of an edge, it must say what a ray cast at
    the point itself says, and a point asked about twice costs no second ray."""
    import pybullet as p
    from pdsketch_mech.samplers.grasp import SUPPORT_CLEARANCE
    from pdsketch_mech.samplers.support_heights import START_ABOVE, SupportHeights
    with overhanging("plate/0", 0.05) as world:
        bottom = world.aabb("thing")[0][2]
        heights = SupportHeights(world, "thing", bottom, reach=0.15)
        rng = np.random.default_rng(0)
        lo, hi = world.aabb("thing")
        points = np.column_stack([rng.uniform(lo[0] - 0.1, hi[0] + 0.1, 400), rng.uniform(lo[1] - 0.1, hi[1] + 0.1, 400),
                                  bottom + rng.uniform(-0.03, SUPPORT_CLEARANCE, 400)])
        answers = heights.clear(points, SUPPORT_CLEARANCE)
        rays = heights.rays
        assert 0 < rays <= len(points)
        assert np.array_equal(heights.clear(points, SUPPORT_CLEARANCE), answers) and heights.rays == rays
        ignore = {world.bodies["thing"].id, world.robot, -1}
        starts = [[x, y, bottom + START_ABOVE] for x, y, _ in points]
        ends = [[x, y, z - SUPPORT_CLEARANCE] for x, y, z in points]
        single = np.array([hit[0] in ignore for hit in p.rayTestBatch(starts, ends, physicsClientId=world.client)])
        # Nearest-node answers differ only within a node of an edge (the table's, the plate's
        # outline and rim): a handful of 400 points, where a misplaced grid would get most wrong.
        assert np.mean(answers != single) <= 0.02
        assert answers.any() and not answers.all()   # both answers occur: past the edge and over the table


@pytest.mark.parametrize("asset,overhang", [("caliper/0", -0.2), ("caliper/0", 0.05), ("plate/0", 0.05)])
def test_the_fingers_tested_first_keep_exactly_the_frames_the_full_tests_keep(monkeypatch, asset, overhang):
    """The grasp sampler tests the fingers against the support before the costlier test against
    the object's own surface (a caliper lying flat fails there); every test only drops frames,
    so the frames kept must be the same as without that early test, lying flat or overhanging."""
    import pdsketch_mech.samplers.grasp as grasp
    from pdsketch_mech.samplers.geometry import body_mesh, pose_matrix
    from pdsketch_mech.samplers.support_heights import SupportHeights
    with overhanging(asset, overhang) as world:
        mesh = body_mesh(world, "thing")
        placed = pose_matrix(world.pose("thing"))
        pool = grasp.antipodal_pool(mesh)
        p1s, p2s = pool.pairs(np.arange(0, pool.size, 4))

        def frames():
            heights = SupportHeights(world, "thing", world.aabb("thing")[0][2], grasp._gripper_radius(grasp.MAX_OPENING))
            return grasp._approach_frames(world, mesh, placed, p1s, p2s, heights, np.random.default_rng(3))
        early = frames()
        monkeypatch.setattr(grasp, "_EARLY_SUPPORT_TESTS", (grasp._fingertip_points,))
        late = frames()
    assert len(early) == len(late) == len(p1s)
    assert all(np.array_equal(a, b) for a, b in zip(early, late))
    if overhang > 0:
        assert sum(len(a) for a in early) > 0   # an overhang keeps some: the comparison is not of empty sets
