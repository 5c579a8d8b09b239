"""A held object moves rigidly with the hand: after grasp + lift + a 90-degree wrist turn,
all simulated with physics, the object sits at the sampled grasp (every asset the gripper can
hold lying flat; the grasp sampler finds none of the others); a grasp whose fingers miss the
object is not a grasp."""
import itertools
import json
import os
import re

import numpy as np
import pytest

from pdsketch_mech.lang.scene import SceneObject
from pdsketch_mech.operators import basis
from pdsketch_mech.operators.execution import follow_dynamic
from pdsketch_mech.samplers.grasp import sample_grasps
from pdsketch_mech.samplers.trajectory import grasp_motion
from pdsketch_mech.world.values import Grasp
from pdsketch_mech.world.asset_index import assets_root, resolve_asset
from pdsketch_mech.world.attachment import relative_pose
from pdsketch_mech.world.contacts import read_contacts
from pdsketch_mech.world.world import World

ASSETS = assets_root()
MANIFEST = json.load(open(os.path.join(ASSETS, "manifest.json")))


def movable_assets():
    return [f"{cat}/{i}" for cat, entry in MANIFEST["categories"].items() if not entry["fixed"]
            for i in range(len(entry["variants"]))]


# Lying flat, these are out of the gripper's range: wider than its 7.5 cm grasp (bricks,
# calculators 0, 2 and 4), or too low to pinch with the fingertips grasp.SUPPORT_CLEARANCE above
# the table (documents, 9 mm calipers, a plate's 6 mm floor and 1.2-1.8 cm rim, calculator 3's
# wedge, 8 mm at its front). Plates, documents and calipers are grasped once pushed over an edge.
OUT_OF_RANGE_LYING_FLAT = {f"{cat}/{i}" for cat in ("brick", "plate", "document", "caliper") for i in range(5)} \
    | {"calculator/0", "calculator/2", "calculator/3", "calculator/4"}
# Assets the gripper can hold lying flat but the grasp sampler finds no grasp of. banana/1
# (3.0 cm tall): a level top-down pinch across its middle verifies and holds through the lift
# and the turn, its fingertips 8.8 mm above the table; but the faces of its capsules' low-poly
# cross-section lean about 15 degrees at the sides, so every antipodal pair of its mesh closes
# about 11 degrees off level, and with the fingers open 2 cm wider than the banana the lower
# fingertip of every frame the sampler builds ends at most 4.9 mm above the table (5 needed).
MISSED_GRASPS = {"banana/1": "every antipodal pair closes ~11 deg off level: the lower fingertip "
                             "ends under grasp.SUPPORT_CLEARANCE above the table"}


class NoGraspFound(AssertionError):
    """The grasp sampler found no grasp of an asset the gripper can hold."""


def graspable_assets():
    """The movable assets in the gripper's range lying flat; those whose grasps the sampler
    misses are expected to fail, strictly: a sampler that finds them must say so here."""
    return [pytest.param(asset, marks=pytest.mark.xfail(strict=True, raises=NoGraspFound, reason=MISSED_GRASPS[asset]))
            if asset in MISSED_GRASPS else asset
            for asset in movable_assets() if asset not in OUT_OF_RANGE_LYING_FLAT]


def object_world(asset):
    world = World()
    world.add_object(SceneObject("table", "table", (0.6, 0, 0), fixed=True), resolve_asset("table", ASSETS))
    world.add_object(SceneObject("thing", asset, (0.5, 0.0, 0.5)), resolve_asset(asset, ASSETS))
    world.rest_on("thing", "table", (0.5, 0.0))
    world.settle(max_steps=600)
    return world


def grasp_error(world, grasp):
    """Position (m) and angle (rad) between where the gripper is on the object and the grasp."""
    actual = relative_pose(world.pose(grasp.object), world.tcp_pose())
    offset = float(np.linalg.norm(np.subtract(actual[0], grasp.in_object[0])))
    angle = 2 * float(np.arccos(min(1.0, abs(float(np.dot(actual[1], grasp.in_object[1]))))))
    return offset, angle


def grasp_and_lift(world, grasps, rng):
    """The first of `grasps` that executes (approach, close, lift), and the state after it."""
    for grasp in grasps:
        trajectory = grasp_motion(world, "thing", grasp, rng)
        if trajectory is None:
            continue
        with world.saved():
            if basis.grasp(world, "thing", grasp, trajectory).ok:
                return grasp, world.snapshot()
    return None


def turn_wrist(world, angle):
    q = world.arm()
    limits = world.kinematics.limits
    target = q[6] + angle if q[6] + angle <= limits.upper[6] else q[6] - angle
    path = [np.concatenate([q[:6], [q[6] + (target - q[6]) * t]]) for t in np.linspace(0, 1, 16)]
    follow_dynamic(world, path, "wrist turn")


@pytest.mark.parametrize("asset", sorted(OUT_OF_RANGE_LYING_FLAT))
def test_no_grasp_is_sampled_of_an_asset_lying_flat_out_of_the_grippers_range(asset):
    with object_world(asset) as world:
        grasp = next(sample_grasps(world, "thing", np.random.default_rng(0)), None)
        assert grasp is None, f"a grasp of {asset} lying flat: {grasp}"


@pytest.mark.parametrize("asset", graspable_assets())
def test_held_object_stays_at_the_sampled_grasp_through_lift_and_wrist_turn(asset):
    rng = np.random.default_rng(0)
    with object_world(asset) as world:
        grasps = list(itertools.islice(sample_grasps(world, "thing", rng), 12))
        if not grasps:
            raise NoGraspFound(f"the grasp sampler finds no grasp of {asset} lying flat")
        found = grasp_and_lift(world, grasps, rng)
        assert found is not None, f"none of {len(grasps)} sampled grasps of {asset} executes"
        grasp, lifted = found
        world.restore(lifted)
        assert read_contacts(world).holding == "thing"
        offset, angle = grasp_error(world, grasp)
        assert offset < 0.003 and np.degrees(angle) < 3, f"after the lift: {offset * 1000:.1f} mm, " \
                                                          f"{np.degrees(angle):.1f} deg"
        turn_wrist(world, np.pi / 2)
        world.step(120)
        offset, angle = grasp_error(world, grasp)
        assert offset < 0.003 and np.degrees(angle) < 3, f"after the turn: {offset * 1000:.1f} mm, " \
                                                          f"{np.degrees(angle):.1f} deg"
        assert world.pose("thing")[0][2] > 0.05  # off the table, not dragging on it


def shifted(grasp, dx):
    position = (grasp.in_object[0][0] + dx,) + tuple(grasp.in_object[0][1:])
    return Grasp(grasp.object, (position, grasp.in_object[1]), grasp.width, grasp.points)


def test_fingers_that_close_on_nothing_do_not_make_a_grasp():
    rng = np.random.default_rng(1)
    with object_world("block/0") as world:
        for grasp in sample_grasps(world, "thing", rng):
            beside = shifted(grasp, 0.12)  # the gripper frame 12 cm off the block: fingers on air
            trajectory = grasp_motion(world, "thing", beside, rng)
            if trajectory is not None:
                break
        outcome = basis.grasp(world, "thing", beside, trajectory)
        assert not outcome.ok and outcome.reason == "neither finger touches thing when closed"


def test_a_grasp_executed_far_from_the_stored_grasp_is_refused():
    rng = np.random.default_rng(2)
    with object_world("block/0") as world:
        grasp = next(sample_grasps(world, "thing", rng))
        trajectory = grasp_motion(world, "thing", grasp, rng)
        outcome = basis.grasp(world, "thing", shifted(grasp, 0.02), trajectory)
        assert not outcome.ok and re.match(r"the hand is (19|20)\.\d mm and 0\.\d deg from the grasp of thing",
                                           outcome.reason), outcome.reason
        assert world.attachment is None
