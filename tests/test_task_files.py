"""Task distributions as data files (docs/distributions.md): derived from a problem file's
scene, every built-in task expressible in the same form with byte-identical instances,
located errors, and the commands that take a distribution file."""
from __future__ import annotations

import json
import os
import shutil
from dataclasses import replace

import pytest

from pdsketch_mech.commands import envs as envs_cli
from pdsketch_mech.commands import learn as learn_cli
from pdsketch_mech.envs.generate import sample
from pdsketch_mech.envs.task_file import TaskFileError, dump_document, load_task_file, task_document
from pdsketch_mech.envs.task_names import resolve_task
from pdsketch_mech.envs.tasks import TASKS

from conftest import ROOT

EXAMPLES = os.path.join(ROOT, "docs", "examples")
EXAMPLE = os.path.join(EXAMPLES, "push-to-edge.dist.json")
# A cup on a plate on the table.
TRAY = """(define (problem tray) (:domain mech-basis)
      (:objects table tray cup - item)
      (:init (handempty) (fixed table) (support tray table) (support cup tray))
      (:goal (holding cup))
      (:scene (table :asset "table" :position (0.6 0 0) :fixed)
              (tray :asset "plate/0" :position (0.5 0.1) :on table)
              (cup :asset "small-block/0" :position (0.52 0.1) :on tray)))"""


@pytest.mark.parametrize("name", list(TASKS))
def test_every_built_in_task_is_a_distribution_file_with_the_same_instances(name, tmp_path):
    path = tmp_path / f"{name}.dist.json"
    path.write_text(dump_document(task_document(TASKS[name])))
    loaded = load_task_file(str(path))
    assert replace(loaded, source="") == TASKS[name]
    for split in ("train", "dev", "test"):
        for seed in (0, 7):
            assert sample(replace(loaded, source=""), split, seed).problem_text() == \
                sample(TASKS[name], split, seed).problem_text()


def test_a_distribution_derives_its_objects_from_the_problem_scene():
    task = load_task_file(EXAMPLE)
    table, flat = task.objects
    assert (table.fixed, table.noise_xy, table.noise_yaw) == (True, (0.0, 0.0), 0.0)
    assert flat.xy == (0.48, 0.22) and flat.yaw == pytest.approx(90.0) and flat.on == "table"
    assert flat.assets.of("test") == flat.assets.dev == ("calculator/2", "document/2") and flat.noise_xy == (0.04, 0.04)
    assert task.goal == "(holding flat)" and task.name == "push-to-edge"
    canonical = sample(task).problem_text()
    assert '(flat :asset "calculator/0" :position (0.48 0.22 ' in canonical
    assert "python -m pdsketch_mech.envs " + EXAMPLE in canonical      # says how to regenerate it


def test_dev_assets_of_their_own_keep_the_test_assets_for_test_alone(tmp_path):
    """`"dev": [...]` beside `"test"`: dev tunes on its own held-out assets and test reports on
    shapes dev never shows; without it both draw from `"test"` (the example above)."""
    shutil.copy(os.path.join(EXAMPLES, "push-to-edge.pddl"), tmp_path / "push-to-edge.pddl")
    path = tmp_path / "three.dist.json"
    path.write_text(json.dumps({"format": 1, "problem": "push-to-edge.pddl", "objects": {"flat": {"assets": {
        "train": ["calculator/0"], "dev": ["calculator/2"], "test": ["calculator/3", "calculator/4"]}}}}))
    task = load_task_file(str(path))
    flat = task.object("flat")
    assert flat.assets.of("dev") == ("calculator/2",) and flat.assets.of("test") == ("calculator/3", "calculator/4")
    assert {sample(task, "test", seed).object("flat").asset for seed in range(12)} == {"calculator/3", "calculator/4"}
    assert {sample(task, "dev", seed).object("flat").asset for seed in range(4)} == {"calculator/2"}
    assert task_document(task)["objects"]["flat"]["assets"] == {
        "train": ["calculator/0"], "dev": ["calculator/2"], "test": ["calculator/3", "calculator/4"]}


def test_an_object_on_a_movable_support_moves_with_it(tmp_path):
    (tmp_path / "tray.pddl").write_text(TRAY)
    (tmp_path / "tray.dist.json").write_text(json.dumps({"format": 1, "problem": "tray.pddl",
                                                         "objects": {"cup": {"shift": [0, 0], "turn": 0}}}))
    task = load_task_file(str(tmp_path / "tray.dist.json"))
    cup = task.object("cup")
    assert cup.frame == "tray" and cup.xy == pytest.approx((0.02, 0.0))
    for seed in range(5):
        instance = sample(task, "train", seed)
        tray, placed = instance.object("tray"), instance.object("cup")
        assert placed.position[0] - tray.position[0] == pytest.approx(0.02 * _cos(tray.yaw), abs=1e-3)


def test_an_object_on_a_plate_rests_on_its_inner_surface_not_its_rim(tmp_path):
    """A movable support's top is not its bounding box's: the instance leaves the height to
    the scene loader, which rests the cup inside the plate, where it stays as the scene settles."""
    from pdsketch_mech.lang.parser import parse_text
    from pdsketch_mech.planner.execute import settle_moves
    from pdsketch_mech.world.build import build_world

    (tmp_path / "tray.pddl").write_text(TRAY)
    instance = sample(resolve_task(str(tmp_path / "tray.pddl")), "dev", 1)
    text = instance.problem_text()
    assert ":position (0.557 0.0745) :rpy-deg (0 0 10.14) :on tray)" in text        # no height: it rests
    with build_world(parse_text(text, "tray.pddl")) as world:
        rim = instance.object("cup").position[2]                                   # on the box's top
        assert world.pose("cup")[0][2] < rim - 0.005 and settle_moves(world) == []


def _cos(degrees: float) -> float:
    import math
    return math.cos(math.radians(degrees))


@pytest.mark.parametrize("document, expected", [
    ({"format": 1, "problem": "push-to-edge.pddl", "objects": {"flta": {}}},
     "objects: 'flta' is not an object of the problem's scene (did you mean 'flat'?)"),
    ({"format": 1, "problem": "push-to-edge.pddl", "objects": {"flat": {"shfit": [0, 0]}}},
     "objects: flat: unknown field 'shfit' (did you mean 'shift'?)"),
    ({"format": 1, "problem": "push-to-edge.pddl", "objects": {"flat": {"assets": ["calculater/0"]}}},
     "objects: flat: assets: unknown asset 'calculater/0'"),
    ({"format": 1, "problem": "push-to-edge.pddl", "objects": {"flat": {"assets": {"train": ["calculator/0"],
                                                                                  "tset": ["calculator/2"]}}}},
     "objects: flat: assets: unknown split 'tset' (did you mean 'test'?) (train, dev, test)"),
    ({"format": 1, "problem": "push-to-edge.pddl", "objects": {"flat": {"on": "tabel"}}},
     "objects: flat: on: 'tabel' is not an object of the task (did you mean 'table'?)"),
    ({"format": 1, "problem": "push-to-edge.pddl", "distractors": {"pool": ["aple/0"], "count": [0, 1],
                                                                    "region": [[0.3, 0.5], [0, 0.2]]}},
     "distractors: pool: unknown asset 'aple/0'"),
    ({"format": 1, "problem": "push-to-edge.pddl", "objects": {"flat": {"turn": "a lot"}}},
     "objects: flat: turn: expected a number, got \"a lot\""),
    ({"format": 1, "problem": "push-to-edge.pddl", "objects": {"flat": {"tilt": [90, 400]}}},
     "objects: flat: tilt: expected [ROLL, PITCH] in degrees, each within -180..180"),
    ({"format": 1, "problem": "nowhere.pddl"}, "problem: "),
    ({"format": 2, "problem": "push-to-edge.pddl"}, "format: expected \"format\": 1"),
    ({"format": 1, "problme": "push-to-edge.pddl"}, "unknown field 'problme' (did you mean 'problem'?)"),
    ({"format": 1, "problem": "push-to-edge.pddl", "distractors": {"pool": ["apple/0"], "count": [2, 1],
                                                                    "region": [[0.3, 0.5], [0, 0.2]]}},
     "distractors: count: expected [MIN, MAX]"),
])
def test_a_bad_distribution_is_one_located_line(tmp_path, document, expected):
    shutil.copy(os.path.join(EXAMPLES, "push-to-edge.pddl"), tmp_path / "push-to-edge.pddl")
    path = tmp_path / "bad.dist.json"
    path.write_text(json.dumps(document, indent=1))
    with pytest.raises(TaskFileError) as caught:
        load_task_file(str(path))
    message = str(caught.value)
    assert message.startswith(str(path)) and ": error: " in message and expected in message, message
    assert "\n" not in message


def test_an_unknown_asset_suggests_the_closest(tmp_path):
    shutil.copy(os.path.join(EXAMPLES, "push-to-edge.pddl"), tmp_path / "push-to-edge.pddl")
    path = tmp_path / "bad.dist.json"
    path.write_text(json.dumps({"format": 1, "problem": "push-to-edge.pddl",
                                "objects": {"flat": {"assets": ["calculater/0"]}}}))
    with pytest.raises(TaskFileError, match=r"\(did you mean 'calculator/0'\?\)"):
        load_task_file(str(path))


def test_envs_warns_when_a_region_holds_fewer_distractors_than_asked(tmp_path, capsys):
    shutil.copy(os.path.join(EXAMPLES, "push-to-edge.pddl"), tmp_path / "push-to-edge.pddl")
    path = tmp_path / "crowded.dist.json"
    path.write_text(json.dumps({"format": 1, "problem": "push-to-edge.pddl", "distractors": {
        "pool": ["apple/0"], "count": [5, 5], "region": [[0.3, 0.36], [-0.3, -0.24]]}}))
    assert envs_cli.main([str(path), "--seed", "1"]) == 0
    assert "distractors placed, fewer than the 5 asked for" in capsys.readouterr().err


def test_the_error_points_at_the_offending_key(tmp_path):
    shutil.copy(os.path.join(EXAMPLES, "push-to-edge.pddl"), tmp_path / "push-to-edge.pddl")
    path = tmp_path / "bad.dist.json"
    path.write_text('{"format": 1, "problem": "push-to-edge.pddl",\n "objects": {\n  "flta": {}}}\n')
    with pytest.raises(TaskFileError, match=r"bad\.dist\.json:3:3: error"):
        load_task_file(str(path))


def test_resolve_task_names_the_choices():
    assert resolve_task("hook") is TASKS["hook"]
    with pytest.raises(KeyError, match="did you mean 'hook'"):
        resolve_task("hok")


def test_envs_writes_instances_of_a_distribution_file_and_exports_built_ins(tmp_path, capsys):
    assert envs_cli.main([EXAMPLE, "--seed", "2", "--split", "dev"]) == 0
    assert "(define (problem push-to-edge-dev-2)" in capsys.readouterr().out
    out = tmp_path / "lever.dist.json"
    assert envs_cli.main(["lever", "--export", "--out", str(out)]) == 0
    capsys.readouterr()
    assert envs_cli.main([str(out), "--seed", "3", "--split", "test"]) == 0
    from_file = capsys.readouterr().out
    assert envs_cli.main(["lever", "--seed", "3", "--split", "test"]) == 0
    # The same scene; only the header's regeneration command names the file.
    assert from_file.split("\n", 2)[2] == capsys.readouterr().out.split("\n", 2)[2]


def test_a_problem_file_stands_for_its_default_distribution(tmp_path, capsys, monkeypatch):
    """`--task problem.pddl`: the scene's fixed objects kept, movable ones shifted +-5 cm and
    turned +-15 degrees, every asset its own; instances regenerate from the same file."""
    shutil.copy(os.path.join(EXAMPLES, "push-to-edge.pddl"), tmp_path / "push-to-edge.pddl")
    monkeypatch.chdir(tmp_path)
    task = resolve_task("push-to-edge.pddl")
    table, flat = task.objects
    assert (table.fixed, table.noise_xy) == (True, (0.0, 0.0))
    assert flat.noise_xy == (0.05, 0.05) and flat.noise_yaw == 15.0 and flat.assets.dev == ("calculator/0",)
    assert envs_cli.main(["push-to-edge.pddl", "--seed", "4", "--split", "dev"]) == 0
    text = capsys.readouterr().out
    assert "Generated by `python -m pdsketch_mech.envs push-to-edge.pddl --split dev --seed 4`" in text
    assert text == sample(task, "dev", 4).problem_text()
    assert envs_cli.main(["nowhere.pddl", "--seed", "1"]) == 2
    assert capsys.readouterr().err.strip() == "nowhere.pddl: error: problem: nowhere.pddl: no such file"


def test_learn_refuses_a_bad_distribution_file_before_playing(tmp_path, capsys):
    fragment = os.path.join(ROOT, "domains", "mechanisms", "edge.pddl")
    bad = tmp_path / "bad.dist.json"
    bad.write_text('{"format": 1, "problem": "nowhere.pddl"}')
    status = learn_cli.main(["selfplay", "edge", "--fragment", fragment, "--task", str(bad), "--episodes", "1",
                             "--out", str(tmp_path / "data")])
    assert status == 2 and "problem: " in capsys.readouterr().err
    assert not os.listdir(tmp_path / "data") if os.path.exists(tmp_path / "data") else True


@pytest.mark.slow
def test_selfplay_plays_a_distribution_file(tmp_path, capsys):
    folder = tmp_path / "ex"
    shutil.copytree(EXAMPLES, folder)
    from pdsketch_mech.commands import demo as demo_cli
    assert demo_cli.main(["record", str(folder / "push-to-edge.demo.json")]) == 0
    fragment = str(folder / "push-to-edge.mech.pddl")
    assert learn_cli.main(["extract", str(folder / "push-to-edge"), "--out", fragment]) == 0
    status = learn_cli.main(["selfplay", "push-to-edge", "--fragment", fragment, "--task",
                             str(folder / "push-to-edge.dist.json"), "--episodes", "1", "--seed", "1",
                             "--out", str(tmp_path / "data")])
    err = capsys.readouterr().err
    assert "1 episodes in" in err and status in (0, 1)
    manifest = json.load(open(tmp_path / "data" / "manifest.json"))
    assert manifest["config"]["task"] == str(folder / "push-to-edge.dist.json")


def test_a_fixed_object_resting_on_nothing_keeps_its_height(tmp_path):
    """A raised fixed shelf in the problem (no :on) stays at its height in every instance,
    written to the full form too, instead of sinking to z = 0."""
    problem = os.path.join(ROOT, "problems", "contract", "user-mechanism", "shelf-pull.pddl")
    path = tmp_path / "shelf.dist.json"
    path.write_text(json.dumps({"format": 1, "problem": os.path.relpath(problem, tmp_path),
                                "objects": {"box": {"shift": [0.02, 0.02]}}}))
    task = load_task_file(str(path))
    shelf = next(o for o in task.objects if o.name == "shelf")
    assert shelf.on is None and shelf.z == pytest.approx(0.06)
    assert "(shelf :asset \"brick/0\" :position (1 0 0.06)" in sample(task, "test", 3).problem_text()
    assert task_document(task)["objects"]["shelf"]["z"] == pytest.approx(0.06)


def test_a_tilted_object_keeps_its_tilt_turns_about_the_vertical_and_rests_on_its_edge(tmp_path):
    """A calculator standing on its edge in the problem: every instance keeps it on its edge
    (roll 90), turned about z only, resting on the table by its collision vertices (its
    short side down: the height is half its thickness-wise width, not half its thickness),
    and settles where it was put."""
    from pdsketch_mech.lang.parser import parse_text
    from pdsketch_mech.planner.execute import settle_start
    from pdsketch_mech.world.asset_index import asset_info
    from pdsketch_mech.world.build import build_world

    (tmp_path / "edge-on.pddl").write_text("""(define (problem edge-on) (:domain mech-basis)
      (:objects table flat - item)
      (:init (handempty) (fixed table) (support flat table))
      (:goal (holding flat))
      (:scene (table :asset "table" :position (0.6 0 0) :fixed)
              (flat :asset "calculator/0" :position (0.5 0.1 0.2) :rpy-deg (90 0 30) :on table)))""")
    (tmp_path / "edge-on.dist.json").write_text(json.dumps({"format": 1, "problem": "edge-on.pddl", "objects": {
        "flat": {"assets": {"train": ["calculator/0", "calculator/1"], "test": ["calculator/2"]}, "turn": 40}}}))
    task = load_task_file(str(tmp_path / "edge-on.dist.json"))
    assert task.object("flat").tilt == pytest.approx((90.0, 0.0)) and task.object("flat").yaw == pytest.approx(30.0)
    assert task_document(task)["objects"]["flat"]["tilt"] == pytest.approx([90.0, 0.0])
    for split, seed in (("train", 0), ("dev", 1), ("test", 2)):
        text = sample(task, split, seed).problem_text()
        placed = sample(task, split, seed).object("flat")
        half_width = -asset_info(placed.asset)["aabb"]["min"][1] * placed.scale
        assert placed.tilt == pytest.approx((90.0, 0.0)) and abs(placed.yaw - 30.0) <= 40.0
        assert placed.position[2] == pytest.approx(half_width, abs=2e-3), text     # on its edge
        assert ":rpy-deg (90 0 " in text
        problem = parse_text(text, "edge-on.pddl")
        with build_world(problem) as world:
            assert settle_start(world) == []                                        # does not fall or sink


def test_the_canonical_instance_keeps_a_problems_scale(tmp_path):
    """`envs --canonical` regenerates the problem's own scene: a `:scale 0.8` object stays 0.8."""
    text = open(os.path.join(EXAMPLES, "push-to-edge.pddl")).read()
    scaled = text.replace(':asset "calculator/0"', ':asset "calculator/0" :scale 0.8')
    assert scaled != text
    (tmp_path / "small.pddl").write_text(scaled)
    task = resolve_task(str(tmp_path / "small.pddl"))
    assert ":scale 0.8" in sample(task).problem_text()
    assert ":scale" not in sample(TASKS["edge"]).problem_text().split("(:scene")[1]   # built-ins: 1
