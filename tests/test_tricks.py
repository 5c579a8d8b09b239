"""The users' tricks in problems/tricks (each a scene, a demonstration file, a distribution, the
extracted fragment with its anchors and a trained checkpoint; results/tricks has their held-out
runs): each demonstration still performs its trick and extracts to the committed fragment's
steps and anchors, and each distribution gives scenes that `check` accepts."""
from __future__ import annotations

import json
import os
import shutil

import pytest

from pdsketch_mech.commands import check as check_cli
from pdsketch_mech.commands import demo as demo_cli
from pdsketch_mech.commands import envs as envs_cli
from pdsketch_mech.commands import learn as learn_cli

from conftest import ROOT

TRICKS = os.path.join(ROOT, "problems", "tricks")
NAMES = sorted(n for n in os.listdir(TRICKS) if os.path.isdir(os.path.join(TRICKS, n)))


def _steps(fragment: str) -> list:
    """The fragment's mechanism steps, as written in its :actions (one per line), with what
    each says physics does after it (`:then`)."""
    text = open(fragment).read()
    lines = [line.strip() for line in text[text.index(":actions"):].splitlines()[1:]]
    return [line[:line.index(")") + 1] if line.startswith("(") else line.rstrip(")") for line in lines
            if line.startswith(("(", ":then"))]


@pytest.mark.parametrize("name", NAMES)
def test_a_tricks_demonstration_performs_it_and_extracts_to_the_committed_fragment(name, tmp_path, capsys):
    source = os.path.join(TRICKS, name)
    for suffix in (".pddl", ".demo.json"):
        shutil.copy(os.path.join(source, name + suffix), tmp_path / (name + suffix))
    assert demo_cli.main(["record", str(tmp_path / f"{name}.demo.json")]) == 0
    assert "holds" in capsys.readouterr().err
    fragment = tmp_path / f"{name}.mech.pddl"
    assert learn_cli.main(["extract", str(tmp_path / name), "--name", name, "--out", str(fragment)]) == 0
    committed = os.path.join(source, f"{name}.mech.pddl")
    assert _steps(str(fragment)) == _steps(committed)
    ours = json.loads((tmp_path / f"{name}.anchors.json").read_text())["variables"]
    theirs = json.load(open(os.path.join(source, f"{name}.anchors.json")))["variables"]
    assert ours.keys() == theirs.keys()


@pytest.mark.parametrize("name", NAMES)
def test_a_tricks_distribution_gives_scenes_check_accepts(name, tmp_path, capsys):
    for seed in (0, 1):
        out = tmp_path / f"{name}-{seed}.pddl"
        assert envs_cli.main([os.path.join(TRICKS, name, f"{name}.dist.json"), "--split", "train",
                              "--seed", str(seed), "--out", str(out)]) == 0
        assert check_cli.main([str(out)]) == 0, capsys.readouterr().err
