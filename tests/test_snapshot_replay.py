"""Re-simulating from a snapshot is the same as simulating in a fresh world built from the
scene file: the planner's search tree and `replay` agree (issue: "solved" means it replays)."""
import os

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdsketch_mech.lang.loader import load_domain, load_problem
from pdsketch_mech.planner.bilevel import bilevel_plan
from pdsketch_mech.planner.execute import execute_step, settle_start
from pdsketch_mech.planner.serialize import from_json, plan_entries
from pdsketch_mech.world.build import build_world
from pdsketch_mech.world.collision import CollisionChecker
from pdsketch_mech.world.motion import plan_motion

from conftest import ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")


def load(name):
    return load_problem(os.path.join(ROOT, "problems", name + ".pddl"), [load_domain([BASIS])])


@pytest.fixture(scope="module", params=["edge", "stack"])
def planned(request):
    """A real plan (a push, grasps, placements) and its problem."""
    domain, problem = load(request.param)
    with build_world(problem) as world:
        result = bilevel_plan(domain, problem, world, timeout=120, seed=0)
    assert result.status == "solved", result.reason
    return problem, plan_entries(result.steps, result.values)


def values_of(entry):
    return {name: from_json(value) for name, value in entry["params"].items()}


def run(world, entries, start=0, first=None):
    """Execute entries[start:] as the planner and replay do (a snapshot at each step boundary,
    restored to start the step; `first`: the snapshot to start from instead of taking one);
    returns the snapshots. Like the planner, never snapshot a state just restored: PyBullet
    stores orientations in a form that does not read back bit-exactly, and a contact-rich
    push amplifies that 1e-18 into 0.1 mm."""
    snapshots = []
    for entry in entries[start:]:
        snapshots.append(first if first is not None and not snapshots else world.snapshot())
        assert execute_step(world, snapshots[-1], entry["name"], entry["args"], values_of(entry)).ok
    return snapshots


def poses(world):
    return {name: world.pose(name) for name in world.movable()}


def assert_close(a, b, mm=1.0, deg=1.0):
    for name in a:
        offset = np.linalg.norm(np.subtract(a[name][0], b[name][0]))
        angle = np.degrees((Rotation.from_quat(a[name][1]).inv() * Rotation.from_quat(b[name][1])).magnitude())
        assert offset * 1000 < mm and angle < deg, f"{name}: {offset * 1000:.2f} mm, {angle:.2f} deg"


def test_restored_prefixes_simulate_like_a_fresh_world(planned):
    problem, entries = planned
    with build_world(problem) as fresh:
        settle_start(fresh)
        run(fresh, entries)
        expected = poses(fresh)
    rng = np.random.default_rng(0)
    with build_world(problem) as world:
        settle_start(world)
        snapshots = run(world, entries)
        for k in rng.permutation(len(entries)):
            # Leave hidden simulator state behind: another branch of the plan, collision checks.
            world.restore(snapshots[0])
            run(world, entries[:rng.integers(len(entries) + 1)])
            checker = CollisionChecker(world)
            for _ in range(20):
                checker.collides(world.kinematics.limits.sample(rng))
            run(world, entries, start=k, first=snapshots[k])
            # The issue asks for 1 mm / 1 degree; a canonical restore gives float-exact
            # agreement, and any leak of hidden state (cached contacts: ~0.2 mm here) shows.
            assert_close(poses(world), expected, mm=1e-3, deg=1e-3)


def test_restoring_while_another_object_is_held_keeps_the_saved_grasp():
    _, problem = load("stack")
    with build_world(problem) as world:
        world.settle()
        a, b = world.movable()[:2]
        hand = np.array(world.hand_pose()[0])
        world.set_pose(a, ((hand[0], hand[1], hand[2] - 0.15), (0, 0, 0.3826834, 0.9238795)))
        world.attach(a)                       # wherever it is: 15 cm below the hand, turned 45 degrees
        saved_pose, saved_grasp = world.pose(a), world.attachment.in_hand
        held_a = world.snapshot()
        world.detach()
        world.set_pose(b, ((hand[0], hand[1], hand[2] - 0.05), (0, 0, 0, 1)))
        world.attach(b)
        world.step(30)
        world.restore(held_a)
        assert world.attachment.name == a
        assert np.allclose(world.attachment.in_hand[0], saved_grasp[0], atol=1e-9)
        assert np.allclose(world.pose(a)[0], saved_pose[0], atol=1e-9)
        world.step(60)                        # and it stays there under physics
        assert np.allclose(world.pose(a)[0], world.held_pose()[0], atol=1e-6)
        assert np.allclose(world.attachment.in_hand[0], saved_grasp[0], atol=1e-9)


def test_motion_plans_depend_on_the_seed_alone():
    """OMPL is re-seeded per query and stopped by a collision-check budget, so neither
    earlier queries nor the machine's load change a path."""
    _, problem = load("hook-use")
    rng = np.random.default_rng(3)
    with build_world(problem) as world:
        checker = CollisionChecker(world)
        for _ in range(100):
            a, b = world.kinematics.limits.sample(rng), world.kinematics.limits.sample(rng)
            with world.saved():
                if checker.collides(a) or checker.collides(b):
                    continue
            first = plan_motion(world, a, b, seed=5)
            if first.path is None or first.checks < 1000:
                continue  # a straight line needs no random search
            plan_motion(world, b, a, seed=11)
            again, other = plan_motion(world, a, b, seed=5), plan_motion(world, a, b, seed=6)
            assert np.array_equal(first.path, again.path)
            assert other.path is None or other.path.shape != first.path.shape or \
                not np.allclose(other.path, first.path)
            return
    pytest.fail("no query needed the random search")


def test_a_placeholder_drawn_again_is_printed_apart(monkeypatch):
    """Two pushes from one optimistic contact are two values: the second is `#contact4.2`, in
    its arguments and its parameters alike (what `replay` reads)."""
    import pdsketch_mech.planner.serialize as serialize
    from pdsketch_mech.planner.skeleton import Step

    monkeypatch.setattr(serialize, "to_json", lambda value: {"value": value})
    push = Step("transit-cont", ("box", "table", "#contact4", "#traj20"), 0)
    entries = plan_entries([push, push], [{"#contact4": 1.0, "#traj20": 2.0}, {"#contact4": 3.0, "#traj20": 4.0}])
    assert entries[0]["args"][2:] == ["#contact4", "#traj20"]
    assert entries[1]["args"][2:] == ["#contact4.2", "#traj20.2"]
    assert entries[1]["params"] == {"#contact4.2": {"value": 3.0}, "#traj20.2": {"value": 4.0}}
