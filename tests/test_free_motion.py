"""Contact motions simulate only where something can happen: the free tail of a path (every
waypoint from there on clear of everything, nothing moving) is teleported along, and fingers
that close or open in free space are set. What touches or moves, and every waypoint before a
contact, is still simulated, waypoint by waypoint, as before."""
import numpy as np
import pybullet as p
from scipy.spatial.transform import Rotation

from pdsketch_mech.lang.scene import SceneObject
from pdsketch_mech.operators.execution import (SETTLE_AFTER_MOTION, STEPS_PER_WAYPOINT, move_straight,
                                               set_fingers_dynamic)
from pdsketch_mech.world.asset_index import assets_root, resolve_asset
from pdsketch_mech.world.robot import CLOSED, MAX_OPENING
from pdsketch_mech.world.world import World

DOWN = tuple(Rotation.from_euler("xyz", [np.pi, 0, 0]).as_quat())
UP = (0.0, 0.0, 1.0)


def world_with_block(x: float = 0.5, y: float = 0.0) -> World:
    """The table top at z = 0, a block resting on it at (x, y)."""
    assets = assets_root()
    world = World()
    world.add_object(SceneObject("table", "table", (0.6, 0, 0), fixed=True), resolve_asset("table", assets))
    world.add_object(SceneObject("block", "block/0", (x, y, 0.5)), resolve_asset("block/0", assets))
    world.rest_on("block", "table", (x, y))
    world.settle()
    return world


def hand_at(world: World, position) -> None:
    world.set_arm(world.kinematics.ik(position, DOWN, np.random.default_rng(0)))


def test_a_lift_in_free_space_with_nothing_moving_is_teleported_and_ends_straight_above():
    with world_with_block() as world:
        hand_at(world, (0.4, -0.25, 0.3))
        start, steps = np.asarray(world.tcp_pose()[0]), world.sim_steps
        move_straight(world, UP, 0.1, "lift")
        assert world.sim_steps == steps
        assert np.allclose(np.asarray(world.tcp_pose()[0]) - start, (0, 0, 0.1), atol=3e-3)


def test_a_lift_while_an_object_slides_is_simulated_waypoint_by_waypoint():
    with world_with_block() as world:
        hand_at(world, (0.4, -0.25, 0.3))
        p.resetBaseVelocity(world.bodies["block"].id, (0.3, 0, 0), (0, 0, 0), physicsClientId=world.client)
        steps = world.sim_steps
        move_straight(world, UP, 0.05, "lift")
        assert world.sim_steps - steps >= 5 * STEPS_PER_WAYPOINT   # the sliding block's time passes


def test_a_lift_from_the_table_is_simulated_until_the_hand_is_clear():
    """The open fingers start around the block (nothing moves, but they are close): the first
    centimetres are simulated, the rest teleported once the hand is CLEARANCE away."""
    with world_with_block() as world:
        lo, hi = world.aabb("block")
        top = hi[2]
        world.set_fingers((hi[0] - lo[0]) / 2 + 0.003)      # 3 mm either side: a cube
        hand_at(world, (0.5, 0.0, top - 0.01))
        steps = world.sim_steps
        move_straight(world, UP, 0.1, "lift")
        simulated = world.sim_steps - steps
        assert STEPS_PER_WAYPOINT <= simulated < 10 * STEPS_PER_WAYPOINT + SETTLE_AFTER_MOTION
        assert np.asarray(world.tcp_pose()[0])[2] > top - 0.01 + 0.1 - 3e-3


def test_a_descent_that_ends_near_an_object_is_simulated_all_the_way():
    """Its last waypoints are near the block, so it has no free tail: a push's approach
    reaches its contact at the speed it always did."""
    with world_with_block() as world:
        top = world.aabb("block")[1][2]
        world.set_fingers(0.0)
        hand_at(world, (0.5, 0.0, top + 0.06))
        steps = world.sim_steps
        move_straight(world, (0.0, 0.0, -1.0), 0.05, "descent")
        assert world.sim_steps - steps == 6 * STEPS_PER_WAYPOINT + SETTLE_AFTER_MOTION   # the start, 5 cm in 1 cm


def test_fingers_closing_in_free_space_are_set_and_closing_on_an_object_is_simulated():
    with world_with_block() as world:
        hand_at(world, (0.4, -0.25, 0.3))
        world.set_fingers(MAX_OPENING / 2)
        steps = world.sim_steps
        set_fingers_dynamic(world, CLOSED)
        assert world.sim_steps == steps
        assert np.allclose(world.finger_target, CLOSED)
        world.set_fingers(MAX_OPENING / 2)
        lo, hi = world.aabb("block")
        hand_at(world, (0.5, 0.0, hi[2] - 0.01))            # the block between the open fingers
        world.attach("block")
        steps = world.sim_steps
        set_fingers_dynamic(world, CLOSED)
        assert world.sim_steps - steps >= 10                 # they close on it, with physics
