"""Demonstrations: the world observer hook, the recorder and its file format, the goal check,
the `demo` command, the committed recordings, and the scripted demos on perturbed instances."""
from __future__ import annotations

import json
import os
import re

import numpy as np
import pytest

from pdsketch_mech.commands import demo as demo_cli
from pdsketch_mech.envs import TASKS, sample
from pdsketch_mech.envs.demos import run as demo_run
from pdsketch_mech.envs.demos.run import DEMOS, demo_instance, goal_holds, run_demo
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.world.recording import (
    SCHEMA, Recorder, RecordingExists, load_recording, recording_paths, save_recording,
)
from pdsketch_mech.world.build import build_world

from conftest import ROOT

DEMOS_DIR = os.path.join(ROOT, "domains", "mechanisms", "demos")
OPERATORS = re.compile(r"\b(transit|transit-cont|grasp|place|move|move-cont)\b")

BLOCK = """(define (problem drop) (:domain mech-basis) (:objects table a - item)
  (:init (handempty) (fixed table) (support a table)) (:goal (holding a))
  (:scene (table :asset "table" :position (0.6 0 0) :fixed)
          (a :asset "block/0" :position (0.5 0 0.04) :on table)))"""


def test_world_observers_see_every_step():
    with build_world(parse_text(BLOCK)) as world:
        seen = []
        world.observers.append(lambda w: seen.append(w.sim_steps))
        start = world.sim_steps
        world.step(5)
        world.settle(max_steps=3, quiet_steps=100)
        assert seen == list(range(start + 1, start + 9))


def test_recorder_captures_frames_and_contacts(tmp_path):
    with build_world(parse_text(BLOCK)) as world:
        with Recorder(world) as recorder:
            world.step(40)     # the block drops 1.5 cm and lands
        arrays, header = recorder.arrays(), recorder.header(problem=BLOCK)
    assert recorder.frames == 11 and header["frames"] == 11 and header["rate_hz"] == 60
    assert list(arrays["step"]) == list(range(0, 41, 4))
    assert arrays["joints"].shape == (11, 7) and arrays["poses"].shape == (11, 2, 7)
    assert np.allclose(arrays["gripper_opening"], arrays["fingers"].sum(axis=1))
    z = arrays["poses"][:, 1, 2]
    assert z[0] == pytest.approx(0.04, abs=1e-4) and z[-1] < 0.027    # it fell onto the table
    offsets = arrays["contact_offsets"]
    assert offsets[0] == 0 and offsets[-1] == len(arrays["contact_bodies"]) and np.all(np.diff(offsets) >= 0)
    assert offsets[1] == 0 and offsets[-1] > offsets[-2]               # no contact at first, then the landing
    names = [b["name"] for b in header["bodies"]]
    assert names == ["robot", "table", "a"]
    last = arrays["contact_bodies"][offsets[-2]:offsets[-1]]
    assert {tuple(sorted(pair)) for pair in last.tolist()} == {(1, 2)}   # block on table
    assert np.all(arrays["contact_force"][offsets[-2]:] >= 0)
    assert set(arrays) == set(header["arrays"])

    base = str(tmp_path / "drop")
    npz, js = save_recording(base, arrays, header)
    assert (npz, js) == recording_paths(base + ".json")
    with pytest.raises(RecordingExists):
        save_recording(base, arrays, header)
    save_recording(base, arrays, header, force=True)
    assert sorted(os.listdir(tmp_path)) == ["drop.json", "drop.npz"]    # no temporary files left
    loaded = load_recording(npz)
    assert loaded.header["schema"] == SCHEMA and loaded.frames == 11
    assert all(np.array_equal(loaded.arrays[k], arrays[k]) for k in arrays)
    assert len(loaded.contacts(10)["bodies"]) == offsets[-1] - offsets[-2]


def test_goal_evaluation_over_contact_facts():
    problem = parse_text(BLOCK.replace("(:goal (holding a))",
                                       "(:goal (and (exists (?x - item) (support a ?x)) (not (holding a)) "
                                       "(or (handempty) (holding table))))"))
    facts = {("handempty",), ("support", "a", "table")}
    assert goal_holds(problem.goal, facts, problem)
    assert not goal_holds(problem.goal, {("holding", "a")}, problem)
    assert not goal_holds(problem.goal, {("handempty",), ("support", "a", "floor")}, problem)  # floor: no item


def test_a_demo_that_misses_its_goal_fails_in_one_line(monkeypatch, tmp_path, capsys):
    monkeypatch.setitem(demo_run.DEMOS, "com", lambda world, instance, driver: driver.up(0.02))
    assert demo_cli.main(["record", "com", "--out", str(tmp_path)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "the goal (and (support flat pedestal)" in err[0] and "does not hold" in err[0]
    assert os.listdir(tmp_path) == []


def test_demo_command_rejects_bad_requests(tmp_path, capsys):
    assert demo_cli.main(["record", "hok", "--out", str(tmp_path)]) == 2
    (tmp_path / "a-file").write_text("")
    assert demo_cli.main(["record", "com", "--out", str(tmp_path / "a-file" / "demos")]) == 2
    (tmp_path / "com.json").write_text("{}")
    assert demo_cli.main(["record", "com", "--out", str(tmp_path)]) == 2
    assert demo_cli.main(["show", str(tmp_path / "nothing.npz"), "--strip", str(tmp_path / "s.png")]) == 2
    # A compositional task is a distribution without a script: one line, not a KeyError.
    assert demo_cli.main(["record", "push-pick-hook", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 5 and all(line.startswith("error: ") for line in err)
    assert err[1] == f"error: --out {tmp_path}/a-file/demos: cannot create: Not a directory"
    assert "exists (use --force" in err[2]
    assert "'push-pick-hook' has no demonstration" in err[4]


def test_demo_list_names_only_tasks_with_a_script(capsys):
    assert demo_cli.main(["list"]) == 0
    assert [line.split()[0] for line in capsys.readouterr().out.splitlines()] == list(DEMOS)


def test_record_into_a_new_folder_and_show_a_demo(tmp_path, capsys):
    folder = tmp_path / "new" / "demos"   # made with its parents
    assert demo_cli.main(["record", "com", "--out", str(folder)]) == 0
    header = json.loads((folder / "com.json").read_text())
    assert header["goal_achieved"] and header["task"] == "com" and header["seed"] is None
    assert header["problem"] == sample(TASKS["com"]).problem_text()
    assert not OPERATORS.search(json.dumps(header))
    assert (folder / "com.npz").stat().st_size < 5e6
    strip, gif = tmp_path / "strip.png", tmp_path / "demo.gif"
    assert demo_cli.main(["show", str(folder / "com.npz"), "--strip", str(strip), "--render", str(gif),
                          "--every", "30"]) == 0
    assert strip.stat().st_size > 10_000 and gif.stat().st_size > 10_000
    assert "goal (and (support flat pedestal)" in capsys.readouterr().err


def test_recordings_are_deterministic():
    first = run_demo("com")
    second = run_demo("com")
    assert first.goal_reached and second.goal_reached
    a, b = first.extra["arrays"], second.extra["arrays"]
    assert all(np.array_equal(a[k], b[k]) for k in a)


@pytest.mark.parametrize("name", list(DEMOS))
def test_committed_recording_is_current(name):
    """domains/mechanisms/demos/NAME: the canonical instance's demonstration, goal reached,
    raw data only, under 5 MB. (Re-record with `python -m pdsketch_mech.demo record NAME
    --force` after changing a task or its script.)"""
    npz, js = recording_paths(os.path.join(DEMOS_DIR, name))
    assert os.path.getsize(npz) + os.path.getsize(js) < 5e6
    recording = load_recording(npz)
    header = recording.header
    assert header["schema"] == SCHEMA and header["goal_achieved"] and header["rate_hz"] == 60
    assert header["problem"] == sample(TASKS[name]).problem_text()
    assert not OPERATORS.search(json.dumps(header))
    assert recording.frames == header["frames"] > 60
    assert recording.arrays["contact_offsets"][-1] == header["contacts"]


@pytest.mark.slow
@pytest.mark.parametrize("name", list(DEMOS))
def test_demo_succeeds_on_perturbed_instances(name):
    for seed in (None, 0, 1, 2):
        result = run_demo(name, demo_instance(name, "train", seed), record=False)
        assert result.goal_reached, f"{name} seed {seed}: {result.error or result.facts_text()}"
        assert result.wall_s < 30
