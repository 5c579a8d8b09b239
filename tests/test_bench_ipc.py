"""The IPC benchmark: trials in subprocesses, timeouts, the peer columns and CLI errors."""
import importlib.util
import json
import os
import shutil
import time

import pytest

from pdsketch_mech.bench import ipc
from pdsketch_mech.bench.__main__ import INSTALL_HINT, main

from conftest import DATA

IPC = os.path.join(DATA, "ipc")


@pytest.fixture
def gripper_dir(tmp_path):
    """DIR/gripper/{domain,task01}.pddl: one small problem."""
    folder = tmp_path / "gripper"
    folder.mkdir()
    for name in ("domain.pddl", "task01.pddl"):
        shutil.copy(os.path.join(IPC, "gripper", name), folder / name)
    return str(tmp_path)


def test_ours_solves_gripper_with_a_valid_plan(gripper_dir):
    [trial] = ipc.run_ipc(gripper_dir, timeout=30, progress=False)
    assert (trial.domain, trial.problem, trial.planner) == ("gripper", "task01", "ours")
    assert trial.status == "solved" and trial.valid is True
    assert trial.time_s > 0 and trial.length > 0 and trial.expansions > 0
    summary = ipc.summarize([trial])
    assert summary["ours_solved"] == 1 and summary["ours_invalid"] == []


def test_pyperplan_peer_gives_both_columns_and_a_ratio(gripper_dir):
    # pyperplan is in the `test` extra, so this runs in CI rather than skipping.
    trials = ipc.run_ipc(gripper_dir, timeout=30, peer="pyperplan", progress=False)
    assert [t.planner for t in trials] == ["ours", "pyperplan"]
    assert all(t.status == "solved" and t.time_s > 0 and t.length > 0 for t in trials)
    header, [row] = ipc.table(trials, "pyperplan")
    assert header[-4:] == ["pyperplan", "time s", "length", "ratio"]
    assert float(row[-1]) == pytest.approx(trials[1].time_s / trials[0].time_s, rel=0.01, abs=0.01)
    summary = ipc.summarize(trials, "pyperplan")
    assert summary["peer_solved"] == summary["both_solved"] == 1 and summary["peer_only"] == []
    assert summary["median_time_ratio"] > 0 and summary["median_length_ratio"] > 0


def test_cli_prints_table_and_writes_json_and_markdown(gripper_dir, tmp_path, capsys):
    out_json, out_md = tmp_path / "out.json", tmp_path / "out.md"
    assert main(["ipc", gripper_dir, "--timeout", "30", "--json", str(out_json), "--markdown", str(out_md)]) == 0
    stdout = capsys.readouterr().out
    assert "gripper/task01" in stdout and "ours solved: 1/1 (every plan valid)" in stdout
    data = json.loads(out_json.read_text())
    assert data["trials"][0]["status"] == "solved" and data["summary"]["ours_solved"] == 1
    assert out_md.read_text().startswith("| problem | ours |")


@pytest.mark.parametrize("make_dir", [lambda p: p, lambda p: p / "missing"], ids=["empty", "missing"])
def test_bad_dir_exits_2_with_one_line(tmp_path, capsys, make_dir):
    assert main(["ipc", str(make_dir(tmp_path))]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1


def test_missing_pyperplan_is_reported(gripper_dir, capsys, monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "pyperplan" else real(name, *a))
    assert main(["ipc", gripper_dir, "--peer", "pyperplan"]) == 2
    assert capsys.readouterr().err == f"error: {INSTALL_HINT}\n"


def test_tiny_timeout_reports_timeout():
    start = time.perf_counter()
    trial = ipc.run_trial("ours", "blocks", os.path.join(IPC, "blocks", "p03.pddl"), "gbfs", 0.001)
    assert trial.status == "timeout" and trial.length is None
    assert time.perf_counter() - start < 15


def test_overrunning_peer_is_killed():
    # pyperplan is in the `test` extra, so this runs in CI rather than skipping.
    start = time.perf_counter()  # pyperplan needs about a minute on this problem
    trial = ipc.run_trial("pyperplan", "logistics00", os.path.join(IPC, "logistics00", "problem03.pddl"),
                          "gbfs", 0.2)
    assert trial.status == "timeout" and trial.time_s is None and "killed" in trial.message
    assert time.perf_counter() - start < 15
