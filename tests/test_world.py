"""The simulated world: scenes, kinematics, collisions, motion plans, contacts, physics, pictures."""
import json
import os

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdsketch_mech.lang.loader import load_problem
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.lang.scene import SceneObject
from pdsketch_mech.world.asset_index import assets_root, resolve_asset
from pdsketch_mech.world.build import build_world
from pdsketch_mech.world.collision import CollisionChecker
from pdsketch_mech.world.contacts import pair_normal_z, read_contacts
from pdsketch_mech.world.motion import cartesian_path, path_is_free, plan_motion
from pdsketch_mech.world.render import Camera, View, render, save_gif, save_png, scene_camera
from pdsketch_mech.lang.errors import PddlError
from pdsketch_mech.world.world import World

from conftest import ROOT

ASSETS = assets_root()
DOWN = tuple(Rotation.from_euler("xyz", [np.pi, 0, 0]).as_quat())


def table_world(*objects):
    """A world with the table top at z = 0 and `objects` ((name, asset, x, y), ...) resting on it."""
    world = World()
    world.add_object(SceneObject("table", "table", (0.6, 0, 0), fixed=True), resolve_asset("table", ASSETS))
    for name, asset, x, y in objects:
        world.add_object(SceneObject(name, asset, (x, y, 0.5)), resolve_asset(asset, ASSETS))
        world.rest_on(name, "table", (x, y))
    return world


def moved(before, after):
    return float(np.linalg.norm(np.subtract(before[0], after[0])))


def test_hook_problem_scene_loads():
    _, problem = load_problem(os.path.join(ROOT, "problems", "hook-use.pddl"))
    with build_world(problem) as world:
        assert set(world.bodies) == {"table", "hook", "box"}
        assert world.bodies["table"].fixed and not world.bodies["box"].fixed
        assert np.allclose(world.pose("hook")[0], (0.5, 0.15, 0.011), atol=1e-6)


def test_two_worlds_are_independent():
    with table_world(("a", "block/0", 0.5, 0.0)) as first, table_world(("a", "block/0", 0.5, 0.0)) as second:
        assert first.client != second.client
        first.set_pose("a", ((0.3, 0.3, 0.5), (0, 0, 0, 1)))
        assert np.allclose(second.pose("a")[0][:2], (0.5, 0.0), atol=1e-6)


def movable_assets():
    manifest = json.load(open(os.path.join(ASSETS, "manifest.json")))
    return [f"{cat}/{i}" for cat, entry in manifest["categories"].items() if not entry["fixed"]
            for i in range(len(entry["variants"]))]


@pytest.mark.slow
@pytest.mark.parametrize("asset", movable_assets())
def test_every_asset_rests_stably_on_the_table(asset):
    with table_world(("thing", asset, 0.5, 0.0)) as world:
        world.settle(max_steps=600)
        before = world.pose("thing")
        world.settle(max_steps=240)
        assert moved(before, world.pose("thing")) < 0.005
        assert ("thing", "table") in read_contacts(world).support


def test_snapshot_restore_is_exact():
    with table_world(("a", "block/0", 0.5, 0.0), ("b", "box/0", 0.5, 0.2)) as world:
        world.settle()
        snapshot = world.snapshot()
        poses = {n: world.pose(n) for n in world.bodies}
        arm = world.arm()
        world.set_arm(world.kinematics.limits.sample(np.random.default_rng(1)))
        world.set_pose("a", ((0.2, -0.2, 0.3), (0, 0, 0, 1)))
        world.step(50)
        world.restore(snapshot)
        assert all(world.pose(n) == poses[n] for n in world.bodies)
        assert np.array_equal(world.arm(), arm)
        with world.saved():
            world.set_pose("b", ((0.1, 0.1, 0.4), (0, 0, 0, 1)))
        assert world.pose("b") == poses["b"]


def test_moved_since_tells_a_nudged_or_turned_object_from_one_left_where_it_was():
    with table_world(("box", "box/0", 0.5, 0.0)) as world:
        start = world.snapshot()
        world.step(20)                                   # resting: settling noise is not a move
        assert not world.moved_since(start, "box")
        position, orientation = world.pose("box")
        world.set_pose("box", ((position[0] + 0.01, position[1], position[2]), orientation))
        assert world.moved_since(start, "box")
        world.restore(start)
        turned = (Rotation.from_quat(orientation) * Rotation.from_euler("z", 5, degrees=True)).as_quat()
        world.set_pose("box", (position, tuple(turned)))
        assert world.moved_since(start, "box")
        world.restore(start)
        assert not world.moved_since(start, "box") and not world.moved_since(start, "table")


def test_ik_solutions_are_verified_by_forward_kinematics():
    rng = np.random.default_rng(0)
    with World() as world:
        kin = world.kinematics
        for _ in range(20):
            target = np.array([rng.uniform(0.3, 0.6), rng.uniform(-0.3, 0.3), rng.uniform(0.05, 0.3)])
            q = kin.ik(target, DOWN, rng)
            assert q is not None and kin.limits.contains(q)
            position, orientation = kin.fk(q)
            assert np.linalg.norm(np.subtract(position, target)) < 0.005
            assert (Rotation.from_quat(orientation) * Rotation.from_quat(DOWN).inv()).magnitude() < 0.05
        assert kin.ik([3.0, 0.0, 0.2], DOWN, rng) is None  # far out of reach


def test_motion_plan_is_collision_free_along_the_whole_path():
    rng = np.random.default_rng(2)
    with table_world(("wall", "brick/0", 0.5, 0.0)) as world:
        start = world.kinematics.ik([0.5, -0.2, 0.04], DOWN, rng)
        goal = world.kinematics.ik([0.5, 0.2, 0.04], DOWN, rng)
        result = plan_motion(world, start, goal, max_checks=40000)
        assert result.path is not None, result.reason
        assert np.allclose(result.path[0], start) and np.allclose(result.path[-1], goal)
        assert path_is_free(world, result.path, step=0.005)
        assert not path_is_free(world, np.array([start, goal]), step=0.005)  # the straight line hits the box


def test_a_detour_around_an_obstacle_is_shortcut_close_to_the_straight_line():
    # The RRT's raw path wanders; rope shortcutting pulls it taut. simplifySolution's paths
    # averaged 2.0x the straight line's length here, the shortcut ones 1.55x.
    ratios = []
    for seed in range(2, 6):
        rng = np.random.default_rng(2)
        with table_world(("wall", "brick/0", 0.5, 0.0)) as world:
            start = world.kinematics.ik([0.5, -0.2, 0.04], DOWN, rng)
            goal = world.kinematics.ik([0.5, 0.2, 0.04], DOWN, rng)
            result = plan_motion(world, start, goal, max_checks=40000, seed=seed)
            assert result.path is not None and path_is_free(world, result.path, step=0.005)
            length = np.sum(np.linalg.norm(np.diff(result.path, axis=0), axis=1))
            ratios.append(length / np.linalg.norm(goal - start))
    assert np.mean(ratios) < 1.75, ratios


def test_a_start_pressed_a_little_past_a_joint_limit_still_gets_a_path_from_where_it_is():
    rng = np.random.default_rng(2)
    with table_world(("wall", "brick/0", 0.5, 0.0)) as world:
        limits = world.kinematics.limits
        start = world.kinematics.ik([0.5, -0.2, 0.04], DOWN, rng)
        goal = world.kinematics.ik([0.5, 0.2, 0.04], DOWN, rng)
        start[6] = limits.upper[6] + 0.01          # the wrist, as a push with physics on can leave it
        result = plan_motion(world, start, goal, max_checks=40000)
        assert result.path is not None, result.reason
        assert np.array_equal(result.path[0], start) and limits.contains(result.path[-1])
        start[6] = limits.upper[6] + 0.1
        assert plan_motion(world, start, goal).reason == "start is outside the joint limits"


def test_motion_plan_reports_a_colliding_goal():
    rng = np.random.default_rng(3)
    with table_world(("wall", "box/0", 0.5, 0.0)) as world:
        start = world.kinematics.ik([0.5, -0.25, 0.15], DOWN, rng)
        inside = world.kinematics.ik(list(world.aabb("wall")[1] - [0.06, 0.06, 0.03]), DOWN, rng)
        result = plan_motion(world, start, inside)
        assert result.path is None and result.reason.startswith("goal configuration is in collision with")


def test_cartesian_path_moves_in_a_straight_line():
    rng = np.random.default_rng(4)
    with World() as world:
        start = world.kinematics.ik([0.45, 0.0, 0.2], DOWN, rng)
        path = cartesian_path(world, start, [0, 0, -1], 0.1, rng)
        assert path is not None
        points = np.array([world.kinematics.fk(q)[0] for q in path])
        assert np.allclose(points[:, :2], [0.45, 0.0], atol=0.006) and abs(points[-1, 2] - 0.1) < 0.006


def test_contact_graph_support_and_holding():
    with table_world(("base", "box/0", 0.5, 0.0), ("top", "block/0", 0.5, 0.2)) as world:
        world.rest_on("top", "base", (0.5, 0.0))
        world.settle()
        graph = read_contacts(world)
        assert graph.support == {("base", "table"), ("top", "base")}
        assert graph.holding is None and ("handempty",) in graph.facts()
        world.attach("top")
        graph = read_contacts(world)
        assert graph.holding == "top" and ("top", "base") not in graph.support


def test_held_object_follows_the_hand_and_is_checked_for_collisions():
    rng = np.random.default_rng(5)
    with table_world(("held", "block/0", 0.5, 0.0), ("other", "box/0", 0.5, 0.25)) as world:
        grasp = world.kinematics.ik(np.add(world.pose("held")[0], [0, 0, 0.01]), DOWN, rng)
        world.set_arm(grasp)
        world.attach("held")
        offset = np.subtract(world.pose("held")[0], world.hand_pose()[0])
        world.set_arm(world.kinematics.ik([0.4, -0.2, 0.25], DOWN, rng))
        assert np.allclose(np.subtract(world.pose("held")[0], world.hand_pose()[0]), offset, atol=1e-4)
        above_other = world.kinematics.ik(np.add(world.pose("other")[0], [0, 0, 0.045]), DOWN, rng)
        checker = CollisionChecker(world)
        with world.saved():
            assert checker.collides(above_other)           # the held block sinks into the box
            assert not CollisionChecker(world, ignore=["other"]).collides(above_other)


def test_collision_checks_give_the_same_answers_without_the_objects_own_contacts(monkeypatch):
    """A check computes only the arm's and the held object's contacts (World.check_groups):
    over configurations near objects resting on each other, with and without a held object,
    every answer is the one the canonical groups give, and afterwards stepping and the
    contact graph see the objects' own contacts again."""
    rng = np.random.default_rng(3)
    with table_world(("base", "box/0", 0.5, 0.0), ("top", "block/0", 0.5, 0.2), ("held", "block/0", 0.4, -0.2)) as world:
        world.rest_on("top", "base", (0.5, 0.0))
        world.settle()
        grasp = world.kinematics.ik(np.add(world.pose("held")[0], [0, 0, 0.01]), DOWN, rng)
        targets = [np.add(world.pose(name)[0], rng.uniform([-0.05, -0.05, 0.0], [0.05, 0.05, 0.12]))
                   for name in ("base", "top") for _ in range(60)]
        configurations = [q for q in (world.kinematics.ik(t, DOWN, rng) for t in targets) if q is not None]
        for holding in (False, True):
            if holding:
                world.set_arm(grasp)
                world.attach("held")
            checker, arm_only = CollisionChecker(world), CollisionChecker(world, check_held=False)
            with world.saved():
                fast = [checker.collides(q) for q in configurations]
                by_arm = [arm_only.collides(q) for q in configurations]
            with monkeypatch.context() as patch:
                patch.setattr(World, "check_groups", lambda self: None)
                with world.saved():
                    canonical = [checker.collides(q) for q in configurations]
            assert fast == canonical
            assert 0 < sum(by_arm) < len(configurations)
            assert (sum(fast) > sum(by_arm)) == holding   # the held block hits what the hand does not
        # Left in check groups, outside any saved() block, the arm back where it was:
        where = world.arm()
        checker.collides(configurations[0])
        world.set_arm(where)
        assert ("top", "base") in read_contacts(world).support
        checker.collides(configurations[0])
        world.set_arm(where)
        before = world.pose("top")
        world.step(120)
        assert moved(before, world.pose("top")) < 1e-3   # it still rests on the box


def slide_distance(slope_asset, friction):
    with World() as world:
        world.add_object(SceneObject("slope", slope_asset, (0.5, 0, 0), fixed=True, friction=friction),
                         resolve_asset(slope_asset, ASSETS))
        world.add_object(SceneObject("block", "block/0", (0.5, 0, 1.0), friction=friction),
                         resolve_asset("block/0", ASSETS))
        lo, hi = world.aabb("slope")
        centre = (lo + hi) / 2
        world.set_pose("block", ((centre[0], centre[1], hi[2] + 0.05), (0, 0, 0, 1)))
        world.settle(max_steps=120)  # land on the board
        start = world.pose("block")
        world.settle(max_steps=720)
        return moved(start, world.pose("block"))


def test_block_slides_off_a_steep_slippery_slope_but_not_a_gentle_rough_one():
    assert slide_distance("slope/2", friction=0.2) > 0.05
    assert slide_distance("slope/0", friction=1.0) < 0.01


def test_plate_pushed_past_the_table_edge_tips_and_an_overhang_stays():
    with table_world(("plate", "plate/0", 0.5, 0.0)) as world:
        edge = world.aabb("table")[1][0]
        radius = (world.aabb("plate")[1][0] - world.aabb("plate")[0][0]) / 2
        world.rest_on("plate", "table", (edge + radius * 0.1, 0.0))   # overhangs by 60 %: centre beyond the edge
        world.settle(max_steps=720)
        assert world.pose("plate")[0][2] < -0.05                      # fell off
        world.set_pose("plate", ((0.5, 0, 0.3), (0, 0, 0, 1)))
        world.rest_on("plate", "table", (edge - radius * 0.6, 0.0))   # overhangs by 40 %: stays
        world.settle(max_steps=60)                                    # drop the bounding-box padding
        before = world.pose("plate")
        world.settle(max_steps=720)
        assert moved(before, world.pose("plate")) < 0.005


def _pixels(camera, points):
    """Where world `points` land in `camera`'s image, as (column, row)."""
    import pybullet as p
    view = np.array(p.computeViewMatrixFromYawPitchRoll(camera.target, camera.distance, camera.yaw, camera.pitch, 0,
                                                        2)).reshape(4, 4).T
    projection = np.array(p.computeProjectionMatrixFOV(camera.fov, camera.width / camera.height, 0.02,
                                                       10.0)).reshape(4, 4).T
    clip = (projection @ view @ np.hstack([points, np.ones((len(points), 1))]).T).T
    ndc = clip[:, :2] / clip[:, 3:4]
    return np.stack([(ndc[:, 0] + 1) / 2 * camera.width, (1 - ndc[:, 1]) / 2 * camera.height], axis=1)


def _corners(world, name):
    lo, hi = world.aabb(name)
    return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])


def test_the_scene_camera_frames_the_objects_and_shows_them_large():
    path = os.path.join(ROOT, "docs", "examples", "first-problem.pddl")
    with open(path, encoding="utf-8") as handle, build_world(parse_text(handle.read(), path)) as world:
        framed = scene_camera(world)
        assert (framed.width, framed.height) == (640, 480)
        for name in world.movable():   # every object, and the arm's first pivot, are in the picture
            inside = _pixels(framed, np.vstack([_corners(world, name), [world.shoulder]]))
            assert np.all((inside >= 0) & (inside <= (640, 480))), name
        width = lambda camera: np.ptp(_pixels(camera, _corners(world, "block"))[:, 0])  # noqa: E731
        assert width(framed) > 2 * width(Camera())   # the fixed, far camera showed it small
        turned = scene_camera(world, View(yaw=90.0, pitch=-60.0, distance=1.2))
        assert (turned.yaw, turned.pitch, turned.distance, turned.target) == (90.0, -60.0, 1.2, framed.target)


def test_rendering_produces_a_non_blank_image(tmp_path):
    with table_world(("a", "block/0", 0.5, 0.0)) as world:
        image = render(world)
        assert image.shape == (360, 480, 3) and image.std() > 10
        save_png(image, str(tmp_path / "scene.png"))
        save_gif([image, render(world)], str(tmp_path / "scene.gif"))
        assert (tmp_path / "scene.png").stat().st_size > 1000 and (tmp_path / "scene.gif").stat().st_size > 1000


def test_a_world_without_visual_shapes_has_the_same_physics_and_refuses_to_render():
    """Planning worlds skip the meshes only a camera sees: the plate tipping over the
    edge must fall the same way, and rendering such a world is a clear error."""
    def tipped(visual):
        world = World(visual=visual)
        world.add_object(SceneObject("table", "table", (0.6, 0, 0), fixed=True), resolve_asset("table", ASSETS))
        world.add_object(SceneObject("plate", "plate/0", (0.5, 0, 0.5)), resolve_asset("plate/0", ASSETS))
        with world:
            edge = world.aabb("table")[1][0]
            world.rest_on("plate", "table", (edge + 0.01, 0.0))
            world.settle(max_steps=240)
            if not visual:
                with pytest.raises(ValueError, match="without visual shapes"):
                    render(world)
            return world.pose("plate")
    with_meshes, without = tipped(True), tipped(False)
    assert with_meshes[0][2] < -0.02   # it fell: the comparison below is of a real motion
    assert np.allclose(with_meshes[0], without[0], atol=1e-9) and np.allclose(with_meshes[1], without[1], atol=1e-9)


SCENE_PROBLEM = """(define (problem p) (:domain mech-basis) (:objects table a b - item)
  (:init (handempty)) (:goal (holding a))
  (:scene (table :asset "table" :position (0.6 0 0) :fixed)
          (a :asset "{a}" :position (0.5 0 {z}))
          (b :asset "block/0" :position (0.5 0.3 0.5))))"""


def test_unknown_asset_is_a_located_error_naming_the_object():
    with pytest.raises(PddlError) as error:
        build_world(parse_text(SCENE_PROBLEM.format(a="l-stik/0", z=0.5), "p.pddl"))
    assert str(error.value).startswith("p.pddl:4:14: error: scene object 'a': unknown asset 'l-stik/0'")


def test_object_put_inside_another_is_a_located_error_naming_both():
    text = SCENE_PROBLEM.format(a="block/0", z=0.5).replace("(0.5 0.3 0.5)", "(0.5 0 0.5)")
    # Reported at 'b': it was put where 'a' already is.
    with pytest.raises(PddlError, match=r"^p.pddl:5:11: error: scene object 'b': overlaps 'a' by \d+\.\d cm"):
        build_world(parse_text(text, "p.pddl"))


def test_scene_overlapping_the_robot_is_reported():
    text = SCENE_PROBLEM.format(a="box/0", z=0.3).replace("(0.5 0 0.3)", "(0.0 0.0 0.3)")
    with pytest.raises(PddlError, match="scene object 'a': overlaps the robot"):
        build_world(parse_text(text, "p.pddl"))


def test_a_pairs_normal_comes_from_its_closest_points():
    """A plate resting on a ledge (normals up, 0 mm) whose rim passes 1-2 mm from the ledge's
    wall (normals sideways) rests on it: only points within 0.5 mm of the closest count."""
    up, side = [1.0] * 4, [0.0] * 10
    assert pair_normal_z([0.0] * 4 + [0.0015] * 10, up + side) == pytest.approx(1.0)
    # Points equally close all count: a block leaning on a wall as much as resting is touching.
    assert pair_normal_z([0.0] * 14, up + side) == pytest.approx(4 / 14)


def test_the_robot_stands_on_a_mount_from_the_floor_to_its_base():
    """The pedestal is a body of the world, under the base, clear of the table and of the base."""
    import pybullet as p
    with table_world() as world:
        low, high = p.getAABB(world.mount, physicsClientId=world.client)
        base_low, base_high = p.getAABB(world.robot, -1, physicsClientId=world.client)
        assert low[2] < -0.7 and -0.01 < high[2] <= base_low[2] + 0.01
        assert low[0] <= base_low[0] and high[0] >= base_high[0] - 0.01       # under the whole base
        table_low, _ = p.getAABB(world.bodies["table"].id, physicsClientId=world.client)
        assert high[0] < table_low[0]                                          # clear of the table's edge
        assert all(c[8] >= 0 for c in p.getClosestPoints(world.mount, world.robot, 0.0, physicsClientId=world.client))


def test_a_movable_object_inside_the_mount_is_refused_by_name():
    problem = parse_text("""(define (problem p) (:domain mech-basis) (:objects table a - item)
      (:init (handempty)) (:goal (handempty))
      (:scene (table :asset "table" :position (0.6 0 0) :fixed)
              (a :asset "block/0" :position (-0.05 0 -0.3))))""")
    with pytest.raises(PddlError, match="overlaps the robot's mount"):
        build_world(problem)


def test_a_held_object_in_the_mount_collides_and_the_check_names_it():
    """Collision checks see the pedestal: a held block that the hand holds inside it collides."""
    import pybullet as p
    with table_world(("held", "block/0", 0.5, 0.0)) as world:
        q = world.arm()
        assert not CollisionChecker(world).collides(q)
        inside = ((-0.05, 0.0, -0.3), (0.0, 0.0, 0.0, 1.0))   # in the pedestal, under the base
        hand = world.hand_pose()
        world.attach("held", in_hand=p.multiplyTransforms(*p.invertTransform(*hand), *inside))
        assert CollisionChecker(world).collides(q)
        assert "the robot's mount" in CollisionChecker(world).colliding_bodies(q)
