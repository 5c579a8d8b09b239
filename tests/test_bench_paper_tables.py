"""`bench mechanisms` (Table 1) and `bench compose` (Table 2): the resumable trial store, the
same instances for every method, the tables in the paper's format, argument errors; one
slow end-to-end run of the CLI (plan, replay, resume)."""
import json
import os

import pytest

from pdsketch_mech.bench import compose, mechanisms
from pdsketch_mech.bench.__main__ import main
from pdsketch_mech.bench.trials import Job, Trial, TrialsError, TrialStore


def trial(task, method, index, status="solved", time_s=1.0, simulated=None):
    return Trial(task, method, index, f"{task}-test-{index}", index, status, time_s,
                 simulated=simulated if simulated is not None else {"grasp": 4})


def job(task, method, index):
    return Job(task, method, index, f"{task}-test-{index}", "(define ...)", "d.pddl")


def test_store_keeps_finished_trials_and_resume_skips_them(tmp_path):
    folder = str(tmp_path / "run")
    store = TrialStore(folder, {"timeout_s": 60.0}, resume=False)
    store.add(trial("edge", "macro", 0))
    with open(os.path.join(folder, "trials.jsonl"), "a") as handle:
        handle.write('{"task": "edge", "method": "macro", "ind')  # a kill in mid-line
    again = TrialStore(folder, {"timeout_s": 60.0}, resume=True)
    pending = again.pending([job("edge", "macro", 0), job("edge", "macro", 1), job("edge", "basis", 0)])
    assert [j.key for j in pending] == [("edge", "macro", 1), ("edge", "basis", 0)]
    assert again.trials[("edge", "macro", 0)].status == "solved"


def test_store_refuses_to_overwrite_or_mix_settings(tmp_path):
    folder = str(tmp_path / "run")
    TrialStore(folder, {"timeout_s": 60.0}, resume=False).add(trial("edge", "macro", 0))
    with pytest.raises(TrialsError, match="--resume"):
        TrialStore(folder, {"timeout_s": 60.0}, resume=False)
    with pytest.raises(TrialsError, match="timeout_s=60.0"):
        TrialStore(folder, {"timeout_s": 600.0}, resume=True)
    assert len(open(os.path.join(folder, "trials.jsonl")).readlines()) == 1  # nothing lost


def test_a_trial_records_its_checkout_and_a_table_says_which_commits_ran_it():
    from pdsketch_mech.bench.paper_commands import commits_line
    from pdsketch_mech.bench.trials import checkout_commit
    assert checkout_commit() == "" or checkout_commit()[:7].isalnum()   # this checkout, or not a git one
    same = [Trial("edge", "macro", i, "x", i, "solved", 1.0, commit="abc1234") for i in range(2)]
    assert commits_line(same) == "run at commit abc1234"
    resumed = same + [Trial("hook", "macro", 0, "x", 0, "solved", 1.0, commit="def5678-dirty")]
    assert commits_line(resumed) == "run at commit abc1234 (2 trials), def5678-dirty (1 trial)"


def test_every_method_plans_the_same_instances():
    jobs = mechanisms.instance_jobs("com", ["basis", "macro", "macro+sampler"], 2, 5, 60.0, "com.pddl")
    by_method = {}
    for j in jobs:
        by_method.setdefault(j.method, []).append((j.instance, j.problem_text, j.seed))
    assert len(by_method) == 3 and len({tuple(v) for v in by_method.values()}) == 1
    assert [i for i, _, _ in by_method["macro"]] == ["com-dev-5", "com-dev-6"]


def test_a_planner_seed_offset_plans_the_same_instances_with_other_seeds(tmp_path):
    plain = mechanisms.instance_jobs("com", ["macro"], 2, 5, 60.0, "com.pddl")
    shifted = mechanisms.instance_jobs("com", ["macro"], 2, 5, 60.0, "com.pddl", planner_seed_offset=100)
    assert [(j.instance, j.problem_text) for j in shifted] == [(j.instance, j.problem_text) for j in plain]
    assert [j.seed for j in plain] == [5, 6] and [j.seed for j in shifted] == [105, 106]
    # A run made before the option existed resumes with the default only.
    folder = tmp_path / "old"
    folder.mkdir()
    (folder / "config.json").write_text('{"kind": "mechanisms", "seed": 0, "timeout_s": 60.0}')
    with pytest.raises(TrialsError, match="planner_seed_offset=0"):
        TrialStore(str(folder), {"kind": "mechanisms", "seed": 0, "planner_seed_offset": 100, "timeout_s": 60.0},
                   resume=True)
    TrialStore(str(folder), {"kind": "mechanisms", "seed": 0, "planner_seed_offset": 0, "timeout_s": 60.0}, resume=True)


def test_table1_counts_unfinished_trials_at_the_limit_and_marks_a_lower_bound():
    column = mechanisms.BY_TASK["edge"]
    trials = [trial("edge", "macro", 0, time_s=10.0), trial("edge", "macro", 1, "unsolved", 99.0),
              trial("edge", "macro+sampler", 0, time_s=1.0, simulated={"grasp": 2}),
              trial("edge", "macro+sampler", 1, time_s=3.0, simulated={"grasp": 2})]
    header, rows, lines = mechanisms.table(trials, [column], ["macro", "macro+sampler"], timeout=60.0)
    assert header == ["method", "Edge"]
    assert rows[0] == ["Macro (ours)", ">35.00 ± 25.00 (med 35.00, 1/2)"]
    assert rows[1] == ["Macro (paper)", "8.34"]
    assert rows[2] == ["Macro+Sampler (ours)", "2.00 ± 1.00 (med 2.00, 2/2)"]
    assert any("2.0x fewer values" in line for line in lines)


def test_a_row_of_the_planners_own_time_when_the_trials_recorded_it():
    """The start-up is apart: a row of planning_s (unfinished trials at the limit), and none
    for trials stored before planning_s was recorded."""
    column = mechanisms.BY_TASK["com"]
    trials = [trial("com", "macro+sampler", 0, time_s=1.2), trial("com", "macro+sampler", 1, "unsolved", 61.0),
              trial("com", "macro", 0, time_s=1.1)]
    trials[0].planning_s, trials[1].planning_s = 0.5, 60.3
    header, rows, lines = mechanisms.table(trials, [column], ["macro", "macro+sampler"], timeout=60.0)
    assert [r[0] for r in rows] == ["Macro (ours)", "Macro (paper)", "Macro+Sampler (ours)",
                                    "Macro+Sampler (ours, planner alone)", "Macro+Sampler (paper)"]
    assert rows[3][1] == ">30.25 (med 30.25)"
    assert any(line.startswith("Macro+Sampler, planner alone: geometric mean 30.25 s") for line in lines)
    assert not any(line.startswith("Macro, planner alone") for line in lines)


def test_table1_says_when_nothing_finished_and_draws_the_paper_beside(tmp_path):
    column = mechanisms.BY_TASK["poking"]
    trials = [trial("poking", "basis", i, "unsolved", 60.0) for i in range(2)]
    _, rows, _ = mechanisms.table(trials, [column], ["basis"], timeout=60.0)
    assert rows == [["Basis only (ours)", ">60 (0/2)"], ["Basis only (paper)", ">600"]]
    png = tmp_path / "t.png"
    mechanisms.plot(trials, [column], ["basis"], 60.0, str(png), "t")
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_table2_reports_success_rates_and_the_paper_rates():
    trials = [trial("hook-slope", "macro+sampler", 0, time_s=12.0), trial("hook-slope", "macro+sampler", 1, "unsolved"),
              trial("hook-slope", "macro", 0, "invalid")]
    trials[-1].reason = "did not replay: goal not reached"
    header, rows, lines = compose.table(trials, [compose.BY_TASK["hook-slope"]], ["macro", "macro+sampler"])
    assert rows[0] == ["Macro (ours)", "0/1 (0 %)"] and rows[1] == ["Macro (paper)", "0 %"]
    assert rows[2] == ["Macro+Sampler (ours)", "1/2 (50 %), median 12.0 s"] and rows[3][1] == "90 %"
    assert any("did not replay" in line for line in lines)


def test_table2_draws_success_rates_beside_the_papers_and_every_runs_time(tmp_path):
    trials = [trial("hook-slope", "macro+sampler", 0, time_s=12.0), trial("hook-slope", "macro+sampler", 1, "unsolved"),
              trial("push-pick-hook", "macro", 0, time_s=40.0)]
    png = tmp_path / "t2.png"
    compose.plot(trials, list(compose.TABLE2), ["macro", "macro+sampler"], 60.0, str(png), "t")
    assert png.read_bytes()[:4] == b"\x89PNG" and png.stat().st_size > 10_000


def one_error_line(capsys, argv, expected):
    try:
        code = main(argv)
    except SystemExit as exit_:
        code = exit_.code
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: ") and err.count("\n") == 1, err
    assert expected in err


@pytest.mark.parametrize("argv, expected", [
    (["mechanisms", "--tasks", "edge,nosuch"], "unknown nosuch"),
    (["mechanisms", "--methods", "macro,fast"], "unknown fast"),
    (["compose", "--tasks", "hook-slope,nosuch"], "unknown nosuch"),
    (["mechanisms", "--mechanisms-dir", "/nonexistent"], "/nonexistent/edge.pddl: no such file"),
    (["compose", "--mechanisms-dir", "/nonexistent"], "no .pddl fragments"),
    (["mechanisms", "--trials", "0"], "--trials"),
])
def test_bad_arguments_get_one_line(capsys, argv, expected):
    one_error_line(capsys, argv, expected)


def test_results_of_another_run_are_not_overwritten(tmp_path, capsys):
    out = tmp_path / "run"
    TrialStore(str(out), {"kind": "mechanisms"}, resume=False).add(trial("com", "macro", 0))
    one_error_line(capsys, ["mechanisms", "--tasks", "com", "--out", str(out)], "--resume")


def test_table_only_shows_what_a_run_holds_and_plans_nothing(tmp_path, capsys, monkeypatch):
    out = tmp_path / "run"
    one_error_line(capsys, ["mechanisms", "--out", str(out), "--table-only"], "holds no trials")
    config = {"kind": "mechanisms", "seed": 0, "timeout_s": 600.0, "mechanisms_dir": "domains/mechanisms"}
    TrialStore(str(out), config, resume=False).add(trial("com", "macro", 0, time_s=2.0))

    def no_planning(*args, **kwargs):
        raise AssertionError("--table-only ran a trial")
    monkeypatch.setattr("pdsketch_mech.bench.trials.run_job", no_planning)
    assert main(["mechanisms", "--tasks", "edge,com", "--methods", "basis,macro", "--trials", "2", "--out", str(out),
                 "--table-only", "--quiet"]) == 0
    table = (out / "table.md").read_text()
    macro = next(line for line in table.splitlines() if line.startswith("| Macro (ours)"))
    assert macro.split(" | ")[1:] == ["-", "2.00 ± 0.00 (med 2.00, 1/1) |"]   # edge not run; com one of two
    assert "1 of 8 trials" in capsys.readouterr().err


@pytest.mark.slow
def test_table1_end_to_end_plans_replays_and_resumes(tmp_path, capsys):
    out = str(tmp_path / "t1")
    argv = ["mechanisms", "--tasks", "com", "--methods", "macro", "--trials", "1", "--timeout", "60", "--out", out,
            "--quiet"]
    assert main(argv) == 0
    results = json.load(open(os.path.join(out, "results.json")))
    (only,) = results["trials"]
    assert only["status"] == "solved" and only["instance"] == "com-dev-0" and sum(only["simulated"].values()) > 0
    assert 0 < only["planning_s"] < only["time_s"]  # the planner's own time, start-up apart
    assert os.path.getsize(os.path.join(out, "table.png")) > 0
    assert main(argv + ["--resume"]) == 0  # nothing left to run: the same table from the store
    assert "0 to run" in capsys.readouterr().err


def test_every_column_is_a_task_with_a_shipped_mechanism():
    from pdsketch_mech.envs.tasks import TASKS
    from conftest import ROOT
    for column in mechanisms.TABLE1:
        assert column.task in TASKS
        assert os.path.isfile(mechanisms.fragment_of(column, os.path.join(ROOT, "domains", "mechanisms")))
    assert all(c.task in TASKS for c in compose.TABLE2)


@pytest.mark.slow
def test_the_ray_backend_gives_the_trials_the_local_one_gives():
    pytest.importorskip("ray")
    from conftest import ROOT
    from pdsketch_mech.bench.trials import execute
    jobs = mechanisms.instance_jobs("com", ["macro"], 1, 3, 60.0, os.path.join(ROOT, "domains", "mechanisms", "com.pddl"))
    (local,) = execute(jobs, 1, "local")
    (remote,) = execute(jobs, 1, "ray")
    assert local.status == remote.status == "solved"
    assert (local.simulated, local.proposals, local.steps) == (remote.simulated, remote.proposals, remote.steps)


def test_all_mechanisms_row_plans_the_same_instances_with_every_fragment(monkeypatch, tmp_path, capsys):
    """Table 1's fourth row: the basis domain with every committed fragment, on the instances
    and planner seeds of the task's own mechanism; dev unless --split test, which says what
    test is for."""
    from pdsketch_mech.bench import paper_commands
    seen = []
    monkeypatch.setattr(paper_commands, "_run", lambda args, jobs, kind: seen.extend(jobs) or [])
    monkeypatch.setattr(mechanisms, "plot", lambda *a, **k: None)
    monkeypatch.setattr(paper_commands, "_write", lambda *a, **k: None)
    main(["mechanisms", "--tasks", "com", "--methods", "macro+sampler,all-mechanisms", "--trials", "2",
          "--out", str(tmp_path / "t"), "--quiet"])
    own = [j for j in seen if j.method == "macro+sampler"]
    every = [j for j in seen if j.method == "all-mechanisms"]
    assert [(j.instance, j.seed, j.problem_text) for j in own] == [(j.instance, j.seed, j.problem_text) for j in every]
    assert own[0].instance == "com-dev-0" and own[0].domain.endswith("com.pddl") and not own[0].mechanisms
    assert every[0].domain.endswith("basis.pddl") and len(every[0].mechanisms) >= 6
    assert "test split" not in capsys.readouterr().err
    seen.clear()
    main(["mechanisms", "--tasks", "com", "--methods", "macro", "--trials", "1", "--split", "test",
          "--out", str(tmp_path / "u"), "--quiet"])
    from pdsketch_mech.envs import TASKS, sample
    assert seen[0].problem_text == sample(TASKS["com"], "test", 0).problem_text()
    assert "note: the test split is for reported tables only" in capsys.readouterr().err
