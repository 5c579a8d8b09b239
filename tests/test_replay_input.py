"""replay checks a saved plan against its problem and domain before it builds a world: every
malformed document is one located `PLAN.json:LINE:COL: error: step N (action): ...` line,
exit 2, no traceback."""
import copy
import json
import math
import os
import re
import subprocess
import sys

import pytest

from pdsketch_mech.commands import replay
from pdsketch_mech.planner.plan_document import EXECUTION_MODEL, locate

from conftest import ROOT

PICK = os.path.join(ROOT, "problems", "pick.pddl")
EDGE = os.path.join(ROOT, "problems", "edge.pddl")
BASIS = os.path.join(ROOT, "domains", "basis.pddl")

# A plan for problems/pick.pddl, in the shape `plan --json` writes.
VALID = {
    "status": "solved", "reason": "solved", "time_s": 1.0, "seed": 0, "stats": {},
    "plan": [{
        "name": "grasp", "args": ["block", "table", "#grasp2", "#traj3"], "mechanism": None,
        "params": {
            "#grasp2": {"type": "grasp", "object": "block", "in_object": [[0.0, 0.015, 0.015], [0.6916288618, 0.6916288618, 0.1471377501, -0.1471377501]],
                        "width": 0.05, "points": [[-0.025, 0.015, 0.015], [0.025, 0.015, 0.015]]},
            "#traj3": {"type": "trajectory", "kind": "grasp", "approach": [[0.0, -0.5, 0.0, -2.2, 0.0, 1.7, 0.785]],
                       "final": [[0.0, -0.49, 0.0, -2.2, 0.0, 1.7, 0.785]], "push_distance": None},
        },
    }],
}


def edited(edit):
    document = copy.deepcopy(VALID)
    edit(document)
    return document


def step(document):
    return document["plan"][0]


CASES = [
    ("plan of another problem", EDGE, lambda d: None,
     "step 1 (grasp): argument 1: unknown object 'block' (is the plan for another problem?)"),
    # Its objects may all exist there too (two test instances of one task): the name tells.
    ("plan made for a problem of another name", PICK, lambda d: d.update(problem="pick-block-2"),
     f"the plan was made for problem 'pick-block-2', not 'pick-block' ({PICK})"),
    ("unknown action", PICK, lambda d: step(d).update(name="grsp"),
     "step 1 (grsp): unknown action 'grsp' (did you mean 'grasp'?)"),
    ("unknown parameter type", PICK, lambda d: step(d)["params"]["#grasp2"].update(type="gasp"),
     "step 1 (grasp): parameter '#grasp2' has unknown type 'gasp'; expected grasp, placement, contact, trajectory"),
    ("params as a list", PICK, lambda d: step(d).update(params=[1, 2]),
     "step 1 (grasp): \"params\" must be an object (placeholder -> value)"),
    ("missing params", PICK, lambda d: step(d).pop("params"),
     "step 1 (grasp): \"params\" must be an object (placeholder -> value)"),
    ("missing value", PICK, lambda d: step(d)["params"].pop("#traj3"),
     "step 1 (grasp): argument 4 (#traj3) has no value in \"params\""),
    ("unknown object", PICK, lambda d: step(d)["args"].__setitem__(1, "tabel"),
     "step 1 (grasp): argument 2: unknown object 'tabel' (did you mean 'table'?) (is the plan for another problem?)"),
    ("empty args", PICK, lambda d: step(d).update(args=[]),
     "step 1 (grasp): 'grasp' takes 4 arguments, got 0"),
    ("NaN joint", PICK, lambda d: step(d)["params"]["#traj3"]["approach"][0].__setitem__(3, math.nan),
     "step 1 (grasp): parameter '#traj3': \"approach\" waypoint 1: entry 4 is nan, not a joint angle in [-6.283, 6.283]"),
    ("six joints", PICK, lambda d: step(d)["params"]["#traj3"]["final"][0].pop(),
     "step 1 (grasp): parameter '#traj3': \"final\" waypoint 1 must be a list of 7 numbers"),
    ("infinite width", PICK, lambda d: step(d)["params"]["#grasp2"].update(width=math.inf),
     "step 1 (grasp): parameter '#grasp2': \"width\" is inf, not a finite number >= 0"),
    ("value of the wrong kind", PICK, lambda d: step(d)["args"].__setitem__(2, "#traj3"),
     "step 1 (grasp): parameter '#traj3' is a trajectory, but 'grasp' takes a grasp there"),
    ("mechanism as a step", os.path.join(ROOT, "problems", "hook-use.pddl"),
     lambda d: step(d).update(name="hook-use"),
     "step 1 (hook-use): 'hook-use' is a mechanism; a saved plan lists its basis steps"),
    ("a step that is not an object", PICK, lambda d: d["plan"].append("grasp"),
     "step 2: expected an object with a \"name\", \"args\" and \"params\""),
    ("no plan list", PICK, lambda d: d.pop("plan"),
     "not a plan written by `plan --json`: expected an object with a \"plan\" list"),
]


@pytest.mark.parametrize("problem,edit,message", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_malformed_plan_is_one_located_line(tmp_path, capsys, problem, edit, message):
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(edited(edit), indent=1))
    domains = [os.path.join(ROOT, "domains", "mechanisms", "hook-use.pddl")] if "hook" in problem else []
    status = replay.main([problem, str(path), *domains])
    err = capsys.readouterr().err
    assert status == 2
    assert re.fullmatch(rf"{re.escape(str(path))}:\d+:\d+: error: {re.escape(message)}\n", err), err


def test_error_points_at_the_offending_value(tmp_path, capsys):
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(edited(lambda d: step(d)["params"]["#traj3"]["approach"][0].__setitem__(3, 99.0)),
                               indent=1))
    replay.main([PICK, str(path)])
    line, col = map(int, capsys.readouterr().err.split(":")[1:3])
    assert path.read_text().splitlines()[line - 1][col - 1:].startswith("99.0")


def test_invalid_json_is_located(tmp_path, capsys):
    path = tmp_path / "plan.json"
    path.write_text('{"plan": [\n  {"name": "grasp",, }]}')
    assert replay.main([PICK, str(path)]) == 2
    assert capsys.readouterr().err == f"{path}:2:20: error: not valid JSON: Expecting property name enclosed in double quotes\n"


def test_locate_follows_keys_and_indices():
    text = '{"a": [1, {"b": 2, "b": [3, 4]}], "c": 5}'
    assert locate(text, ("a", 1, "b", 1)) == (1, text.index("4") + 1)
    assert locate(text, ("c",)) == (1, text.index("5") + 1)
    assert locate(text, ("missing", 0)) == (1, 1)


def test_a_valid_plan_replays_in_a_subprocess_without_traceback(tmp_path):
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(VALID))
    done = subprocess.run([sys.executable, "-m", "pdsketch_mech.replay", PICK, str(path)],
                          capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert done.returncode in (0, 1), done.stderr
    assert done.stderr.startswith("replay: 1 steps;") and "Traceback" not in done.stderr


def test_render_path_is_checked_before_replay(tmp_path, capsys):
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(VALID))
    assert replay.main([PICK, str(path), "--render", str(tmp_path / "nope" / "a.gif")]) == 2
    assert capsys.readouterr().err == f"error: --render {tmp_path}/nope/a.gif: folder {tmp_path}/nope does not exist\n"


def test_a_problem_of_the_basis_domain_needs_no_domain_file(tmp_path, capsys, monkeypatch):
    """The problem names mech-basis and nothing beside it declares it: the shipped basis
    domain is used (a user's problem anywhere, an installed package's domain)."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "p.pddl").write_text(open(PICK).read())
    (tmp_path / "plan.json").write_text(json.dumps(VALID))
    assert replay.main(["p.pddl", "plan.json"]) in (0, 1)
    assert "error" not in capsys.readouterr().err


OTHER = edited(lambda d: d.update(problem="pick-block-2"))   # refused once read: shows which file was taken as what


@pytest.mark.parametrize("order", [
    ("problem", "plan"), ("plan", "problem"), ("domain", "problem", "plan"), ("plan", "domain", "problem"),
    ("problem", "plan", "domain")], ids=lambda order: " ".join(order))
def test_files_are_recognised_in_any_order(tmp_path, capsys, order):
    path = tmp_path / "my-plan.txt"   # recognised by its content, not its name
    path.write_text(json.dumps(OTHER, indent=1))
    files = {"problem": PICK, "plan": str(path), "domain": BASIS}
    assert replay.main([files[role] for role in order]) == 2
    assert re.fullmatch(rf"{re.escape(str(path))}:\d+:\d+: error: the plan was made for problem 'pick-block-2', "
                        rf"not 'pick-block' \({re.escape(PICK)}\)\n", capsys.readouterr().err)


def test_shipped_names_take_their_documented_roles(tmp_path, capsys):
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(OTHER))
    assert replay.main([str(path), "basis", "pick"]) == 2   # `basis` only names a domain; `pick` is the problem
    assert "error: the plan was made for problem 'pick-block-2', not 'pick-block'" in capsys.readouterr().err


@pytest.mark.parametrize("files,message", [
    (lambda plan: [PICK, plan, plan + "2"], "two plans given ({plan}, {plan}2): replay takes one plan JSON"),
    (lambda plan: [PICK, BASIS], "no plan given: replay needs the JSON file `plan --json` wrote, with its problem "
                                 "(and domain) files, in any order"),
    (lambda plan: [BASIS, plan], "no problem given: replay needs the problem the plan was made for "
                                 "(given: {basis}, {plan})"),
    (lambda plan: [PICK, EDGE, plan], "two problems given ({pick}, {edge}): replay takes one problem; a domain "
                                      "file starts with (define (domain"),
], ids=["two plans", "no plan", "no problem", "two problems"])
def test_a_missing_or_doubled_input_is_one_line(tmp_path, capsys, files, message):
    plan = str(tmp_path / "plan.json")
    for name in (plan, plan + "2"):
        with open(name, "w") as handle:
            json.dump(VALID, handle)
    assert replay.main(files(plan)) == 2
    assert capsys.readouterr().err == "error: " + message.format(plan=plan, basis=BASIS, pick=PICK, edge=EDGE) + "\n"


def test_replay_render_takes_the_camera_options(tmp_path, capsys):
    from PIL import Image

    path, gif = tmp_path / "plan.json", tmp_path / "turned.gif"
    path.write_text(json.dumps(VALID))
    assert replay.main([PICK, str(path), "--render", str(gif), "--yaw", "90", "--pitch", "-60", "--distance", "1.2"]) \
        in (0, 1)
    assert Image.open(gif).size == (640, 480)
    capsys.readouterr()
    with pytest.raises(SystemExit) as exited:
        replay.main([PICK, str(path), "--render", str(gif), "--distance", "0"])
    assert exited.value.code == 2
    assert capsys.readouterr().err == "error: argument --distance: must be a finite number from 0.05 to 100, got '0'\n"


@pytest.mark.parametrize("model, noted", [(None, True), (1, True), (EXECUTION_MODEL, False)])
def test_a_failed_replay_of_a_plan_found_with_another_execution_model_says_so(tmp_path, capsys, model, noted):
    """A push amplifies any change in how motions are simulated: a plan of another model may
    fail here, and the failure then says why and what to do."""
    document = edited(lambda d: d.update(execution_model=model) if model is not None else None)
    step(document)["params"]["#grasp2"]["in_object"][0] = [0.0, 0.015, 0.3]     # the hand far off the block
    path = tmp_path / "plan.json"
    path.write_text(json.dumps(document))
    assert replay.main([PICK, str(path)]) == 1
    err = capsys.readouterr().err
    assert ("plan again to replay it here" in err) == noted, err
    if noted:
        assert f"model {model or 1}, and this version simulates motions with model {EXECUTION_MODEL}" in err
