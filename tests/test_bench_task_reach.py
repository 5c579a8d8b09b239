"""`bench task` and `bench reach`: argument errors, the pinned-asset instances, the skeleton
matcher and the tables, on canned planner output (no planning, except the slow test)."""
import json
import math
import os
import subprocess
import sys

import pytest

from pdsketch_mech.bench import reach, tasks
from pdsketch_mech.bench.__main__ import main
from pdsketch_mech.bench.plans import Run, make_run, RunOutcome, skeleton_ops, solving_rank
from pdsketch_mech.envs.tasks import TASKS

from conftest import ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")
HOOK_PROBLEM = os.path.join(ROOT, "problems", "hook-use.pddl")
PICK_PROBLEM = os.path.join(ROOT, "problems", "pick.pddl")


def one_error_line(capsys, argv, expected):
    """`bench ARGV` exits 2 with one `error:` line containing `expected`."""
    try:
        code = main(argv)
    except SystemExit as exit_:  # argparse's own errors
        code = exit_.code
    err = capsys.readouterr().err
    assert code == 2
    assert err.startswith("error: ") and err.count("\n") == 1, err
    assert expected in err


@pytest.mark.parametrize("argv, expected", [
    (["task", "nosuch", "--vary", "tool=spoon/0"], "unknown task 'nosuch'"),
    (["task", "hook", "--vary", "tool"], "expected ROLE=ASSET"),
    (["task", "hook", "--vary", "tool="], "expected ROLE=ASSET"),
    (["task", "hook", "--vary", "tool=spoon/0,spoon/0"], "named twice"),
    (["task", "hook", "--vary", "handle=spoon/0"], "has no object 'handle'"),
    (["task", "hook", "--vary", "tool=spoon/9"], "unknown asset 'spoon/9'"),
    (["task", "hook", "--vary", "tool=spoon/0", "--gif"], "add --keep DIR"),
    (["task", "hook", "--vary", "tool=spoon/0", "--seeds", "0"], "--seeds"),
    (["task", "hook", "--vary", "tool=spoon/0", "--timeout", "-1"], "--timeout"),
    (["task", "hook", "--vary", "tool=spoon/0", "--json", "out.txt"], "must end in .json"),
    (["task", "hook", "--vary", "tool=spoon/0", "--domain", "missing.pddl"], "missing.pddl: no such file"),
    (["task", "hook"], "--vary"),
    (["reach", BASIS, HOOK_PROBLEM], "--skeleton"),
    (["reach", BASIS, HOOK_PROBLEM, "--skeleton", "grasp mve"], "'mve' is not an operator"),
    (["reach", BASIS, HOOK_PROBLEM, "--skeleton", "(grasp hammer table)"], "'hammer' is not an object"),
    (["reach", BASIS, HOOK_PROBLEM, "--skeleton", "  "], "no operators given"),
    (["reach", BASIS, HOOK_PROBLEM, "--skeleton", "grasp", "--enumerate", "-1"], "--enumerate"),
    (["reach", BASIS, "missing.pddl", "--skeleton", "grasp"], "missing.pddl: no such file"),
])
def test_bad_arguments_exit_2_with_one_line(capsys, argv, expected):
    one_error_line(capsys, argv, expected)


def test_keep_under_a_missing_folder_is_refused(capsys, tmp_path):
    one_error_line(capsys, ["task", "hook", "--vary", "tool=spoon/0", "--keep", str(tmp_path / "a" / "b")],
                   "does not exist")


def test_unparsable_domain_is_a_located_error(capsys, tmp_path):
    bad = tmp_path / "bad.pddl"
    bad.write_text("(define (domain x) (:action")
    assert main(["reach", str(bad), HOOK_PROBLEM, "--skeleton", "grasp"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(str(bad) + ":") and err.count("\n") == 1


def test_bad_arguments_from_the_command_line():
    done = subprocess.run([sys.executable, "-m", "pdsketch_mech.bench", "task", "hook", "--vary", "tool=nothing/0"],
                          capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr.startswith("error: --vary tool: unknown asset 'nothing/0'") and done.stderr.count("\n") == 1


# ----------------------------------------------------------------------------- instances
def test_parse_vary():
    assert tasks.parse_vary("tool=l-stick/0, spoon/0") == ("tool", ("l-stick/0", "spoon/0"))


@pytest.mark.parametrize("task, role, asset", [("hook", "tool", "spoon/0"), ("hook", "tool", "caliper/0"),
                                               ("edge", "flat", "caliper/0"), ("edge", "flat", "document/0")])
def test_pinned_instance_uses_the_asset_at_scale_1_without_distractors(task, role, asset):
    spec = next(o for o in TASKS[task].objects if o.name == role)
    for seed in range(5):
        instance = tasks.pinned_instance(task, role, asset, seed)
        placed = instance.object(role)
        assert placed.asset == asset and placed.scale == 1.0
        assert [o.name for o in instance.objects] == [o.name for o in TASKS[task].objects]  # no distractors
        # +-5 cm / +-15 degrees about the canonical pose (the caliper's canonical yaw is per category)
        assert abs(placed.position[0] - spec.xy[0]) <= 0.05 + 1e-9
        assert abs(placed.position[1] - spec.xy[1]) <= 0.05 + 1e-9
        delta = (placed.yaw - spec.canonical_yaw(asset) + 180) % 360 - 180
        assert abs(delta) <= 15 + 1e-9


def test_pinned_problem_is_deterministic_and_named_for_its_asset():
    a = tasks.pinned_problem_text("hook", "tool", "soup-ladle/0", 3)
    assert a == tasks.pinned_problem_text("hook", "tool", "soup-ladle/0", 3)
    assert a != tasks.pinned_problem_text("hook", "tool", "soup-ladle/0", 4)
    assert "(define (problem hook-soup-ladle-0-3)" in a and '(tool :asset "soup-ladle/0"' in a
    assert "--vary tool=soup-ladle/0` (seed 3)" in a.split("\n")[1]
    # The other objects' poses do not depend on which asset is pinned (the same draws).
    b = tasks.pinned_problem_text("hook", "tool", "hammer/0", 3)
    target = [line for line in a.split("\n") if line.strip().startswith("(target ")]
    assert target == [line for line in b.split("\n") if line.strip().startswith("(target ")]


def test_pinned_problem_loads(tmp_path):
    from pdsketch_mech.lang.loader import load_domain, load_problem

    path = tmp_path / "p.pddl"
    path.write_text(tasks.pinned_problem_text("edge", "flat", "caliper/0", 0))
    _, problem = load_problem(str(path), [load_domain([BASIS])])
    assert problem.name == "edge-caliper-0-0"


# ----------------------------------------------------------------------------- skeletons
LOG = [
    {"rank": 1, "created_s": 0.01, "skeleton": "(grasp box table #grasp3 #traj4)"},
    {"rank": 2, "created_s": 0.9, "skeleton": "(transit-cont box table #contact9 #traj34) (grasp box table #grasp3 #traj4)"},
    {"rank": 26, "created_s": 14.2, "skeleton": "(grasp hook table #grasp2 #traj3) (move-cont hook box table #contact25 "
                                                "#traj41) (place hook table #placement4 #traj8) (grasp box table #grasp3 #traj4)"},
    {"rank": 27, "created_s": 15.0, "skeleton": "(grasp hook table #grasp2 #traj3) (move-cont hook box table #contact25 "
                                                "#traj41) (place hook box #placement5 #traj9) (grasp box table #grasp3 #traj4)"},
]


def test_skeleton_ops_drop_placeholders():
    assert skeleton_ops("grasp move-cont") == [("grasp", ()), ("move-cont", ())]
    assert skeleton_ops("(grasp hook table #g1 #t1) (place hook box)") == [("grasp", ("hook", "table")),
                                                                          ("place", ("hook", "box"))]


@pytest.mark.parametrize("pattern, rank", [
    ("grasp", 1),
    ("grasp move-cont place grasp", 26),
    ("(grasp hook table) (move-cont hook box table) (place hook box) (grasp box table)", 27),
    ("(grasp hook table #grasp2 #traj3) (move-cont hook box table) (place hook table) (grasp box table)", 26),
    ("transit-cont grasp", 2),
    ("grasp move-cont place", None),           # a prefix is not a match
    ("(grasp box)", None),                     # arguments must agree exactly
    ("grasp grasp", None),
])
def test_first_match(pattern, rank):
    reached = reach.first_match(pattern, LOG)
    assert reached.rank == rank
    if rank is not None:
        assert reached.created_s == next(e["created_s"] for e in LOG if e["rank"] == rank)


def test_solving_rank_basis_and_mechanism_plans():
    plan = [{"name": "grasp", "args": ["hook", "table", "#grasp2", "#traj3"], "mechanism": None},
            {"name": "move-cont", "args": ["hook", "box", "table", "#contact25", "#traj41"], "mechanism": None},
            {"name": "place", "args": ["hook", "table", "#placement4", "#traj8"], "mechanism": None},
            {"name": "grasp", "args": ["box", "table", "#grasp3", "#traj4"], "mechanism": None}]
    assert solving_rank({"plan": plan, "stats": {"skeleton_log": LOG}}) == 26
    macro = [dict(step, mechanism="hook-use") for step in plan]
    log = LOG[:2] + [{"rank": 3, "created_s": 1.0, "skeleton": "(hook-use hook box table)"}]
    assert solving_rank({"plan": macro, "stats": {"skeleton_log": log}}) == 3
    assert solving_rank({"plan": plan[:1], "stats": {"skeleton_log": LOG[1:]}}) is None
    assert solving_rank({"plan": plan, "stats": {"solved_rank": 9, "skeleton_log": LOG}}) == 9


def test_make_run_from_a_crash_and_from_a_document():
    crashed = make_run("p.pddl", "d.pddl", 0, RunOutcome({}, None, "Traceback...\nkilled after 90 s"))
    assert crashed.status == "crashed" and crashed.reason == "killed after 90 s" and math.isnan(crashed.time_s)
    document = {"status": "unsolved", "reason": "timed out after 10.0 s", "time_s": 10.2, "plan": [],
                "stats": {"skeletons": 30, "refined": 29, "pruned": 4, "rejected": 1, "samples": {"grasp": 7},
                          "failures": {"grasp: no IK": 5}, "skeleton_log": LOG}}
    run = make_run("p.pddl", "d.pddl", 1, RunOutcome(document, 1, ""))
    assert (run.status, run.skeletons, run.refined, run.pruned, run.rejected, run.rank) == ("unsolved", 30, 29, 4, 1, None)
    assert run.samples == {"grasp": 7} and run.failures == {"grasp: no IK": 5}


def _run(label, seed, status, time_s, rank=None, **stats):
    return Run("p", "d", seed, status, time_s, {"grasp": 10 * (seed + 1)}, 4, stats.get("skeletons", 10),
               stats.get("refined", 9), stats.get("pruned", 2), 0, rank, stats.get("reason", ""),
               stats.get("replay", ""), 0, stats.get("failures", {}), label)


def test_task_table_rows_totals_and_failures():
    runs = [_run("spoon/0", 0, "solved", 30.0, 26), _run("spoon/0", 1, "solved", 50.0, 27),
            _run("spoon/0", 2, "unsolved", 120.3, reason="timed out after 120.0 s", failures={"contact: no IK": 12}),
            _run("hammer/0", 0, "invalid", 40.0, 26, replay="replay: step 2 (move-cont) failed")]
    header, rows, lines = tasks.table(runs)
    assert header[:4] == ["asset", "solved", "median s", "max s"]
    assert rows[0][:6] == ["spoon/0", "2/3", "40.0", "50.0", "10.0/9.0/2.0", "26,27"]
    assert rows[0][6] == "grasp 20"
    assert rows[1][:4] == ["hammer/0", "0/1", "-", "-"]
    assert lines[0] == "total: 2/4 solved, median 40.0 s, max 50.0 s over solved runs; 1 plan that did not replay"
    assert "spoon/0 seed 2: unsolved: timed out after 120.0 s; most frequent failure (12x): contact: no IK" in lines
    assert "hammer/0 seed 0: invalid: replay: step 2 (move-cont) failed" in lines


def test_reach_table():
    pattern = "grasp move-cont place grasp"
    items = [reach.ReachRun(_run("", 0, "solved", 33.0, 26), [reach.first_match(pattern, LOG)], 15.0),
             reach.ReachRun(_run("", 1, "unsolved", 60.0), [reach.first_match(pattern, LOG[:2])], 0.9)]
    header, rows, lines = reach.table(items, [pattern], ({pattern: 26}, 26))
    assert header[:3] == ["seed", "A: rank", "A: created s"]
    assert rows[0][:3] == ["0", "26", "14.2"] and rows[0][-3:] == ["solved", "33.0", "26"]
    assert rows[1][:3] == ["1", "-", "-"]
    assert lines[0] == f"A = {pattern}: created in 1/2 runs, at 14.2 s; enumerated as skeleton #26"


def test_enumeration_rank_of_the_hook_tool_use_skeleton():
    """The symbolic order alone (no sampling): where the planner will create it."""
    pattern = "(grasp hook table) (move-cont hook box table) (place hook table) (grasp box table)"
    found, count = reach.enumeration_rank([pattern, "grasp grasp"], BASIS, HOOK_PROBLEM, True, 40, 30.0)
    assert found[pattern] is not None and found[pattern] <= count <= 40
    assert found["grasp grasp"] is None


# ----------------------------------------------------------------------------- end to end
@pytest.mark.slow
def test_reach_and_task_end_to_end(tmp_path, capsys):
    out = tmp_path / "reach.json"
    assert main(["reach", BASIS, PICK_PROBLEM, "--skeleton", "grasp", "--seeds", "1", "--timeout", "30",
                 "--json", str(out), "--enumerate", "5"]) == 0
    data = json.loads(out.read_text())
    [run] = data["runs"]
    assert run["status"] == "solved" and run["replay"] == "ok" and run["reached"][0]["rank"] == 1
    assert data["enumeration_rank"] == {"grasp": 1}
    capsys.readouterr()
    # A run cut short by a tiny timeout: reported, not solved, the problem and JSON kept.
    keep = tmp_path / "kept"
    assert main(["task", "edge", "--vary", "flat=calculator/0", "--seeds", "1", "--timeout", "3", "--basis-only",
                 "--keep", str(keep), "--json", str(tmp_path / "task.json")]) == 0
    assert "calculator/0" in capsys.readouterr().out
    assert sorted(os.listdir(keep)) == ["edge-calculator-0-seed0.json", "edge-calculator-0-seed0.pddl"]
    [run] = json.loads((tmp_path / "task.json").read_text())["runs"]
    assert run["status"] in ("unsolved", "solved") and run["label"] == "calculator/0"
