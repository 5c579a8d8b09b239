"""Users' demonstrations (docs/demonstrations.md): the file format's checks, each with its
located error; points and directions relative to objects' boxes; the docs' worked example
(file and Python forms) recorded, extracted to its expected steps and planned with; perturbed
scenes from a seed."""
from __future__ import annotations

import json
import os
import shutil

import numpy as np
import pytest

from pdsketch_mech.commands import demo as demo_cli
from pdsketch_mech.commands import learn as learn_cli
from pdsketch_mech.envs.demos.anchors import AnchorError, anchor_local, check_words, face, object_box
from pdsketch_mech.envs.demos.demo_file import DemoFileError, read_demo_file
from pdsketch_mech.envs.demos.user import perturbed
from pdsketch_mech.lang.parser import parse_file
from pdsketch_mech.lang.scene import build_scene
from pdsketch_mech.lang.writer import write_problem

from conftest import ROOT

EXAMPLES = os.path.join(ROOT, "docs", "examples")
EXPECTED_STEPS = "2 steps (transit-cont flat table) (grasp flat table)"


def example_folder(tmp_path) -> str:
    for name in ("push-to-edge.pddl", "push-to-edge.demo.json", "push-to-edge.py"):
        shutil.copy(os.path.join(EXAMPLES, name), tmp_path / name)
    return str(tmp_path)


def write_demo(tmp_path, steps, **top) -> str:
    """A demonstration in the worked example's scene with the given steps."""
    folder = example_folder(tmp_path)
    path = os.path.join(folder, "try.demo.json")
    with open(path, "w") as handle:
        json.dump({"format": 1, "problem": "push-to-edge.pddl", "steps": steps, **top}, handle, indent=1)
    return path


def record(path, capsys, *extra) -> tuple:
    status = demo_cli.main(["record", path, *extra])
    return status, capsys.readouterr().err.strip().splitlines()[-1]


# ---------------------------------------------------------------------- places
def test_face_words_follow_the_object_as_it_turns():
    box = object_box(((0.5, 0.2, 0.01), (0, 0, 0.7071068, 0.7071068)), (-0.075, -0.04, -0.0075), (0.075, 0.04, 0.0075))
    # Turned 90 degrees about z: its +x axis points to the robot's left (+y).
    assert face("left", box) == (0, 1) and face("far", box) == (1, -1) and face("top", box) == (2, 1)
    assert np.allclose(box.to_world(anchor_local("left top", box)), (0.5, 0.275, 0.0175), atol=1e-6)
    assert np.allclose(box.to_world(anchor_local("far right bottom", box)), (0.54, 0.125, 0.0025), atol=1e-6)
    with pytest.raises(AnchorError, match="same axis"):
        anchor_local("left +x", box)


def test_anchor_words_are_checked_before_any_world_exists():
    assert check_words("far top") is None and check_words("center") is None
    assert "unknown face 'abvoe'" in check_words("abvoe")
    assert "same axis" in check_words("top bottom")


# ---------------------------------------------------------------------- bad files
@pytest.mark.parametrize("steps, expected", [
    ([{"do": "opne"}], "step 1 (opne): do: unknown command \"opne\" (did you mean 'open'?)"),
    ([{"do": "open"}, {"do": "grasp"}], "step 2 (grasp): object: missing"),
    ([{"do": "lift", "distance": "far"}], "step 1 (lift): distance: expected a distance in metres (>= 0), got \"far\""),
    ([{"do": "open", "speed": 1}], "step 1 (open): unknown field 'speed'"),
    ([{"do": "line", "direction": "down"}], "step 1 (line): give a distance, a point to go \"to\""),
    ([{"do": "move", "to": {"object": "flat", "at": "abvoe"}}], "step 1 (move): to.at: unknown face 'abvoe'"),
    ([{"do": "move", "to": {"object": "flat", "offset": {"beyond": 1}}}], "step 1 (move): to.offset: unknown offset 'beyond'"),
    ([{"do": "line", "direction": [0, 0, 0], "distance": 0.1}], "step 1 (line): direction: the direction [0, 0, 0] has no length"),
    ([{"do": "grasp", "object": "flat", "fingers": 3}], "step 1 (grasp): fingers: expected 1 or 2"),
])
def test_a_malformed_step_is_one_located_line_and_exit_2(tmp_path, capsys, steps, expected):
    path = write_demo(tmp_path, steps)
    status, line = record(path, capsys)
    assert status == 2
    assert line.startswith(f"{path}:") and ": error: " in line and expected in line, line


def test_the_location_is_the_step_line_and_column(tmp_path):
    path = tmp_path / "x.demo.json"
    path.write_text('{"format": 1,\n "steps": [\n   {"do": "open"},\n     {"do": "fly"}]}\n')
    with pytest.raises(DemoFileError, match=r"x\.demo\.json:4:6: error: step 2 \(fly\)"):
        read_demo_file(str(path))


@pytest.mark.parametrize("text, expected", [
    ('{"format": 1, "steps": [{"do": "open"},]}', ":1:40: error: not JSON: Expecting value (a comma before ']'?"),
    ('{"steps": [{"do": "open"}]}', "error: format: expected \"format\": 1 (the only format there is); it is missing"),
    ('{"format": 1, "stpes": []}', "error: unknown field 'stpes' (did you mean 'steps'?)"),
    ('{"format": 1, "steps": []}', "error: steps: expected a non-empty list of steps"),
    ('[1, 2]', ":1:1: error: a demonstration is a JSON object"),
])
def test_a_malformed_file_is_one_line(tmp_path, capsys, text, expected):
    path = tmp_path / "bad.demo.json"
    path.write_text(text)
    status, line = record(str(path), capsys)
    assert status == 2 and line.startswith(str(path)) and expected in line, line


def test_an_unknown_object_is_named_with_its_step_before_anything_moves(tmp_path, capsys):
    path = write_demo(tmp_path, [{"do": "open"}, {"do": "close"}, {"do": "grasp", "object": "flta"}])
    status, line = record(path, capsys)
    assert status == 2
    assert "step 3 (grasp): object: 'flta' is not an object of the scene (did you mean 'flat'?)" in line, line


def test_a_missing_problem_file_is_named(tmp_path, capsys):
    path = write_demo(tmp_path, [{"do": "open"}], problem="nowhere.pddl")
    status, line = record(path, capsys)
    assert status == 2 and "problem: " in line and "nowhere.pddl: no such file" in line


def test_a_step_that_fails_in_simulation_names_it_and_exits_1(tmp_path, capsys):
    path = write_demo(tmp_path, [{"do": "open"}, {"do": "lift", "distance": 0.02}, {"do": "grasp", "object": "flat"}])
    status, line = record(path, capsys)
    assert status == 1
    assert "try.demo.json:" in line and "step 3 (grasp): the fingers do not hold 'flat'" in line, line
    assert not os.path.exists(tmp_path / "try.npz")        # nothing is recorded


def test_an_unreachable_pose_names_its_step(tmp_path, capsys):
    path = write_demo(tmp_path, [{"do": "move", "to": [2.0, 0.0, 0.3]}])
    status, line = record(path, capsys)
    # By the rule docs/first-problem.md states: the flange, not the gripper point, within 0.82 m.
    assert status == 1 and "step 1 (move): no way to approach the gripper pose at [2.0, 0.0, 0.3]: the arm's " \
                           "flange (0.21 m behind the gripper point, along the fingers) would be 2.00 m from the " \
                           "robot's shoulder, beyond its reach (0.82 m)" in line, line


def test_a_blocked_pose_names_what_the_arm_would_hit(tmp_path, capsys):
    # Fingertips 1 cm inside the calculator, coming from above.
    path = write_demo(tmp_path, [{"do": "open"}, {"do": "move", "to": {"object": "flat", "at": "top",
                                                                        "offset": {"down": 0.01}}}])
    status, line = record(path, capsys)
    assert status == 1 and "step 2 (move): no way to approach" in line and "would hit: the panda_" in line and "mm into 'flat'" in line, line


def test_until_touches_explains_what_touching_means(tmp_path, capsys):
    path = write_demo(tmp_path, [{"do": "close"}, {"do": "line", "direction": "up", "distance": 0.05,
                                                   "until": {"touches": "flat"}}])
    status, line = record(path, capsys)
    assert status == 1 and "neither the hand nor what it holds touched 'flat'" in line and '{"moves": "flat"}' in line


BOWL = """(define (problem bowl) (:domain mech-basis) (:objects table cube bowl - item)
  (:init (handempty) (fixed table) (support cube table) (support bowl table))
  (:goal (and (support cube bowl) (handempty)))
  (:scene (table :asset "table" :position (0.6 0 0) :fixed)
          (cube :asset "small-block/0" :position (0.45 0.15) :rpy-deg (0 0 20) :on table)
          (bowl :asset "bowl/0" :position (0.5 -0.15) :on table)))"""


def test_fingers_wedged_after_a_release_stop_the_demonstration(tmp_path, capsys):
    """Let go deep inside a bowl, the opening fingers press on its walls: the next lift would
    carry the bowl off, which a recording must not call a release."""
    (tmp_path / "bowl.pddl").write_text(BOWL)
    path = tmp_path / "bowl.demo.json"
    path.write_text(json.dumps({"format": 1, "steps": [
        {"do": "open"}, {"do": "move", "to": {"object": "cube"}}, {"do": "grasp", "object": "cube"},
        {"do": "lift", "distance": 0.1}, {"do": "put", "at": {"object": "bowl", "at": "bottom", "offset": {"up": 0.012}}},
        {"do": "release"}, {"do": "lift", "distance": 0.1}]}))
    status, line = record(str(path), capsys)
    assert status == 1 and "step 6 (release): after the fingers opened, both fingers still press on 'bowl'" in line


def test_a_demonstration_that_misses_its_goal_says_so(tmp_path, capsys):
    path = write_demo(tmp_path, [{"do": "close"}, {"do": "lift", "distance": 0.02}])
    status, line = record(path, capsys)
    assert status == 1 and line.startswith(f"{path}: error: every step was done, but the goal (holding flat) "
                                           "does not hold at the end"), line


@pytest.mark.parametrize("last_line, expected", [
    ('hand.grasp("flat")', "the fingers do not hold 'flat'"),          # a step the robot cannot do
    ('hand.lift("high")', "the script failed: TypeError"),              # a bug in the script
])
def test_a_failing_script_is_located_at_its_line(tmp_path, capsys, last_line, expected):
    folder = example_folder(tmp_path)
    script = os.path.join(folder, "mine.py")
    with open(script, "w") as handle:
        handle.write(f'PROBLEM = "push-to-edge.pddl"\n\n\ndef demonstrate(hand):\n    hand.open()\n    {last_line}\n')
    status, line = record(script, capsys)
    assert status == 1 and line.startswith(f"{script}:6: error: {expected}"), line


def test_a_scene_that_does_not_build_is_one_located_line(tmp_path, capsys):
    folder = example_folder(tmp_path)
    scene = os.path.join(folder, "push-to-edge.pddl")
    text = open(scene).read().replace(":position (0.48 0.22) :rpy-deg (0 0 90) :on table",
                                      ":position (0.48 0.22 -0.02) :rpy-deg (0 0 90)")
    open(scene, "w").write(text)
    status, line = record(os.path.join(folder, "push-to-edge.demo.json"), capsys)
    assert status == 2 and line.startswith(f"{scene}:") and "error: scene object 'flat'" in line, line


# ---------------------------------------------------------------------- the worked example
@pytest.mark.parametrize("form", ["push-to-edge.demo.json", "push-to-edge.py"])
def test_the_worked_example_records_and_extracts_to_its_steps(tmp_path, capsys, form):
    folder = example_folder(tmp_path)
    status, line = record(os.path.join(folder, form), capsys)
    assert status == 0 and "goal (holding flat) holds" in line, line
    header = json.load(open(os.path.join(folder, "push-to-edge.json")))
    assert header["task"] == "push-to-edge" and header["problem_file"] == "push-to-edge.pddl"
    fragment = os.path.join(folder, "push-to-edge.mech.pddl")
    assert learn_cli.main(["extract", os.path.join(folder, "push-to-edge"), "--out", fragment]) == 0
    assert EXPECTED_STEPS in capsys.readouterr().err
    assert '(:extends "basis")' in open(fragment).read()       # not this checkout's path


@pytest.mark.slow
def test_the_worked_example_plans_with_its_mechanism(tmp_path, capsys):
    from pdsketch_mech.commands import plan as plan_cli

    folder = example_folder(tmp_path)
    assert record(os.path.join(folder, "push-to-edge.demo.json"), capsys)[0] == 0
    fragment = os.path.join(folder, "push-to-edge.mech.pddl")
    assert learn_cli.main(["extract", os.path.join(folder, "push-to-edge"), "--out", fragment]) == 0
    plan = os.path.join(folder, "plan.json")
    status = plan_cli.main([fragment, os.path.join(folder, "push-to-edge.pddl"), "--seed", "1", "--timeout", "90",
                            "--json", plan])
    assert status == 0
    assert any(step.get("mechanism") == "push-to-edge" for step in json.load(open(plan))["plan"])


def test_a_hook_written_as_a_file_extracts_to_the_shipped_hook(tmp_path, capsys):
    """Written by a new user from the docs alone: the same steps as the built-in script's."""
    for name in ("hook.pddl", "hook.demo.json"):
        shutil.copy(os.path.join(EXAMPLES, name), tmp_path / name)
    status, line = record(str(tmp_path / "hook.demo.json"), capsys, "--seed", "1")
    assert status == 0, line
    assert learn_cli.main(["extract", str(tmp_path / "hook-seed-1"), "--out", str(tmp_path / "hook.mech.pddl")]) == 0
    assert "4 steps (grasp hook table) (move-cont hook box table) (place hook table) (grasp box table)" \
        in capsys.readouterr().err


STACK = """(define (problem stack) (:domain mech-basis) (:objects table cube tower - item)
  (:init (handempty) (fixed table) (support cube table) (support tower table))
  (:goal (and (support cube tower) (handempty)))
  (:scene (table :asset "table" :position (0.6 0 0) :fixed)
          (cube :asset "block/0" :position (0.45 0.15) :rpy-deg (0 0 30) :on table)
          (tower :asset "block/2" :position (0.5 -0.12) :on table)))"""


def test_put_carries_the_held_object_point_to_point_and_turns_it(tmp_path, capsys):
    (tmp_path / "stack.pddl").write_text(STACK)
    path = tmp_path / "stack.demo.json"
    path.write_text(json.dumps({"format": 1, "steps": [
        {"do": "open"}, {"do": "move", "to": {"object": "cube"}}, {"do": "grasp", "object": "cube"},
        {"do": "lift", "distance": 0.1},
        {"do": "put", "at": {"object": "tower", "at": "top", "offset": {"up": 0.003}}, "turn": 20},
        {"do": "release"}, {"do": "lift", "distance": 0.05}]}))
    status, line = record(str(path), capsys)
    assert status == 0, line
    from pdsketch_mech.world.recording import load_recording
    recording = load_recording(str(tmp_path / "stack"))
    cube, tower = (recording.objects.index(n) for n in ("cube", "tower"))
    last = recording.arrays["poses"][-1]
    assert np.linalg.norm(last[cube][:2] - last[tower][:2]) < 0.01          # centred on the tower
    import pybullet as p
    yaw = np.degrees(p.getEulerFromQuaternion(last[cube][3:])[2])
    assert abs(((yaw - 50.0) + 45.0) % 90.0 - 45.0) < 4.0                    # 30 degrees, turned by 20


def test_an_existing_recording_is_kept_without_force(tmp_path, capsys):
    folder = example_folder(tmp_path)
    (tmp_path / "push-to-edge.npz").write_bytes(b"mine")
    status, line = record(os.path.join(folder, "push-to-edge.demo.json"), capsys)
    assert status == 2 and "exists (use --force to replace it)" in line
    assert (tmp_path / "push-to-edge.npz").read_bytes() == b"mine"


# ---------------------------------------------------------------------- perturbed scenes
def test_a_seed_perturbs_movable_objects_reproducibly_and_within_bounds():
    problem = parse_file(os.path.join(EXAMPLES, "push-to-edge.pddl"))
    a, b, c = perturbed(problem, 3), perturbed(problem, 3), perturbed(problem, 4)
    assert write_problem(a) == write_problem(b) != write_problem(c)
    before = {o.name: o for o in build_scene(problem)}
    for obj in build_scene(a):
        shift = np.subtract(obj.position[:2], before[obj.name].position[:2])
        if obj.fixed:
            assert np.allclose(shift, 0)
        else:
            assert 0 < np.abs(shift).max() <= 0.02 + 1e-9
