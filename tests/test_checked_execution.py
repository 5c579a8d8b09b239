"""Execution checks what it is given: motions are collision-checked, a trajectory must start
where the arm is, a grasp must be where the plan says with both fingers on the object, a
push must touch what it pushes; so `replay` refuses edited plans, naming the step."""
import copy
import json
import os

import numpy as np
import pytest

from pdsketch_mech.commands import plan
from pdsketch_mech.commands import replay as replay_command
from pdsketch_mech.lang.loader import load_domain, load_problem
from pdsketch_mech.operators import basis
from pdsketch_mech.samplers.contact import sample_contacts
from pdsketch_mech.samplers.trajectory import push_motion
from pdsketch_mech.world.values import Contact, Trajectory
from pdsketch_mech.world.build import build_world

from conftest import ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")
PICK = os.path.join(ROOT, "problems", "pick.pddl")


@pytest.fixture(scope="module")
def pick_plan(tmp_path_factory):
    out = tmp_path_factory.mktemp("plans") / "pick.json"
    assert plan.main([BASIS, PICK, "--json", str(out), "--timeout", "60"]) == 0
    return json.loads(out.read_text())


def replay_edited(tmp_path, document, capsys):
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(document))
    status = replay_command.main([PICK, str(path)])
    return status, capsys.readouterr().err


def grasp_params(document):
    step = document["plan"][0]
    assert step["name"] == "grasp"
    return next(v for v in step["params"].values() if v["type"] == "grasp"), \
        next(v for v in step["params"].values() if v["type"] == "trajectory")


def test_replay_refuses_a_plan_whose_joints_were_shifted(tmp_path, capsys, pick_plan):
    edited = copy.deepcopy(pick_plan)
    _, trajectory = grasp_params(edited)
    trajectory["approach"] = [[q + 0.8 for q in waypoint] for waypoint in trajectory["approach"]]
    trajectory["final"] = [[q + 0.8 for q in waypoint] for waypoint in trajectory["final"]]
    status, err = replay_edited(tmp_path, edited, capsys)
    assert status == 1
    assert "step 1 (grasp) failed: the approach starts 0.800 rad away from the arm's configuration" in err


def test_replay_refuses_a_plan_whose_grasp_was_moved(tmp_path, capsys, pick_plan):
    edited = copy.deepcopy(pick_plan)
    grasp, _ = grasp_params(edited)
    grasp["in_object"][0][0] += 0.5
    status, err = replay_edited(tmp_path, edited, capsys)
    assert status == 1
    assert "step 1 (grasp) failed: the hand is 50" in err and "from the grasp of block" in err


def test_the_unedited_plan_replays_and_renders(tmp_path, capsys, pick_plan):
    path, gif = tmp_path / "plan.json", tmp_path / "replay.gif"
    path.write_text(json.dumps(pick_plan))
    assert replay_command.main([PICK, str(path), "--render", str(gif)]) == 0, capsys.readouterr().err
    assert gif.stat().st_size > 10000


def load(name):
    return load_problem(os.path.join(ROOT, "problems", name + ".pddl"), [load_domain([BASIS])])


def test_a_motion_through_the_table_is_refused():
    rng = np.random.default_rng(0)
    _, problem = load("pick")
    with build_world(problem) as world:
        world.settle()
        start = world.arm()
        below = world.kinematics.ik((0.45, -0.3, -0.05), (1, 0, 0, 0), rng)  # 5 cm into the table top
        path = np.linspace(start, below, 20)
        before = world.arm()
        outcome = basis.transit(world, Trajectory("free", path))
        assert not outcome.ok and outcome.reason.startswith("the motion collides with table")
        assert np.allclose(world.arm(), before)  # nothing was executed


def test_a_push_that_misses_its_object_fails():
    rng = np.random.default_rng(1)
    _, problem = load("pick")
    with build_world(problem) as world:
        world.settle()
        for contact in sample_contacts(world, "block", "table", rng):
            trajectory = push_motion(world, contact, rng)
            if trajectory is not None:
                break
        start = world.snapshot()
        assert basis.push(world, contact, trajectory).ok
        # The same push, with the block moved out of its way first.
        world.restore(start)
        world.set_pose("block", ((0.35, -0.3, world.pose("block")[0][2]), world.pose("block")[1]))
        missed = basis.push(world, Contact(None, "block", "table", contact.pusher_pose, contact.direction,
                                           contact.point, contact.normal), trajectory)
        assert not missed.ok and missed.reason == "the push never touched block"
