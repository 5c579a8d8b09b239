"""`bench contract`: the contract's arithmetic (time <= 1.5 x basis + 5 s, solved), its table and
summary, the configs it plans, the fragments it finds, the store's extra fields. No planning."""
import json
import os

import pytest

from pdsketch_mech.bench import contract, contract_report
from pdsketch_mech.bench.contract import ContractStore, ContractTrial, ContractError


def trial(problem, config, status="solved", time_s=1.0, simulated=None, executions=0, certified=0):
    return ContractTrial(problem, config, 0, problem, 0, status, time_s,
                         simulated=simulated if simulated is not None else {"grasp": 2},
                         executions=executions, certified_failures=certified)


def test_the_limit_is_one_and_a_half_times_basis_plus_five_seconds():
    assert contract_report.limit_s(10.0) == pytest.approx(20.0)
    assert contract_report.limit_s(0.0) == pytest.approx(5.0)
    basis = trial("p", "basis", time_s=10.0)
    assert contract_report.verdict(trial("p", "all", time_s=20.0), basis).meets is True        # at the limit
    assert contract_report.verdict(trial("p", "all", time_s=20.01), basis).meets is False
    assert contract_report.verdict(trial("p", "all", time_s=4.0), basis).ratio == pytest.approx(0.4)
    unsolved = contract_report.verdict(trial("p", "all", "unsolved", 120.0), basis)
    assert unsolved.meets is False and unsolved.ratio is None
    assert contract_report.verdict(trial("p", "all", "invalid", 3.0), basis).meets is False    # did not replay
    # A problem the basis operators did not solve is outside the contract: not counted.
    free = contract_report.verdict(trial("p", "all", time_s=3.0), trial("p", "basis", "unsolved", 120.0))
    assert free.meets is None and not free.counted and free.limit_s is None


def test_the_table_marks_the_pairs_that_break_it_and_counts_per_problem():
    trials = [trial("a", "basis", time_s=2.0), trial("a", "+edge", time_s=7.5), trial("a", "all", time_s=8.5),
              trial("b", "basis", time_s=10.0), trial("b", "+edge", "unsolved", 120.0), trial("b", "all", time_s=12.0),
              trial("c", "basis", "unsolved", 120.0), trial("c", "+edge", time_s=5.0)]
    header, rows, lines = contract_report.table(trials, ["a", "b", "c"], ["basis", "+edge", "all"], 120.0)
    assert header == ["problem", "basis s", "limit s", "+edge", "all", "meets"]
    assert rows[0] == ["a", "2.00", "8.00", "7.50", "8.50 !", "1/2"]
    assert rows[1] == ["b", "10.00", "20.00", "unsolved !", "12.00", "1/2"]
    assert rows[2] == ["c", "unsolved", "-", "5.00", "-", contract_report.NOT_COUNTED]
    assert lines[0].startswith("contract: 2/4 config x problem pairs keep it (2 configs x 2 problems")
    assert "worst ratio 4.25x (a, all: 8.50 s against 2.00 s)" in lines[0] and "1 unsolved" in lines[0]
    assert any(line.startswith("not counted") and line.endswith(": c") for line in lines)
    assert "breaks: a all: 8.50 s > 8.00 s (4.25x)" in lines
    assert any(line.startswith("breaks: b +edge: unsolved") for line in lines)


def test_the_summary_compares_values_simulated_and_counts_certified_failures():
    trials = [trial("a", "basis", simulated={"grasp": 4}), trial("a", "+m", simulated={"grasp": 8}, certified=3),
              trial("b", "basis", simulated={"grasp": 10}), trial("b", "+m", simulated={"grasp": 5, "place": 5}),
              trial("c", "basis", "unsolved", 120.0), trial("c", "+m", "unsolved", 120.0, certified=4)]
    summary = contract_report.summarize(trials, ["+m"])
    assert summary["pairs"] == 2 and summary["met"] == 2 and summary["unsolved"] == 0
    assert summary["per_config"]["+m"]["values_ratio_geomean"] == pytest.approx(2 ** 0.5)   # 2x and 1x
    assert summary["per_config"]["+m"]["certified_failures"] == 7   # c's too, though c is not counted
    header, rows = contract_report.values_table(trials, ["a", "b"], ["basis", "+m"])
    assert rows == [["a", "4 (0)", "8 (0)"], ["b", "10 (0)", "10 (0)"]]


def test_configs_put_basis_first_and_expand_each_and_all():
    fragments = [("edge", "m/edge.pddl"), ("hook-use", "m/hook-use.pddl")]
    got = contract.configs("each,all", fragments)
    assert [c.name for c in got] == ["basis", "+edge", "+hook-use", "all"]
    assert got[0].extra == ("--basis-only",)
    assert got[1].extra == ("--mechanisms", "m/edge.pddl")
    assert got[3].extra == ("--mechanisms", "m/edge.pddl", "m/hook-use.pddl")
    assert [c.name for c in contract.configs("basis,hook-use,+hook-use", fragments)] == ["basis", "+hook-use"]
    with pytest.raises(ContractError, match="unknown hok"):
        contract.configs("basis,hok", fragments)


def test_fragments_are_domain_files_and_problems_are_the_others(tmp_path):
    mech = tmp_path / "mech"
    mech.mkdir()
    (mech / "push.mech.pddl").write_text('; a fragment\n(define (domain push)\n  (:extends "basis"))\n')
    (mech / "push.pddl").write_text("(define (problem push) (:domain mech-basis))\n")   # the demo's scene
    assert contract.fragments_in([str(mech)]) == [("push", str(mech / "push.mech.pddl"))]
    assert contract.problems_in(str(mech)) == [("push", str(mech / "push.pddl"))]
    with pytest.raises(ContractError, match="no such folder"):
        contract.fragments_in([str(tmp_path / "nowhere")])
    shipped = dict(contract.fragments_in([os.path.join(os.path.dirname(__file__), "..", "domains", "mechanisms")]))
    assert {"edge", "hook-use", "gap-push"} <= set(shipped)


def test_the_store_keeps_what_a_trial_simulated_and_resume_skips_it(tmp_path):
    folder = str(tmp_path / "run")
    store = ContractStore(folder, {"kind": "contract", "timeout_s": 60.0}, resume=False)
    store.add(trial("a", "basis", executions=7, certified=2))
    with open(os.path.join(folder, "trials.jsonl"), "a") as handle:
        handle.write('{"task": "a", "method": "all", "ind')   # a kill in mid-line
    again = ContractStore(folder, {"kind": "contract", "timeout_s": 60.0}, resume=True)
    kept = again.trials[("a", "basis", 0)]
    assert isinstance(kept, ContractTrial) and kept.executions == 7 and kept.certified_failures == 2
    jobs = contract.jobs_of([("a", __file__)], contract.configs("all", [("m", "m.pddl")]), "basis.pddl", 0, 60.0)
    assert [j.key for j in again.pending(jobs)] == [("a", "all", 0)]
    assert json.loads(open(os.path.join(folder, "trials.jsonl")).readline())["executions"] == 7


def test_bad_input_is_one_error_line_and_exit_2(tmp_path, capsys):
    from pdsketch_mech.bench.__main__ import main
    root = os.path.join(os.path.dirname(__file__), "..")
    problems = os.path.join(root, "problems", "contract")
    mechanisms = os.path.join(root, "domains", "mechanisms")
    out = str(tmp_path / "out")
    assert main(["contract", "--problems", str(tmp_path / "none"), "--out", out]) == 2
    assert "--problems" in capsys.readouterr().err
    assert main(["contract", "--problems", problems, "--mechanisms-dir", mechanisms, "--configs", "basis,hok",
                 "--out", out]) == 2
    assert "unknown hok" in capsys.readouterr().err
    assert main(["contract", "--problems", problems, "--mechanisms-dir", mechanisms, "--only", "nope",
                 "--out", out]) == 2
    assert "no problem nope" in capsys.readouterr().err
    assert not os.path.exists(out)   # nothing written before the input is checked


def test_the_shipped_set_holds_at_least_twenty_problems_and_the_user_fragment_is_found():
    root = os.path.join(os.path.dirname(__file__), "..", "problems", "contract")
    assert len(contract.problems_in(root)) >= 20
    assert [name for name, _ in contract.fragments_in([os.path.join(root, "user-mechanism")])] == ["shelf-pull"]


def test_table_only_renders_a_folder_of_trials_and_refuses_an_empty_one(tmp_path, capsys):
    """The command's whole path from a results folder to its table, no planning."""
    from pdsketch_mech.bench.__main__ import main
    root = os.path.join(os.path.dirname(__file__), "..")
    args = ["contract", "--problems", os.path.join(root, "problems", "contract"), "--only", "scene-restack",
            "--mechanisms-dir", os.path.join(root, "domains", "mechanisms"), "--configs", "basis,all"]
    empty = str(tmp_path / "empty")
    assert main(args + ["--out", empty, "--table-only"]) == 2
    assert "holds no trials" in capsys.readouterr().err
    folder = str(tmp_path / "run")
    store = ContractStore(folder, {"kind": "contract"}, resume=False)
    for method, time_s in (("basis", 2.0), ("all", 2.5)):
        store.add(ContractTrial(task="scene-restack", method=method, index=0, instance="scene-restack", seed=0,
                                status="solved", time_s=time_s, skeletons=1, refined=1, steps=2, proposals={},
                                simulated={}))
    assert main(args + ["--out", folder, "--table-only"]) == 0
    printed = capsys.readouterr().out
    assert "scene-restack" in printed and "1/1 config x problem pairs keep it" in printed
