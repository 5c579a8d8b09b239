"""Every goal form plans and replays; unsolvable and timed-out runs say which; a scene that
moves when it settles is reported; nothing the user wrote is silently ignored (a missing
:sampler file, a mechanism's :certified, --validate, --no-learned-samplers)."""
import json
import os
import shutil
from collections import Counter

import numpy as np
import pytest

from pdsketch_mech.commands import check, plan
from pdsketch_mech.envs import TASKS, sample
from pdsketch_mech.lang.loader import load_domain, load_problem
from pdsketch_mech.planner.bilevel import prepare_task
from pdsketch_mech.planner.bindings import StepSampler
from pdsketch_mech.planner.refine import Refinement
from pdsketch_mech.planner.skeleton import skeleton_steps

from pdsketch_mech.world.build import build_world

from conftest import ROOT
from plan_fakes import skeleton_of

BASIS = os.path.join(ROOT, "domains", "basis.pddl")
PICK_TEXT = open(os.path.join(ROOT, "problems", "pick.pddl")).read()
TWO_BLOCKS = PICK_TEXT.replace("(:objects table block - item)", "(:objects table block cube - item)").replace(
    "(support block table))", "(support block table) (support cube table))").replace(
    ":on table)))", ":on table)\n    (cube :asset \"small-block/0\" :position (0.45 -0.2 0.016) :on table)))")


def goal(text, new_goal):
    return text.replace("(:goal (holding block))", f"(:goal {new_goal})")


@pytest.mark.parametrize("form", [
    "(or (holding cube) (holding block))",
    "(exists (?x - item) (and (holding ?x) (not (= ?x block))))",
    "(imply (handempty) (holding cube))",
])
def test_goal_forms_plan_and_replay(form, write_files, capsys):
    (path,) = write_files(**{"p.pddl": goal(TWO_BLOCKS, form)})
    status = plan.main([BASIS, path, "--timeout", "60", "--validate"])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    assert captured.out.startswith("(grasp ") and "reach-goal" not in captured.out
    assert "validate: replayed in a fresh world: the goal holds" in captured.err


def test_an_unreachable_goal_says_no_plan_exists(write_files, capsys):
    (path,) = write_files(**{"p.pddl": goal(PICK_TEXT, "(holding table)")})  # the table is fixed
    assert plan.main([BASIS, path, "--timeout", "30"]) == 1
    err = capsys.readouterr().err
    assert "unsolved: no plan exists: no sequence of operators reaches the goal symbolically" in err


def test_a_timeout_says_so():
    text = os.path.join(ROOT, "problems", "hook-use.pddl")
    domain, problem = load_problem(text, [load_domain([BASIS])])
    from pdsketch_mech.planner.bilevel import bilevel_plan
    with build_world(problem) as world:
        result = bilevel_plan(domain, problem, world, timeout=3, seed=0)
    assert result.status == "unsolved" and result.reason.startswith("timed out after 3.")


def test_an_object_that_falls_when_the_scene_settles_is_named(write_files, capsys):
    floating = PICK_TEXT.replace("(0.5 0.1 0.026)", "(0.5 0.1 0.126)").replace(" :on table", "")
    (path,) = write_files(**{"p.pddl": floating})
    assert plan.main([BASIS, path, "--timeout", "60"]) == 0
    err = capsys.readouterr().err
    assert "warning: object 'block' moved 9.9 cm" in err and "when the scene settled at the start" in err


MECHANISM = """(define (domain grab)
  (:extends "{basis}")
  (:mechanism grab-other
    :parameters (?a - item ?b - item ?s - item ?g - grasp ?t - traj)
    :precondition (and (handempty) (support ?a ?s) (support ?b ?s) (not (= ?a ?b)))
    :certified (holding ?b)
    :actions ((grasp ?a ?s ?g ?t)){sampler}))
"""


def test_a_mechanism_whose_certified_facts_do_not_hold_is_refuted(write_files):
    """grab-other grasps ?a but promises (holding ?b): the simulation shows the promise
    broken, so its refinement never succeeds."""
    fragment, problem_path = write_files(**{"grab.pddl": MECHANISM.format(basis=BASIS, sampler=""),
                                            "p.pddl": TWO_BLOCKS})
    domain, problem = load_problem(problem_path, [load_domain([fragment])])
    task, placeholders = prepare_task(domain, problem)
    macro = next(i for i, op in enumerate(task.operators) if op.name == "grab-other" and op.args[0] == "block")
    steps = skeleton_steps(task, [macro])
    assert steps[-1].certified, "the mechanism's last step carries its promise"
    with build_world(problem) as world:
        world.settle()
        sampler = StepSampler({s.name: s for s in domain.domain.streams}, placeholders, Counter())
        refinement = Refinement(skeleton_of(steps), world.snapshot(), world, task, sampler, np.random.default_rng(0))
        for _ in range(4):
            assert refinement.run(deadline=float("inf"), max_work=3) is None
    assert any("grab-other: its :certified facts do not hold" in reason for reason in refinement.failures)


def test_a_missing_sampler_checkpoint_is_a_located_error(write_files, capsys):
    (fragment,) = write_files(**{"grab.pddl": MECHANISM.format(basis=BASIS, sampler='\n    :sampler "grab.pt"')})
    assert check.main([fragment]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"{fragment}:3:3: error: mechanism 'grab-other': :sampler file 'grab.pt' not found")


def test_a_checkpoint_trained_on_few_episodes_is_a_located_warning(tmp_path, capsys):
    fragment, _, _ = com_copy(tmp_path)
    metadata = tmp_path / "com.samplers.json"
    metadata.write_text(json.dumps(dict(json.loads(metadata.read_text()), episodes=3)))
    assert check.main([fragment]) == 0
    assert "warning: mechanism 'com': its learned samplers were trained on 3 self-play episodes" \
        in capsys.readouterr().err


def test_a_checkpoint_that_cannot_be_loaded_stops_the_plan_unless_declined(write_files, capsys):
    fragment, _, problem_path = write_files(**{
        "grab.pddl": MECHANISM.format(basis=BASIS, sampler='\n    :sampler "grab.samplers.safetensors"'),
        "grab.samplers.safetensors": "not a real checkpoint", "p.pddl": TWO_BLOCKS})
    assert plan.main([fragment, problem_path, "--timeout", "60"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: ") and "grab.samplers.json: not found" in err and len(err.splitlines()) == 1
    assert plan.main([fragment, problem_path, "--timeout", "60", "--no-learned-samplers"]) == 0
    assert "error" not in capsys.readouterr().err


def test_a_missing_checkpoint_is_only_a_warning_where_it_would_not_be_loaded(write_files, capsys):
    """--no-learned-samplers (the way out the outdated-checkpoint error names) also plans
    past a :sampler file that is missing; without it the located error stays."""
    fragment, problem_path = write_files(**{
        "grab.pddl": MECHANISM.format(basis=BASIS, sampler='\n    :sampler "grab.samplers.safetensors"'),
        "p.pddl": TWO_BLOCKS})
    missing = (f"{fragment}:3:3: warning: mechanism 'grab-other': :sampler file 'grab.samplers.safetensors' not "
               f"found (looked for {os.path.dirname(fragment)}/grab.samplers.safetensors); its learned samplers are "
               "not used")
    for flag in ("--no-learned-samplers", "--basis-only"):  # --skeletons: no search
        assert plan.main([fragment, problem_path, flag, "--skeletons", "1"]) == 0
        assert capsys.readouterr().err.splitlines()[0] == missing
    assert check.main([fragment, problem_path, "--no-learned-samplers"]) == 0
    assert capsys.readouterr().err.splitlines() == [missing]
    assert plan.main([fragment, problem_path, "--skeletons", "1"]) == 2
    assert capsys.readouterr().err.strip() == missing.replace("warning", "error").split("; its")[0]
    # render (and replay) never load a checkpoint: a warning, and the picture is drawn.
    from pdsketch_mech.commands import render
    out = os.path.join(os.path.dirname(fragment), "scene.png")
    assert render.main([problem_path, fragment, "--out", out]) == 0 and os.path.isfile(out)
    assert capsys.readouterr().err.splitlines()[0] == missing


COM = os.path.join(ROOT, "domains", "mechanisms", "com.pddl")


def com_copy(folder, edit=lambda text: text):
    """domains/mechanisms/com.pddl, edited, as my-com.pddl in `folder` beside a copy of its
    checkpoint, and a Center-of-Mass problem; returns (fragment, problem, weights file)."""
    with open(COM) as handle:
        text = handle.read().replace('"../basis.pddl"', f'"{BASIS}"')
    fragment, problem = folder / "my-com.pddl", folder / "com-dev-0.pddl"
    fragment.write_text(edit(text))
    problem.write_text(sample(TASKS["com"], "dev", 0).problem_text())
    for suffix in (".samplers.safetensors", ".samplers.json"):
        shutil.copy(os.path.join(ROOT, "domains", "mechanisms", "com" + suffix), folder)
    return str(fragment), str(problem), str(folder / "com.samplers.safetensors")


def test_check_loads_the_learned_samplers_as_plan_does(tmp_path, capsys):
    """A checkpoint outdated by a precondition dropped (groundings it never saw): plan refuses
    it, and so does check, with the same line; both accept it with --no-learned-samplers."""
    fragment, problem, weights = com_copy(tmp_path)
    assert check.main([fragment, problem]) == 0
    capsys.readouterr()
    fragment, problem, weights = com_copy(tmp_path, lambda text: text.replace(
        ":precondition (and (handempty)", ":precondition (and"))
    assert check.main([fragment, problem]) == 2
    out, err = capsys.readouterr()
    assert err.splitlines() == [f"error: {weights} was trained for another definition of mechanism 'com' than the "
                                f"one in {fragment}; retrain it (python -m pdsketch_mech.learn train com --fragment "
                                f"{fragment} --force) or plan with --no-learned-samplers"]
    assert out.splitlines()[-1].startswith(f"{problem}: ok")  # the problem itself is fine
    assert plan.main([fragment, problem, "--timeout", "60"]) == 2
    assert capsys.readouterr().err.splitlines() == err.splitlines()
    assert check.main([fragment, problem, "--no-learned-samplers"]) == 0


def test_a_checkpoint_of_another_mechanism_says_which_it_was_trained_for(tmp_path, capsys):
    fragment, _, weights = com_copy(tmp_path, lambda text: text.replace("(:mechanism com", "(:mechanism my-com"))
    assert check.main([fragment]) == 2
    assert capsys.readouterr().err.splitlines() == [
        f"error: {weights} was trained for mechanism 'com', not 'my-com' (in {fragment}); train one for it "
        f"(python -m pdsketch_mech.learn train my-com --fragment {fragment}) or plan with --no-learned-samplers"]


@pytest.mark.parametrize("text,message", [
    ('{"schema": "pdsketch_mech.samplers/2",\n}', "{json}:2:1: error: the checkpoint's metadata is not valid JSON: "
                                                  "Expecting property name enclosed in double quotes"),
    ("[1, 2]", "error: {json}: not a learned-sampler checkpoint (pdsketch_mech.samplers/2)"),
    ('{"schema": "pdsketch_mech.samplers/2", "mechanism": "com"}',
     "error: {json}: the checkpoint's metadata is malformed (KeyError: 'parameters')"),
], ids=["invalid JSON", "not an object", "no parameters"])
def test_a_broken_checkpoint_metadata_file_is_named(tmp_path, capsys, text, message):
    """Not the weights file: the JSON beside it, and where in it."""
    fragment, problem, weights = com_copy(tmp_path)
    metadata = tmp_path / "com.samplers.json"
    metadata.write_text(text)
    expected = [message.format(json=metadata)]
    assert check.main([fragment]) == 2
    assert capsys.readouterr().err.splitlines() == expected
    assert plan.main([fragment, problem, "--timeout", "60"]) == 2
    assert capsys.readouterr().err.splitlines() == expected
