"""`python -m pdsketch_mech.plan` on classical PDDL: output format, exit codes, JSON, limits;
and the hint an unsolved manipulation problem gets (which step failed, and how)."""
import json
import os
import re
import subprocess
import sys
import time

import pytest

from pdsketch_mech.commands import plan
from pdsketch_mech.planner.failure_hint import failed_steps, failure_hint

from conftest import DATA, ROOT
from test_symbolic import CORRIDOR, corridor_problem

LOGISTICS = os.path.join(DATA, "ipc", "logistics00")


def run_plan(capsys, *args):
    status = plan.main(list(args))
    captured = capsys.readouterr()
    return status, captured.out.splitlines(), captured.err.strip().splitlines()


def test_solved_plan_is_printed_one_action_a_line(write_files, capsys):
    domain, problem = write_files(**{"d.pddl": CORRIDOR, "p.pddl": corridor_problem(goal="(carrying k)")})
    status, out, err = run_plan(capsys, domain, problem, "--validate")
    assert status == 0
    assert out == ["(move r0 r1)", "(pick k r1)"]
    assert err[0].startswith("solved: 2 steps in ")
    assert err[1] == "validate: plan valid: 2 steps reach the goal"


def test_unsolvable_exits_1(write_files, capsys):
    cut = corridor_problem(goal="(at r3)").replace("(adj r2 r3) (adj r3 r2)", "")
    domain, problem = write_files(**{"d.pddl": CORRIDOR, "p.pddl": cut})
    status, out, err = run_plan(capsys, domain, problem)
    assert (status, out) == (1, [])
    assert err[0].startswith("unsolved: no plan exists in ")


def test_bad_input_exits_2_with_one_line(write_files, capsys):
    text = corridor_problem(goal="(carrying k r1)")
    domain, problem = write_files(**{"d.pddl": CORRIDOR, "p.pddl": text})
    status, out, err = run_plan(capsys, domain, problem)
    assert (status, out) == (2, [])
    column = text.index("(carrying k r1)") + 1
    assert err == [f"{problem}:1:{column}: error: predicate 'carrying' takes 1 argument, got 2"]


def test_json_output(tmp_path, capsys):
    out_file = tmp_path / "plan.json"
    status, out, _ = run_plan(capsys, os.path.join(LOGISTICS, "domain.pddl"),
                              os.path.join(LOGISTICS, "problem01.pddl"), "--json", str(out_file), "--seed", "7")
    document = json.loads(out_file.read_text())
    assert status == 0 and document["status"] == "solved" and document["seed"] == 7
    assert [f"({' '.join([s['name']] + s['args'])})" for s in document["plan"]] == out
    assert all(step["params"] == {} for step in document["plan"])
    assert document["stats"]["skeletons"] == 1 and document["stats"]["expansions"] > 0
    assert isinstance(document["time_s"], float)


def test_same_seed_same_plan(capsys):
    args = [os.path.join(DATA, "ipc", "depot", "domain.pddl"), os.path.join(DATA, "ipc", "depot", "task03.pddl")]
    (status, plan, _), (_, again, _) = (run_plan(capsys, *args, "--seed", "3") for _ in range(2))
    assert status == 0 and plan and again == plan


def test_timeout_is_honoured(capsys):
    start = time.perf_counter()
    status, out, err = run_plan(capsys, os.path.join(LOGISTICS, "domain.pddl"),
                                os.path.join(LOGISTICS, "problem03.pddl"), "--search", "wastar",
                                "--weight", "1", "--timeout", "0.5")
    assert (status, out) == (1, [])
    assert err[0].startswith("unsolved: timed out")
    assert time.perf_counter() - start < 5  # generous: the limit is 0.5 s, checked every expansion


def test_skeletons_of_a_stream_domain(capsys):
    basis, problem = os.path.join(ROOT, "domains", "basis.pddl"), os.path.join(ROOT, "problems", "hook-use.pddl")
    status, out, _ = run_plan(capsys, basis, problem, "--skeletons", "2")
    assert status == 0 and out[0] == "1: (grasp box table #grasp3 #traj4)" and len(out) == 2


def test_stream_domain_needs_a_scene(write_files, capsys):
    basis = os.path.join(ROOT, "domains", "basis.pddl")
    text = open(os.path.join(ROOT, "problems", "pick.pddl")).read()
    text = text[: text.index("  (:scene")].rstrip() + ")\n"
    (problem,) = write_files(**{"p.pddl": text})
    status, out, err = run_plan(capsys, basis, problem)
    assert (status, out) == (2, [])
    assert len(err) == 1 and err[0].startswith(f"{problem}:2:1: error: problem 'pick-block' has no :scene")


def test_command_line_closes_quietly_on_a_closed_pipe():
    command = (f"{sys.executable} -m pdsketch_mech.plan {LOGISTICS}/domain.pddl {LOGISTICS}/problem02.pddl"
               " | head -1")
    result = subprocess.run(command, shell=True, capture_output=True, text=True, cwd=ROOT)
    assert result.stdout.count("\n") == 1 and "Traceback" not in result.stderr


BASIS = os.path.join(ROOT, "domains", "basis.pddl")
OUT_OF_REACH = """(define (problem far) (:domain mech-basis)
  (:objects table box - item)
  (:init (handempty) (fixed table) (support box table))
  (:goal (holding box))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (box :asset "box/0" :position (1.0 0 0.031) :on table)))
"""


def test_unsolved_run_names_the_step_that_cannot_be_done_and_suggests_a_mechanism(write_files, capsys, tmp_path):
    (problem,) = write_files(**{"far.pddl": OUT_OF_REACH})
    out = tmp_path / "far.json"
    status, _, err = run_plan(capsys, BASIS, problem, "--timeout", "60", "--json", str(out))
    assert status == 1 and len(err) == 2 and err[0].startswith("unsolved: ")
    assert re.fullmatch(r"hint: never feasible where its objects start: grasp box table \(0 of [1-9]\d* grasp "
                        r"proposals feasible\), transit-cont box table \(0 of [1-9]\d* contact proposals feasible\); "
                        r"a mechanism \(--mechanisms all\) may help", err[1]), err[1]
    stats = json.loads(out.read_text())["stats"]
    assert stats["hint"] == err[1].removeprefix("hint: ")
    grasp = stats["failed_steps"]["grasp box table"]
    assert grasp["dead"] and grasp["why"] == {"no feasible parameters": grasp["failures"]}
    assert grasp["proposals"]["grasp"]["feasible"] == 0


def test_the_hint_names_the_commonest_failure_and_what_its_samplers_let_through():
    failures = {("place hook box", "no feasible parameters"): 45, ("place hook box", "no straight retreat"): 8,
                ("grasp hook table", "no feasible parameters"): 12, ("grasp hook table", "no straight lift"): 50}
    verified = {("place hook box", "placement", False): [5000, 100], ("place hook box", "placement", True): [3, 0],
                ("place hook box", "place-motion", False): [100, 80],
                ("grasp hook table", "grasp", True): [97, 91]}
    failed = failed_steps(failures, verified)
    assert list(failed) == ["grasp hook table", "place hook box"]   # by the commonest single reason
    assert failed["place hook box"]["proposals"]["placement"] == {"verified": 5003, "feasible": 100}
    assert failure_hint(failed, mechanisms=True) == (
        "most failures: grasp hook table (no straight lift, 50 times), then place hook box (no feasible "
        "parameters, 45 times: 100 of 5003 placement proposals feasible)")


def test_a_dead_step_counts_only_the_proposals_where_its_objects_start():
    verified = {("grasp box table", "grasp", True): [57, 0], ("grasp box table", "grasp", False): [40, 6],
                ("grasp box table", "grasp-motion", False): [6, 6]}
    failed = failed_steps({("grasp box table", "no feasible parameters"): 5}, verified, dead=["grasp box table"])
    assert failed["grasp box table"]["proposals"] == {"grasp": {"verified": 57, "feasible": 0}}
    assert failure_hint(failed, mechanisms=False) == ("never feasible where its objects start: grasp box table "
                                                      "(0 of 57 grasp proposals feasible); a mechanism "
                                                      "(--mechanisms all) may help")
    # A fragment loaded but set aside by --basis-only is named, not "all" of the shipped ones.
    assert failure_hint(failed, mechanisms=False, set_aside=["chain-push"]).endswith(
        "planned without chain-push (--basis-only): with it, it may solve")
    assert failure_hint({}, mechanisms=True) is None


def test_the_commonest_failure_is_named_even_when_dead_steps_fill_the_hint():
    contacts = "simulated contacts differ from the skeleton"
    failures = {("grasp target slope", "no feasible parameters"): 3, ("transit-cont target slope", "no feasible parameters"): 2,
                ("grasp chock slope", contacts): 244}
    failed = failed_steps(failures, {}, dead=["grasp target slope", "transit-cont target slope"])
    assert failure_hint(failed, mechanisms=True).endswith(f"most failures: grasp chock slope ({contacts}, 244 times)")


def test_the_hint_says_when_a_mechanism_whose_promise_keeps_failing_got_in_the_way():
    why = "its :certified facts do not hold after its steps"
    failures = {("shelf-pull stick block table", why): 48, ("grasp block table", "no feasible parameters"): 9}
    failed = failed_steps(failures, {})
    crowded = {"shelf-pull": {"skeletons": 41, "of": 44, "certified_failed": 48}}
    hint = failure_hint(failed, mechanisms=True, by_mechanism=crowded)
    assert hint.startswith("mechanism 'shelf-pull' got in the way: its certified facts failed 48 times, "
                           "in 41 of 44 skeletons; plan without it")
    # a mechanism whose promise failed less often than a step failed otherwise is not named
    quiet = {"shelf-pull": {"skeletons": 2, "of": 44, "certified_failed": 3}}
    assert "got in the way" not in failure_hint(failed_steps({("shelf-pull stick block table", why): 3,
                                                               ("grasp block table", "no straight lift"): 30}, {}),
                                                  mechanisms=True, by_mechanism=quiet)


def test_plan_render_takes_the_camera_options(capsys):
    with pytest.raises(SystemExit) as exited:
        plan.main([BASIS, os.path.join(ROOT, "problems", "pick.pddl"), "--render", "x.gif", "--pitch", "nan"])
    captured = capsys.readouterr()
    assert (exited.value.code, captured.out) == (2, "")
    assert captured.err == "error: argument --pitch: must be a finite number, got 'nan'\n"
    args = plan._parser().parse_args([BASIS, "pick", "--render", "x.gif", "--yaw", "90", "--distance", "1.2"])
    assert (args.yaw, args.pitch, args.distance) == (90.0, -35.0, 1.2)


def test_all_takes_a_users_fragment_beside_the_shipped_ones(tmp_path):
    """`--mechanisms all my-trick.pddl`: every shipped fragment and the user's, each once."""
    from pdsketch_mech.learning.paths import resolve_mechanisms, shipped_mechanisms
    mine = tmp_path / "my-trick.pddl"
    mine.write_text("; a user's fragment\n")
    files = resolve_mechanisms(["all", str(mine), "edge"])
    assert len(files) == len(shipped_mechanisms()) + 1 and files[-1] == str(mine)
    assert [os.path.basename(f)[:-5] for f in files[:-1]] == shipped_mechanisms()
