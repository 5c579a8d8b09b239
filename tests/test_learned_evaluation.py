"""`learn evaluate` (learning/evaluate.py): classifiers scored on self-play episodes they were
not trained on -- ranking figures per parameter, seen and held-out categories apart -- and
`learn selfplay --split dev`, whose data it reads and `train` refuses."""
from __future__ import annotations

import json
import os

import numpy as np
import pytest

from pdsketch_mech.commands import learn
from pdsketch_mech.learning.evaluate import ContextScore, score_episodes, summarise
from pdsketch_mech.learning.sampler_training import TrainConfig, train_mechanism

from conftest import ROOT
from learned_data import TINY, synthetic_episodes


@pytest.fixture(scope="module")
def trained():
    model, _ = train_mechanism(synthetic_episodes(30), TrainConfig(epochs=40, encoder=TINY, seed=1))
    return model


def test_a_classifier_that_learned_the_rule_finds_the_used_grasp_sooner_than_random_order(trained):
    fresh = synthetic_episodes(12, seed=7)                      # never trained on
    held_out = {int(ep["episode_id"][0]): int(ep["episode_id"][0]) % 3 == 0 for ep in fresh}
    scored = score_episodes(trained, fresh, held_out)
    grasps = scored["?g"]
    assert grasps and all(isinstance(r, ContextScore) for r in grasps)
    assert np.median([r.auc for r in grasps]) > 0.9
    assert np.median([r.gain for r in grasps]) > 1.5            # the used grasp comes well before random order's
    assert all(r.position <= r.proposals - r.used + 1 for r in grasps)
    rows = {(r.variable, r.group): r for r in summarise(trained, scored)}
    groups = [rows[("?g", g)].contexts for g in ("seen categories", "held-out categories", "all")]
    assert groups[0] + groups[1] == groups[2] == len(grasps) and groups[1] == sum(r.held_out for r in grasps)


def test_a_classifier_that_ranks_backwards_scores_below_random(trained):
    flipped = synthetic_episodes(12, seed=7)
    for ep in flipped:  # the used grasps are now on the -x half: the learned rule is wrong
        ep["value"][:-1, 0] *= -1
        ep["proposal"] = ep["value"]
    scored = score_episodes(trained, flipped, {int(ep["episode_id"][0]): False for ep in flipped})
    assert np.median([r.auc for r in scored["?g"]]) < 0.4
    assert np.median([r.gain for r in scored["?g"]]) < 1


def test_evaluate_cli_says_what_to_run_when_there_is_no_test_data(tmp_path, capsys):
    assert learn.main(["evaluate", "com", "--data", str(tmp_path / "none")]) == 2
    assert learn.main(["evaluate", "com"]) in (0, 2)            # out/selfplay-dev/com may exist on a dev machine
    err = capsys.readouterr().err.strip().splitlines()
    assert err[0] == f"error: {tmp_path / 'none'}: no such folder"


def test_a_fragment_without_the_mechanism_is_named_in_the_error(capsys):
    fragment = os.path.join(ROOT, "domains", "mechanisms", "hook-use.pddl")
    assert learn.main(["evaluate", "com", "--fragment", fragment]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"error: no mechanism named com in {fragment} (it has: hook-use)"]


def test_selfplay_on_the_dev_split_then_evaluate_and_train_refuses_that_folder(tmp_path, capsys):
    data = str(tmp_path / "test-data")
    assert learn.main(["selfplay", "com", "--split", "dev", "--episodes", "2", "--budget", "40", "--out", data]) == 0
    with open(f"{data}/manifest.json") as handle:
        assert json.load(handle)["config"]["split"] == "dev"
    status = learn.main(["evaluate", "com", "--data", data, "--json", str(tmp_path / "e.json")])
    out = capsys.readouterr()
    assert status in (0, 1) and "| parameter |" in out.out and "evaluate com:" in out.err
    refused = learn.main(["train", "com", "--episodes", "2", "--out", data, "--checkpoint",
                          str(tmp_path / "c.samplers.safetensors")])
    err = capsys.readouterr().err.strip().splitlines()
    assert refused == 2 and err[-1].startswith("error: ") and "split 'dev' (this run: 'train')" in err[-1]


def test_evaluate_refuses_data_recorded_with_another_context_count(tmp_path, capsys):
    """The committed Center-of-Mass checkpoint sees the mechanism's objects only; episodes
    that also recorded the nearest body have one object more than its classifiers read."""
    data = str(tmp_path / "wider")
    assert learn.main(["selfplay", "com", "--split", "dev", "--episodes", "1", "--budget", "40", "--context", "1",
                       "--out", data]) == 0
    capsys.readouterr()
    assert learn.main(["evaluate", "com", "--data", data]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {data}: self-play recorded 1 context object(s)")
    assert err[0].endswith("play the data with --context 0")


def test_evaluate_refuses_data_played_with_another_definition_of_the_mechanism(tmp_path, capsys):
    data = str(tmp_path / "old")
    assert learn.main(["selfplay", "com", "--split", "dev", "--episodes", "1", "--budget", "40", "--out", data]) == 0
    capsys.readouterr()
    with open(f"{data}/manifest.json") as handle:
        manifest = json.load(handle)
    manifest["config"]["mechanism_hash"] = "0" * 64      # as if the fragment had been edited since
    with open(f"{data}/manifest.json", "w") as handle:
        json.dump(manifest, handle)
    assert learn.main(["evaluate", "com", "--data", data]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "holds self-play episodes of another definition of mechanism com" in err[0]
