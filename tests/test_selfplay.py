"""Self-play data collection (learning/selfplay*.py, `learn selfplay`): labels, context,
determinism, resuming, workers, and the World's refusal to be pickled.

A tiny configuration: the Center-of-Mass mechanism (two steps, ~1 s an episode), 3 episodes."""
from __future__ import annotations

import os
import pickle
import subprocess
import sys

import numpy as np
import pytest

from pdsketch_mech.learning.selfplay import SelfPlayConfig, default_fragment, episode_seeds, task_of
from pdsketch_mech.samplers.learned.encoding import VALUE_LAYOUT
from pdsketch_mech.learning.selfplay_run import run_selfplay
from pdsketch_mech.learning.selfplay_store import done_episodes, load_dataset, read_episode
from pdsketch_mech.world.asset_index import asset_names
from pdsketch_mech.world.world import World

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIG = SelfPlayConfig("com", default_fragment("com"), "com", seed=0, budget=60)


def equal_data(a, b) -> None:
    """The same arrays, except the measured wall-clock seconds."""
    assert sorted(a) == sorted(b)
    for key in a:
        if key != "episode_seconds":
            assert np.array_equal(a[key], b[key], equal_nan=a[key].dtype.kind == "f"), key


@pytest.fixture(scope="module")
def straight(tmp_path_factory):
    """Three episodes in one run, in this process."""
    folder = str(tmp_path_factory.mktemp("straight"))
    run_selfplay(CONFIG, folder, 3)
    return folder


def test_labels_and_context(straight):
    data = load_dataset(straight)
    assert list(data["episode_id"]) == [0, 1, 2]
    n = len(data["label"])
    assert n > 0 and set(np.unique(data["label"])) <= {0, 1}
    for e, success in zip(data["episode_id"], data["episode_success"]):
        labels = data["label"][data["episode"] == e]
        # a successful episode's plan used one value per mechanism variable, each labelled 1
        assert (labels.sum() == 4) if success else (labels.sum() == 0)
    assert data["episode_success"].any()
    # every kind of value in its numeric layout, NaN-padded beyond it
    values = data["verified"] == 1
    for kind, dim, row in zip(data["kind"][values], data["value_dim"][values], data["value"][values]):
        assert dim == len(VALUE_LAYOUT[str(kind)]) and not np.isnan(row[:3]).any() and np.isnan(row[dim:]).all()
    # proposals that failed verification are rows of their own: never labelled 1, their
    # numbers those of the proposal; a value's proposal is in the value's layout too
    rejected = data["verified"] == 0
    assert rejected.any() and not data["label"][rejected].any()
    assert set(data["kind"][rejected]) <= {"grasp", "placement", "contact", "trajectory"}
    assert np.array_equal(data["proposal"][rejected], data["value"][rejected], equal_nan=True)
    grasps = values & (data["kind"] == "grasp")
    assert np.allclose(data["proposal"][grasps, :8], data["value"][grasps, :8])  # a grasp verifies as proposed
    assert set(data["kind"]) >= {"grasp", "placement", "trajectory"}
    # context: the mechanism's objects as assets + scales, their poses, steps, variables, parents
    m = data["episode_objects"].shape[1]
    assert m == 3 and data["poses"].shape == (n, m, 7)
    assert np.allclose(np.linalg.norm(data["poses"][..., 3:], axis=-1), 1.0, atol=1e-6)
    assert {str(a) for a in data["episode_assets"].ravel()} <= set(asset_names())  # e.g. "plate/0"
    assert data["episode_scales"].shape == (3, m)
    assert set(data["param"]) == {"?g", "?t1", "?p", "?t2"}
    assert set(data["step"]) == {0, 1}
    first = np.flatnonzero(data["param"] == "?t2")[0]
    parents = data["parents"][first][data["parents"][first] >= 0]
    assert [str(data["param"][k]) for k in parents] == ["?g", "?t1", "?p"]  # mechanism order
    for e in range(3):
        assert data["episode_instance_seed"][e] == episode_seeds(0, e)[0]


def test_same_seed_same_data_and_resume(straight, tmp_path):
    resumed = str(tmp_path / "resumed")
    run_selfplay(CONFIG, resumed, 2)
    ran = []
    run_selfplay(CONFIG, resumed, 3, progress=lambda row: ran.append(row["episode"]))
    assert ran == [2]  # only the missing episode runs
    for e in range(3):
        equal_data(read_episode(straight, e), read_episode(resumed, e))


def test_interrupted_episode_leaves_nothing(tmp_path, monkeypatch):
    """An episode killed in flight leaves no file (and no temporary one): a rerun redoes it."""
    from pdsketch_mech.learning import selfplay_run

    folder = str(tmp_path / "cut")
    real = selfplay_run.run_episode

    def interrupted(config, episode):
        if episode == 1:
            raise KeyboardInterrupt
        return real(config, episode)
    monkeypatch.setattr(selfplay_run, "run_episode", interrupted)
    with pytest.raises(KeyboardInterrupt):
        run_selfplay(CONFIG, folder, 3)
    assert done_episodes(folder) == [0]
    assert sorted(os.listdir(os.path.join(folder, "episodes"))) == ["e000000.npz"]


def test_two_workers_give_the_same_data(straight, tmp_path):
    folder = str(tmp_path / "workers")
    run_selfplay(CONFIG, folder, 3, workers=2)
    for e in range(3):
        equal_data(read_episode(straight, e), read_episode(folder, e))


@pytest.mark.slow
def test_ray_backend_gives_the_same_data(straight, tmp_path):
    pytest.importorskip("ray")  # the `test` extra installs it; a user's plain install may not
    folder = str(tmp_path / "ray")
    run_selfplay(CONFIG, folder, 3, workers=2, backend="ray")
    for e in range(3):
        equal_data(read_episode(straight, e), read_episode(folder, e))


def test_another_configuration_is_refused(straight):
    from pdsketch_mech.learning.selfplay_store import StoreError

    other = SelfPlayConfig("com", default_fragment("com"), "com", seed=1, budget=60)
    with pytest.raises(StoreError, match="another configuration"):
        run_selfplay(other, straight, 3)


def _slope_task():
    """A Slope-and-Blocker train instance with a distractor: 18 applicable groundings."""
    from pdsketch_mech.envs.generate import sample as sample_instance
    from pdsketch_mech.envs.tasks import TASKS
    from pdsketch_mech.lang.loader import load_domain
    from pdsketch_mech.lang.parser import parse_text
    from pdsketch_mech.planner.bilevel import prepare_task

    instance = sample_instance(TASKS["slope-blocker"], "train", episode_seeds(0, 0)[0])
    problem = parse_text(instance.problem_text(), file="<instance>")
    task, _ = prepare_task(load_domain([default_fragment("slope-blocker")]), problem, use_mechanisms=True)
    return task


def test_goal_grounding_keeps_the_groundings_that_serve_the_goal():
    """"goal" draws from the groundings whose certified facts put the goal's target on the goal's
    surface; the blocker stays a free choice (the distractor too). "any" keeps every applicable one,
    among them those that promise to put the target on what it leaves."""
    from pdsketch_mech.learning.selfplay import episode_groundings

    task = _slope_task()
    args = lambda ids: [task.operators[i].args for i in ids]  # noqa: E731
    goal = args(episode_groundings(task, "slope-blocker", "goal"))
    assert goal == [("blocker", "block", "table", "slope"), ("d0", "block", "table", "slope")]
    every = args(episode_groundings(task, "slope-blocker", "any"))
    assert len(every) == 18 and set(goal) < set(every) and ("blocker", "block", "table", "table") in every
    with pytest.raises(ValueError, match="grounding policy"):
        episode_groundings(task, "slope-blocker", "some")


def test_context_objects_are_recorded_after_the_mechanisms_own():
    """--context 1: each episode also records the body nearest the mechanism's movable objects."""
    from dataclasses import replace
    from pdsketch_mech.learning.selfplay import run_episode
    plain, wider = run_episode(CONFIG, 0), run_episode(replace(CONFIG, context=1), 0)
    own = [str(o) for o in plain["episode_objects"][0]]
    objects = [str(o) for o in wider["episode_objects"][0]]
    assert len(objects) == 4 and objects[:3] == own and objects[3] not in own
    assert wider["poses"].shape == (len(wider["label"]), 4, 7) and wider["episode_assets"].shape == (1, 4)
    assert np.array_equal(wider["label"], plain["label"])   # the same episode, seen wider


def test_a_folder_older_than_grounding_policies_resumes_as_any(tmp_path):
    from pdsketch_mech.learning.selfplay_store import StoreError, open_folder, read_manifest
    from dataclasses import replace
    import json

    any_config = replace(CONFIG, grounding="any")
    identity = any_config.identity()
    legacy = {k: v for k, v in identity.items() if k not in ("grounding", "context", "mechanism_hash")}
    (tmp_path / "manifest.json").write_text(json.dumps({"schema": "pdsketch_mech.selfplay/2", "config": legacy}))
    assert read_manifest(str(tmp_path))["config"]["grounding"] == "any"
    assert read_manifest(str(tmp_path))["config"]["context"] == 0
    open_folder(str(tmp_path), identity)   # resumes
    with pytest.raises(StoreError, match="grounding 'any'"):
        open_folder(str(tmp_path), CONFIG.identity())


def test_pickling_a_world_is_an_error():
    with World() as world:
        with pytest.raises(TypeError, match="cannot be pickled"):
            pickle.dumps(world)


def test_task_of_a_mechanism():
    assert task_of(default_fragment("com"), "com") == "com"
    assert task_of(default_fragment("hook-use"), "hook-use") == "hook"


def test_task_of_a_mechanism_extracted_from_a_perturbed_instance(tmp_path):
    """`demo record com --seed 5` names its recording com-train-5; the fragment extracted
    from it is still Center-of-Mass's, by the title its header gives."""
    fragment = tmp_path / "my-com.pddl"
    fragment.write_text("; Mechanism my-com: extracted from the demonstration com-train-5 (Center-of-Mass, "
                        "instance com-train-5) by\n(define (domain my-com))\n")
    assert task_of(str(fragment), "my-com") == "com"
    fragment.write_text("; Mechanism my-com: extracted from the demonstration x (Juggling, instance x) by\n")
    assert task_of(str(fragment), "my-com") is None


@pytest.mark.parametrize("argv, message", [
    (["nope"], "no such file"),
    (["com", "--backend", "dask"], "invalid choice"),
    (["com", "--grounding", "all"], "invalid choice"),
    (["com", "--context", "9"], "invalid choice"),
    (["com", "--task", "juggling"], "unknown task"),
    (["com", "--out", "/dev/null/x"], "--out /dev/null/x: cannot create: Not a directory"),
    (["com", "--episodes", "0"], "must be a whole number >= 1"),
])
def test_cli_bad_input(argv, message):
    result = subprocess.run([sys.executable, "-m", "pdsketch_mech.learn", "selfplay", *argv], cwd=ROOT,
                            capture_output=True, text=True, env={**os.environ, "PYTHONPATH": ROOT})
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("error:") and message in result.stderr


def test_cli_makes_its_folder_runs_and_resumes(tmp_path):
    folder = tmp_path / "new" / "data"   # made with its parents
    command = [sys.executable, "-m", "pdsketch_mech.learn", "selfplay", "com", "--episodes", "1", "--budget", "60",
               "--out", str(folder)]
    env = {**os.environ, "PYTHONPATH": ROOT}
    first = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, env=env)
    assert first.returncode == 0, first.stderr
    assert "1 episodes" in first.stderr.splitlines()[-1]
    other = subprocess.run(command[:-2] + ["--seed", "5", "--out", str(folder)], cwd=ROOT, capture_output=True,
                           text=True, env=env)
    assert other.returncode == 2 and "another configuration" in other.stderr


def test_the_log_keeps_rejected_proposals_and_each_values_proposal():
    from pdsketch_mech.learning.selfplay_record import SampleLog
    from pdsketch_mech.samplers.interface import SampleRequest, StepContext
    from pdsketch_mech.world.values import Grasp

    class Still:
        def pose(self, name):
            return (0.5, 0.0, 0.02), (0.0, 0.0, 0.0, 1.0)

    log = SampleLog(Still(), ["box"], [[]], [], {})
    grasp = lambda x: Grasp("box", ((x, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)), 0.05)  # noqa: E731
    request = SampleRequest("sample-grasp", ("box",), ("?x",), StepContext("grasp", ("box",)))
    bad, good = grasp(0.01), grasp(0.02)
    log.verified(request, bad, None)         # rejected: a row of its own
    log.verified(request, good, good)        # verified: its proposal waits for the value
    log(request, good)
    motion = SampleRequest("plan-grasp-motion", ("box", good), ("?x", "?g"), StepContext("grasp", ("box",)))
    log.verified(motion, good, None)         # the stream's own input: no choice of its own
    assert [s.verified for s in log.samples] == [0, 1]
    assert log.samples[0].proposal[0] == 0.01 and log.samples[1].proposal[0] == 0.02
    assert log.label([{"#g": good}]) == 1 and [s.label for s in log.samples] == [0, 1]


@pytest.fixture()
def com_copy(tmp_path):
    """A copy of the Center-of-Mass fragment (without its checkpoint) and the basis it extends."""
    import shutil
    shutil.copy(os.path.join(ROOT, "domains", "basis.pddl"), tmp_path / "basis.pddl")
    (tmp_path / "mechanisms").mkdir()
    path = tmp_path / "mechanisms" / "com.pddl"
    with open(default_fragment("com"), encoding="utf-8") as handle:
        path.write_text(handle.read().replace('\n    :sampler "com.samplers.safetensors"', ""))
    return str(path)


def learn_main(capsys, *argv) -> tuple:
    """`learn` in this process (the fragment parsed afresh): (exit status, stderr)."""
    from pdsketch_mech.commands import learn
    from pdsketch_mech.learning.selfplay import _domain
    _domain.cache_clear()  # a fresh process would read the edited fragment
    capsys.readouterr()
    status = learn.main(list(argv))
    return status, capsys.readouterr().err


def test_data_of_another_definition_of_the_mechanism_are_refused(com_copy, tmp_path, capsys):
    import json
    from pdsketch_mech.learning.selfplay import _domain, find_mechanism
    from pdsketch_mech.learning.selfplay_store import read_manifest
    from pdsketch_mech.samplers.learned.checkpoint import mechanism_hash

    data, weights = str(tmp_path / "data"), str(tmp_path / "w.samplers.safetensors")
    options = ["com", "--episodes", "1", "--budget", "60", "--fragment", com_copy, "--task", "com", "--out", data]
    assert learn_main(capsys, "selfplay", *options)[0] == 0
    # The folder records the definition by the hash a checkpoint of it records.
    digest = mechanism_hash(find_mechanism(_domain(com_copy), "com"))
    assert read_manifest(data)["config"]["mechanism_hash"] == digest
    with open(com_copy, encoding="utf-8") as handle:
        text = handle.read()
    with open(com_copy, "w", encoding="utf-8") as handle:
        handle.write(text.replace("?p ", "?q ").replace("?p)", "?q)"))   # rename a parameter
    for argv in (["selfplay", *options], ["train", *options, "--checkpoint", weights]):
        status, err = learn_main(capsys, *argv)
        assert status == 2 and err.count("\n") == 1, err
        assert err.startswith(f"error: {data} holds self-play episodes of another definition of mechanism com "
                              f"than the one in {com_copy}; use a new --out, or delete the folder")
    # A folder made before the hash was recorded is not refused outright, but training
    # refuses episodes that draw parameters the mechanism does not have.
    manifest = read_manifest(data)
    del manifest["config"]["mechanism_hash"]
    with open(os.path.join(data, "manifest.json"), "w", encoding="utf-8") as handle:
        json.dump(manifest, handle)
    status, err = learn_main(capsys, "train", *options, "--checkpoint", weights)
    assert status == 2 and "(they draw ?p, which it does not have); use a new --out" in err.splitlines()[-1]
    assert not os.path.exists(weights)


def test_train_says_why_it_trained_nothing(com_copy, tmp_path, capsys):
    status, err = learn_main(capsys, "train", "com", "--episodes", "2", "--time-limit", "0.01", "--fragment",
                             com_copy, "--task", "com", "--out", str(tmp_path / "data"),
                             "--checkpoint", str(tmp_path / "w.samplers.safetensors"))
    lines = err.splitlines()
    assert status == 1
    assert ", 0 succeeded (0 %), 2 hit --time-limit 0.01 s, " in lines[-2]
    assert lines[-1] == (f"train com: skipped: none of the 2 self-play episodes in {tmp_path / 'data'} succeeded, "
                         "so no proposal is labelled 1 to learn from (2 hit --time-limit 0.01 s: raise it, or play "
                         "more --episodes)")


@pytest.mark.parametrize("limit,hint", [
    (["--time-limit", "0.01"], "2 hit --time-limit 0.01 s: raise it, or play more --episodes"),
    (["--budget", "1"], "2 used up --budget 1: raise it, or play more --episodes"),
], ids=["time limit", "budget"])
def test_selfplay_says_why_no_episode_succeeded(com_copy, tmp_path, capsys, limit, hint):
    data = tmp_path / "data"
    status, err = learn_main(capsys, "selfplay", "com", "--episodes", "2", *limit, "--fragment", com_copy,
                             "--task", "com", "--out", str(data))
    assert status == 1
    assert err.splitlines()[-1] == (f"selfplay com: none of the 2 episodes in {data} succeeded, so no proposal is "
                                    f"labelled 1 for `train` to learn from ({hint})")


def test_resume_is_announced_and_train_reads_the_first_n_episodes(com_copy, tmp_path, capsys):
    import json
    import re

    data, weights = str(tmp_path / "data"), str(tmp_path / "w.samplers.safetensors")
    options = ["com", "--budget", "60", "--fragment", com_copy, "--task", "com", "--out", data]
    assert learn_main(capsys, "selfplay", *options, "--episodes", "1")[0] == 0
    status, err = learn_main(capsys, "selfplay", *options, "--episodes", "3")
    assert status == 0 and err.startswith(f"resuming: 1 of 3 episodes on disk in {data}\n")
    # The bar's success count is never ahead of the episodes it has counted.
    bars = re.findall(r"(\d+)/2 \[[^]]*?(\d+) succeeded", err)
    assert bars and all(int(succeeded) <= int(done) for done, succeeded in bars), bars
    status, err = learn_main(capsys, "train", *options, "--episodes", "2", "--epochs", "1", "--checkpoint", weights,
                             "--unvalidated")
    assert status == 0, err
    assert err.count("train com: 100%") == 1   # the bar's last line, once
    with open(weights.replace(".safetensors", ".json"), encoding="utf-8") as handle:
        meta = json.load(handle)
    # Episodes 0 and 1 of the 3 on disk, and the command that makes this checkpoint again.
    assert meta["episodes"] == 2
    assert meta["command"] == (f"python -m pdsketch_mech.learn train com --episodes 2 --seed 0 --budget 60 "
                               f"--fragment {com_copy} --task com --out {data} --epochs 1 --checkpoint {weights} --unvalidated")
    with open(weights.replace(".safetensors", ".md"), encoding="utf-8") as handle:
        assert "Self-play: 2 episodes" in handle.read()
