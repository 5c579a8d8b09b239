"""Grasps on overhangs: a flat object pushed 4-6 cm over a table edge the robot can reach
gets a valid, collision-free pinch grasp within 50 proposals of the generic sampler."""
import itertools

import numpy as np
import pytest

from pdsketch_mech.lang.scene import SceneObject
from pdsketch_mech.samplers.grasp import POINTS_PER_ATTEMPT, propose_grasps, verify_grasp
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
            propose_grasps(world, "thing", rng, POINTS_PER_ATTEMPT * limit), limit), 1):
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
