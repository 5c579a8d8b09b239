"""After a push the hand backs out of wherever the push took it before it lifts: a stick
poked through a tunnel comes back out the way it went in, instead of being lifted into
the roof (which jams it and leaves the arm in collision for the next motion)."""
import numpy as np
import pytest

from pdsketch_mech.envs.demos.motion import Driver
from pdsketch_mech.envs.demos.poking import grasp_end, poke
from pdsketch_mech.envs.demos.run import demo_instance
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.operators.basis import BACK, LIFT, OUT_BEYOND, UP
from pdsketch_mech.operators.execution import back_out, move_straight
from pdsketch_mech.world.build import build_world
from pdsketch_mech.world.collision import CollisionChecker
from pdsketch_mech.world.motion import cartesian_path, path_collision


@pytest.fixture(scope="module")
def poked():
    """The canonical Poking scene with the stick held and pushed through the tunnel."""
    instance = demo_instance("poking")
    with build_world(parse_text(instance.problem_text())) as world:
        world.settle()
        driver = Driver(world)
        grasp_end(world, instance, driver, "tool")
        axis, travel = poke(world, instance, driver)
        yield world, np.array([axis[0], axis[1], 0.0]), travel, world.snapshot()


def lift_hits(world):
    path = cartesian_path(world, world.arm(), UP, LIFT, np.random.default_rng(0))
    return path is None or path_collision(world, path) is not None


def test_a_short_retreat_leaves_the_poked_stick_under_the_tunnel_roof(poked):
    world, axis, travel, snapshot = poked
    world.restore(snapshot)
    back_out(world, -axis, BACK, BACK, UP, LIFT)     # no further than the fixed back-off
    assert lift_hits(world)


def test_the_retreat_backs_the_stick_out_of_the_tunnel_and_the_lift_is_clear(poked):
    world, axis, travel, snapshot = poked
    world.restore(snapshot)
    start = np.asarray(world.tcp_pose()[0])
    back_out(world, -axis, BACK, travel + OUT_BEYOND, UP, LIFT)
    backed = float(np.dot(start - np.asarray(world.tcp_pose()[0]), axis))
    assert BACK + 0.01 < backed <= travel + OUT_BEYOND + 0.01
    assert not lift_hits(world)
    move_straight(world, UP, LIFT, "lift")
    assert not CollisionChecker(world).collides(world.arm())


def test_a_stick_pressed_on_the_table_in_the_tunnel_still_backs_out_before_the_lift(poked):
    """A tool pushed along the table touches it where every lift starts; that contact must
    not make every lift look blocked (the retreat then stopped at BACK, inside the tunnel,
    and the lift jammed the stick against the roof)."""
    world, axis, travel, snapshot = poked
    world.restore(snapshot)
    move_straight(world, (0.0, 0.0, -1.0), 0.02, "lower")   # press the stick onto the table
    assert "table" in CollisionChecker(world).colliding_bodies(world.arm())
    start = np.asarray(world.tcp_pose()[0])
    back_out(world, -axis, BACK, travel + OUT_BEYOND, UP, LIFT)
    backed = float(np.dot(start - np.asarray(world.tcp_pose()[0]), axis))
    assert backed > BACK + 0.01
    move_straight(world, UP, LIFT, "lift")
    assert not CollisionChecker(world).collides(world.arm())
