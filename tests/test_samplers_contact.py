"""The generic object-contact sampler: bare-gripper pushes and held-tool contacts (hooks)."""
import itertools

import numpy as np
import pybullet as p
from scipy.spatial.transform import Rotation

from pdsketch_mech.lang.scene import SceneObject
from pdsketch_mech.samplers.contact import CLOSED, sample_contacts
from pdsketch_mech.world.asset_index import assets_root, resolve_asset
from pdsketch_mech.world.collision import CollisionChecker
from pdsketch_mech.world.robot import FINGER_JOINTS
from pdsketch_mech.world.world import World

ASSETS = assets_root()
DOWN = tuple(Rotation.from_euler("xyz", [np.pi, 0, 0]).as_quat())
GAP = 0.01


def table_world(*objects, far_table=False):
    """The table top at z = 0 (a second one beyond it with `far_table`), `objects` ((name,
    asset, x, y, support), ...) resting on their supports, settled."""
    world = World()
    world.add_object(SceneObject("table", "table", (0.6, 0, 0), fixed=True), resolve_asset("table", ASSETS))
    if far_table:
        world.add_object(SceneObject("far", "table", (1.6, 0, 0), fixed=True), resolve_asset("table", ASSETS))
    for name, asset, x, y, support in objects:
        world.add_object(SceneObject(name, asset, (x, y, 0.5)), resolve_asset(asset, ASSETS))
        world.rest_on(name, support, (x, y))
    world.settle()
    return world


def hook_world(box_xy=(0.72, 0.05)):
    """An l-stick held top-down by its handle 10 cm behind its origin, lifted 8 cm; a box."""
    world = table_world(("hook", "l-stick/0", 0.45, 0.15, "table"), ("box", "box/0", *box_xy, "table"))
    rng = np.random.default_rng(0)
    hook = world.pose("hook")[0]
    handle = np.array([hook[0] - 0.1, hook[1] - 0.008, hook[2] + 0.004])  # the handle's centre line
    q = world.kinematics.ik(handle, DOWN, rng)
    world.set_arm(q)
    world.set_fingers(0.01)
    world.attach("hook")
    world.set_arm(world.kinematics.ik(handle + [0, 0, 0.08], DOWN, rng, seed=q))
    return world


def min_distance(world, a, b, **links):
    points = p.getClosestPoints(a, b, 0.2, physicsClientId=world.client, **links)
    return min(c[8] for c in points) if points else np.inf


def state(world):
    return {n: world.pose(n) for n in world.bodies}, tuple(world.arm()), world.finger_target


def test_bare_gripper_pushes_the_side_of_a_block():
    rng = np.random.default_rng(0)
    with table_world(("block", "block/0", 0.5, 0.1, "table")) as world:
        block = world.bodies["block"].id
        before = state(world)
        contacts = list(itertools.islice(sample_contacts(world, "block", "table", rng, gap=GAP), 5))
        assert len(contacts) == 5 and state(world) == before  # the world is left as found
        for c in contacts:
            n2, d = np.array(c.normal), np.array(c.direction)
            assert c.pusher is None and abs(n2[2]) < 0.2
            expected = -(n2 - n2[2] * np.array([0, 0, 1]))
            assert abs(d[2]) < 1e-3 and np.allclose(d, expected / np.linalg.norm(expected), atol=1e-3)
            with world.saved():
                world.set_fingers(CLOSED)
                q = world.kinematics.ik(*c.pusher_pose, rng)
                assert q is not None
                world.set_arm(q)
                assert min_distance(world, world.robot, block) >= -0.001  # nothing penetrates the block
                fingers = min(min_distance(world, world.robot, block, linkIndexA=f) for f in FINGER_JOINTS)
                assert fingers <= GAP + 0.01
                lo, hi = zip(*(p.getAABB(world.robot, f, physicsClientId=world.client) for f in FINGER_JOINTS))
                box_lo, box_hi = np.min(lo, axis=0), np.max(hi, axis=0)
                outside = np.maximum(0, np.maximum(box_lo - c.point, np.array(c.point) - box_hi))
                assert np.linalg.norm(outside) <= GAP + 0.01  # the fingers are at the contact point
                pre = np.array(c.pusher_pose[0]) - 0.05 * d  # backed off along n2
                q_pre = world.kinematics.ik(pre, c.pusher_pose[1], rng, seed=q)
                assert q_pre is not None and not CollisionChecker(world).collides(q_pre)


def test_bare_gripper_pushes_a_flat_plate_without_touching_the_table():
    rng = np.random.default_rng(1)
    with table_world(("plate", "plate/0", 0.5, 0.0, "table")) as world:
        c = next(sample_contacts(world, "plate", "table", rng, gap=GAP))
        with world.saved():
            world.set_fingers(CLOSED)
            q = world.kinematics.ik(*c.pusher_pose, rng)
            world.set_arm(q)
            assert min_distance(world, world.robot, world.bodies["table"].id) > 0.0


def test_held_hook_touches_the_box_without_penetrating_anything():
    rng = np.random.default_rng(0)
    with hook_world() as world:
        hook, box, table = (world.bodies[n].id for n in ("hook", "box", "table"))
        before = state(world)
        contacts = list(itertools.islice(sample_contacts(world, "box", "table", rng, gap=GAP), 5))
        assert len(contacts) == 5 and state(world) == before
        tcp_in_hook = world.held_tcp_in_object()
        for c in contacts:
            assert c.pusher == "hook" and abs(c.normal[2]) < 0.2
            with world.saved():
                world.set_pose("hook", c.pusher_pose)
                assert -0.001 <= min_distance(world, hook, box) <= GAP + 0.002
                assert min_distance(world, hook, table) >= -0.001
                gripper = p.multiplyTransforms(*c.pusher_pose, *tcp_in_hook)
                assert world.kinematics.ik(gripper[0], gripper[1], rng) is not None


def test_a_hook_can_pull_a_far_box_toward_the_robot():
    with hook_world((0.72, 0.05)) as world:
        box_xy = np.array(world.pose("box")[0][:2])
        toward_base = -box_xy / np.linalg.norm(box_xy)
        pulls = (c for c in sample_contacts(world, "box", "table", np.random.default_rng(0), max_attempts=600)
                 if np.dot(c.direction[:2], toward_base) > 0.7)
        pull = next(pulls, None)
        assert pull is not None
        assert np.dot(pull.direction[:2], box_xy) < 0
        assert np.dot(pull.point[:2], -toward_base) > np.dot(box_xy, -toward_base)  # on the box's far side


def test_same_seed_gives_the_same_first_contact():
    # From the same (restored) state: a sampler's own checks may leave float noise behind.
    for make, target in ((lambda: table_world(("block", "block/0", 0.5, 0.1, "table")), "block"),
                         (hook_world, "box")):
        with make() as world:
            start = world.snapshot()
            world.restore(start)
            first = next(sample_contacts(world, target, "table", np.random.default_rng(7)))
            world.restore(start)
            again = next(sample_contacts(world, target, "table", np.random.default_rng(7)))
            assert first == again


def test_an_unreachable_target_yields_nothing():
    with table_world(("box", "box/0", 1.4, 0.0, "far"), far_table=True) as world:
        assert list(sample_contacts(world, "box", "far", np.random.default_rng(0), max_attempts=200)) == []
    with hook_world((0.72, 0.05)) as world:
        world.add_object(SceneObject("far-table", "table", (1.6, 0, 0), fixed=True), resolve_asset("table", ASSETS))
        world.set_pose("box", ((1.45, 0.0, 0.3), (0, 0, 0, 1)))
        world.rest_on("box", "far-table")
        assert list(sample_contacts(world, "box", "far-table", np.random.default_rng(0), max_attempts=200)) == []
