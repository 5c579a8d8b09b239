"""`check` validates what `plan` validates before searching: the scene builds into a world
(no object inside another or the robot, far away or below the table), streams name real
samplers, a stream domain's problem has a scene; scene-vs-:init disagreement and an object
that would fall are warnings; `:position (x y)` rests an object on its `:on` support."""
import os

import pytest

from pdsketch_mech.commands import check, plan
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.world.build import build_world

from conftest import ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")

# Line 7 is b's entry, line 8 a's: {a} is a's position, {more} extra entries.
SCENE = """(define (problem p) (:domain mech-basis)
  (:objects table a b - item)
  (:init (handempty) (support a table) (support b table))
  (:goal (holding a))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (b :asset "block/0" :position (0.5 0.2 0.026) :on table)
    (a :asset "block/0" :position {a} :on table)))
"""


def run_check(capsys, *paths):
    status = check.main(["-q", *paths])
    return status, capsys.readouterr().err.strip().splitlines()


@pytest.mark.parametrize("position,message", [
    ("(0.5 0.2 0.03)", "scene object 'a': overlaps 'b' by 4.8 cm at their scene poses"),
    ("(0.5 0 0)", "scene object 'a': overlaps 'table' by 2.7 cm at their scene poses; at z = 0.027 it would rest "
                  "on 'table'"),
    ("(0 0 0.05)", "scene object 'a': overlaps the robot (panda_link0) by 7.7 cm at its scene pose"),
    ("(100 0 0.026)", "scene object 'a': is 100.0 m from the robot base; a movable object must be within "
                      "2.0 m of it"),
    ("(0.5 0 -0.4)", "scene object 'a': is below 'table' with nothing under it: it would fall (the world "
                     "has no floor)"),
], ids=["overlapping objects", "sunk into the table", "inside the robot base", "100 m away", "below the table"])
def test_scene_errors_are_located_at_the_entry(write_files, capsys, position, message):
    (problem,) = write_files(**{"p.pddl": SCENE.format(a=position)})
    assert run_check(capsys, BASIS, problem) == (2, [f"{problem}:8:5: error: {message}"])


def test_plan_rejects_the_same_scene_with_the_same_line(write_files, capsys):
    (problem,) = write_files(**{"p.pddl": SCENE.format(a="(0.5 0.2 0.03)")})
    status = plan.main([BASIS, problem])
    captured = capsys.readouterr()
    assert (status, captured.out) == (2, "")
    assert captured.err.splitlines() == [f"{problem}:8:5: error: scene object 'a': overlaps 'b' by 4.8 cm "
                                         "at their scene poses"]


def test_movable_object_is_blamed_over_the_furniture_it_sinks_into(write_files, capsys):
    table = '    (table :asset "table" :position (0.6 0 0) :fixed)\n'
    text = SCENE.format(a="(0.5 0 0)").replace(table, "").replace(":on table)))", ":on table)\n" + table + "))")
    (problem,) = write_files(**{"p.pddl": text})
    assert run_check(capsys, BASIS, problem) == (
        2, [f"{problem}:7:5: error: scene object 'a': overlaps 'table' by 2.7 cm at their scene poses; at z = 0.027 "
            "it would rest on 'table'"])


def test_fixed_object_far_away_is_an_error(write_files, capsys):
    text = SCENE.format(a="(0.5 0 0.026)").replace("(0.6 0 0) :fixed", "(0.6 50 0) :fixed")
    (problem,) = write_files(**{"p.pddl": text})
    assert run_check(capsys, BASIS, problem) == (
        2, [f"{problem}:6:5: error: scene object 'table': is 50.0 m from the robot base; a fixed object must be "
            "within 5.0 m of it"])


def test_object_with_nothing_under_it_is_an_error(write_files, capsys):
    text = SCENE.format(a="(0.5 0 0.026)").replace("(0.6 0 0) :fixed", "(0.6 1.5 0) :fixed")  # beside them
    (problem,) = write_files(**{"p.pddl": text})
    assert run_check(capsys, BASIS, problem) == (
        2, [f"{problem}:7:5: error: scene object 'b': has nothing under it: it would fall (the world has no floor)"])


def test_scene_and_init_disagreeing_is_a_warning(write_files, capsys):
    (problem,) = write_files(**{"p.pddl": SCENE.format(a="(0.5 0.2 0.078)")})  # a stands on b
    assert run_check(capsys, BASIS, problem) == (
        0, [f"{problem}: warning: the scene and :init disagree: (support a b) holds in the scene, "
            "(support a table) is not true in the scene"])


def test_clean_scene_passes(write_files, capsys):
    (problem,) = write_files(**{"p.pddl": SCENE.format(a="(0.5 0 0.026)")})
    assert run_check(capsys, BASIS, problem) == (0, [])


def test_stream_domain_problem_needs_a_scene(write_files, capsys):
    text = SCENE.format(a="()").split("  (:scene")[0] + ")\n"
    (problem,) = write_files(**{"p.pddl": text})
    assert run_check(capsys, BASIS, problem) == (
        2, [f"{problem}:1:1: error: problem 'p' has no :scene; domain 'mech-basis' has streams, so the planner "
            "needs the physical scene"])


def test_stream_with_an_unknown_sampler_is_an_error(write_files, capsys):
    fragment = f"""(define (domain extra) (:extends "{BASIS}")
  (:stream sample-grip :inputs (?x - item) :outputs (?g - grasp) :certified (valid-grasp ?x ?g)
    :sampler "grsp"))
"""
    (path,) = write_files(**{"extra.pddl": fragment})
    assert run_check(capsys, path) == (
        2, [f"{path}:2:3: error: stream 'sample-grip' uses sampler 'grsp', which does not exist (did you mean "
            "'grasp'?); known: contact, free-motion, grasp, grasp-motion, held-motion, place-motion, "
            "placement, push-motion"])


def test_the_z_an_overlap_error_suggests_rests_the_object(write_files, capsys):
    (sunk,) = write_files(**{"sunk.pddl": SCENE.format(a="(0.5 0 0.01)")})
    status, lines = run_check(capsys, BASIS, sunk)
    assert status == 2 and lines[0].endswith("; at z = 0.027 it would rest on 'table'")
    (resting,) = write_files(**{"resting.pddl": SCENE.format(a="(0.5 0 0.027)")})
    assert run_check(capsys, BASIS, resting) == (0, [])


def test_overlap_blames_the_object_on_its_support_whichever_comes_first(write_files, capsys):
    text = """(define (problem p) (:domain mech-basis)
  (:objects table a b - item)
  (:init (handempty) (support a b) (support b table))
  (:goal (holding a))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (a :asset "block/0" :position (0.5 0 0.06) :on b)
    (b :asset "block/0" :position (0.5 0 0.027) :on table)))
"""
    (problem,) = write_files(**{"p.pddl": text})
    status, lines = run_check(capsys, BASIS, problem)
    assert status == 2
    assert lines == [f"{problem}:7:5: error: scene object 'a': overlaps 'b' by 1.9 cm at their scene poses; "
                     "at z = 0.079 it would rest on 'b'"]


def test_object_starting_above_its_support_is_a_located_warning(write_files, capsys):
    (problem,) = write_files(**{"p.pddl": SCENE.format(a="(0.5 0 0.145)")})
    assert run_check(capsys, BASIS, problem) == (
        0, [f"{problem}:8:5: warning: scene object 'a': starts 11.8 cm above 'table', so it falls when the "
            "simulation starts; at z = 0.027 it would rest on 'table'"])


def test_object_a_little_above_its_support_is_no_warning(write_files, capsys):
    (problem,) = write_files(**{"p.pddl": SCENE.format(a="(0.5 0 0.03)")})   # 3 mm: within the tolerance
    assert run_check(capsys, BASIS, problem) == (0, [])


def test_an_object_that_tips_over_as_the_scene_settles_is_a_located_warning(write_files, capsys):
    """A calculator leaning at 60 degrees rests on the table by its edge, then tips over."""
    text = SCENE.replace('(a :asset "block/0" :position {a} :on table)',
                         '(a :asset "calculator/0" :position (0.5 -0.1 0.04) :rpy-deg (60 0 0) :on table)')
    (problem,) = write_files(**{"p.pddl": text})
    status, lines = run_check(capsys, BASIS, problem)
    assert status == 0 and len(lines) == 1 and lines[0].startswith(f"{problem}:8:5: warning: scene object 'a': moves ")
    assert lines[0].endswith("cm as the scene settles (it does not rest at its scene pose: it falls, tips over or slides)")


def test_plan_warns_of_a_falling_object_at_its_entry_too(write_files, capsys):
    (problem,) = write_files(**{"p.pddl": SCENE.format(a="(0.5 0 0.145)")})
    plan.main([BASIS, problem, "--timeout", "60"])
    warning = (f"{problem}:8:5: warning: scene object 'a': starts 11.8 cm above 'table', so it falls when the "
               "simulation starts; at z = 0.027 it would rest on 'table'")
    assert warning in capsys.readouterr().err.splitlines()


STACK = """(define (problem p) (:domain mech-basis)
  (:objects table a b plate - item)
  (:init (handempty) (support a b) (support b plate) (support plate table))
  (:goal (holding a))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (a :asset "block/0" :position (0.5 0.1) :on b)
    (b :asset "block/1" :position (0.5 0.1) :rpy-deg (0 0 30) :on plate)
    (plate :asset "plate/0" :position {plate} :on table)))
"""


def test_position_without_z_rests_each_object_on_its_support(write_files, capsys):
    (problem,) = write_files(**{"p.pddl": STACK.format(plate="(0.5 0.1)")})
    assert run_check(capsys, BASIS, problem) == (0, [])   # no overlap, no fall, :init holds
    with build_world(parse_text(open(problem).read(), problem)) as world:
        before = {name: world.pose(name) for name in ("a", "b", "plate")}
        assert before["a"][0][:2] == pytest.approx((0.5, 0.1)) and before["b"][1] == pytest.approx(
            (0, 0, 0.258819, 0.965926), abs=1e-6)
        assert before["plate"][0][2] < before["b"][0][2] < before["a"][0][2]
        world.settle()
        for name, (position, _) in before.items():   # resting already: nothing moves
            assert world.pose(name)[0] == pytest.approx(position, abs=5e-4), name


def test_position_without_z_needs_a_support(write_files, capsys):
    text = SCENE.format(a="(0.5 0)").replace("(0.5 0) :on table", "(0.5 0)")
    (problem,) = write_files(**{"p.pddl": text})
    assert run_check(capsys, BASIS, problem) == (
        2, [f"{problem}:8:25: error: scene object 'a': :position (x y) gives no z, so it needs :on SUPPORT to "
            "rest on; or give (x y z)"])


def test_position_without_z_off_its_support_is_an_error(write_files, capsys):
    (problem,) = write_files(**{"p.pddl": STACK.format(plate="(0.5 1.5)")})
    assert run_check(capsys, BASIS, problem) == (
        2, [f"{problem}:9:5: error: scene object 'plate': 'table' is not under it at x = 0.5, y = 1.5: it has "
            "nowhere to rest (give x and y over 'table', or a z)"])


def test_check_reach_says_which_objects_the_hand_can_grasp_where_they_stand(capsys):
    """The user's shelf scene: the stick on the table is graspable, the box on the far shelf not."""
    status = check.main([os.path.join(ROOT, "problems", "contract", "user-shelf-far.pddl"), "--reach"])
    out = capsys.readouterr().out
    assert status == 0
    assert "reach: hook: graspable where it stands" in out
    assert "reach: box: not graspable where it stands" in out
