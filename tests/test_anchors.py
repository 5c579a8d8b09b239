"""Demonstration anchors: `learn extract` keeps what the demonstration did (the grasp on the
tool, the contact with the target, how far it pulled) beside the fragment, and a mechanism's
samplers propose it, transferred to the scene, once per situation, then mixed with the
generic ones (learning/anchors.py, samplers/anchored.py)."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT

USER = os.path.join(ROOT, "problems", "contract", "user-mechanism")
SHELF_FAR = os.path.join(ROOT, "problems", "contract", "user-shelf-far.pddl")


def _extract(tmp_path, *extra):
    out = tmp_path / "shelf-pull.pddl"
    done = subprocess.run([sys.executable, "-m", "pdsketch_mech.learn", "extract", os.path.join(USER, "shelf-pull.npz"),
                           "--name", "shelf-pull", "--out", str(out), *extra], capture_output=True, text=True, cwd=ROOT)
    return done, out, tmp_path / "shelf-pull.anchors.json"


@pytest.fixture(scope="module")
def extracted(tmp_path_factory):
    done, out, anchors = _extract(tmp_path_factory.mktemp("anchors"))
    assert done.returncode == 0, done.stderr
    return out, anchors


def test_extraction_keeps_the_demonstrated_grasp_contact_and_pull_distance(extracted):
    _, anchors = extracted
    data = json.loads(anchors.read_text())
    variables = data["variables"]
    assert data["mechanism"] == "shelf-pull" and set(variables) == {"?g", "?c", "?t2"}
    assert variables["?g"]["kind"] == "grasp" and variables["?g"]["object"] == "?tool"
    contact = variables["?c"]
    assert contact["kind"] == "contact" and (contact["pusher"], contact["target"]) == ("?tool", "?target")
    # A pull: towards the robot, so against the reach frame's x (from the shoulder to the target).
    assert contact["in_reach"]["direction"][0] < -0.9
    assert 0.05 < variables["?t2"]["distance"] < 0.3


def test_re_extraction_keeps_the_anchors_and_refuses_other_values(extracted, tmp_path):
    out, anchors = extracted
    folder = tmp_path / "again"
    folder.mkdir()
    shutil.copy(out, folder / out.name)
    text = json.loads(anchors.read_text())
    text["variables"]["?t2"]["distance"] = 0.5   # someone else's demonstration
    (folder / anchors.name).write_text(json.dumps(text))
    done, _, kept = _extract(folder)
    assert done.returncode != 0 and "exists and differs" in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert json.loads(kept.read_text())["variables"]["?t2"]["distance"] == 0.5   # nothing overwritten
    done, _, kept = _extract(folder, "--force")
    assert done.returncode == 0 and json.loads(kept.read_text()) == json.loads(anchors.read_text())


def test_the_first_anchored_proposals_are_the_demonstrated_values_in_the_demonstrations_scene(extracted):
    from pdsketch_mech.lang.parser import parse_file
    from pdsketch_mech.samplers.anchored import contact_proposals, grasp_proposals, read_anchors
    from pdsketch_mech.samplers.budget import SamplerBudget
    from pdsketch_mech.samplers.geometry import pose_matrix
    from pdsketch_mech.world.build import build_world

    _, path = extracted
    anchors = read_anchors(str(path), "shelf-pull").variables
    rng, budget = np.random.default_rng(0), SamplerBudget()
    with build_world(parse_file(SHELF_FAR), visual=False) as world:   # the demonstration's own scene
        grasp = grasp_proposals(world, "hook", anchors["?g"], rng, budget).exact[0]
        assert np.allclose(grasp.in_object[0], anchors["?g"]["in_object"][0], atol=1e-3)
        assert 0.0 < grasp.width < 0.08   # the fingers close on the stick
        contact = contact_proposals(world, "box", "shelf", anchors["?c"], rng, budget).exact[0]
        expected = pose_matrix(world.pose("box")) @ pose_matrix(tuple(map(tuple, anchors["?c"]["in_target"]["pusher"])))
        assert np.allclose(contact.pushers[0], expected, atol=1e-3)


class _Generic:
    """A generic sampler stand-in whose proposals say where they came from."""

    budget = 10

    def propose(self, world, request, rng, budget):
        return (f"generic-{k}" for k in range(budget))


class _Scene:
    """Just what an anchored push reads of a world: where its objects lie, what is held."""

    attachment = None

    def __init__(self, box_x: float):
        self.bodies = {"box": None}
        self._box = ((box_x, 0.0, 0.02), (0.0, 0.0, 0.0, 1.0))

    def pose(self, name):
        return self._box


def test_the_demonstrated_value_is_proposed_once_per_situation_then_mixed_with_the_generic_ones():
    from pdsketch_mech.samplers.anchored import AnchoredSampler
    from pdsketch_mech.samplers.interface import SampleRequest

    sampler = AnchoredSampler(_Generic(), {"kind": "push", "distance": 0.125})
    request = SampleRequest("push", ("box", ("a contact",)), ("?o", "?c"))
    rng = np.random.default_rng(0)
    first = list(sampler.propose(_Scene(0.5), request, rng, 10))
    again = list(sampler.propose(_Scene(0.5), request, rng, 10))
    elsewhere = list(sampler.propose(_Scene(0.6), request, rng, 10))
    assert first[0] == 0.125 and elsewhere[0] == 0.125   # as demonstrated, in each new situation
    assert 0.125 not in again                            # the same situation: not again
    for proposals in (first[1:], again):
        generic = [v for v in proposals if isinstance(v, str)]
        spread = [v for v in proposals if not isinstance(v, str)]
        # both sources, neither shut out: the generic sampler's completeness is kept
        assert len(generic) >= 4 and 2 <= len(spread) <= 6 and all(0.01 <= v <= 0.6 for v in spread)
    assert sum(isinstance(v, str) for v in again[:6]) >= 2   # mixed in early, not after the spread ones
    assert {f"generic-{k}" for k in range(10)} <= set(again)


def test_a_malformed_anchors_file_is_one_located_line(extracted, tmp_path):
    out, _ = extracted
    shutil.copy(out, tmp_path / out.name)
    (tmp_path / "shelf-pull.anchors.json").write_text('{"schema": 1, "mechanism": "other", "variables": {}}')
    done = subprocess.run([sys.executable, "-m", "pdsketch_mech.plan", "basis", SHELF_FAR, "--mechanisms",
                           str(tmp_path / out.name), "--timeout", "20"], capture_output=True, text=True, cwd=ROOT)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2 and len(lines) == 1 and "shelf-pull.pddl:" in lines[0] and "anchors" in lines[0]


def test_an_anchored_pull_off_a_shelf_plans_where_generic_samplers_do_not(extracted):
    """The demonstration's own scene: the anchored mechanism alone pulls the box down onto the
    table at once; without anchors (the generic-sampler ablation) its pull rarely drops it."""
    from pdsketch_mech.api.planner import Planner

    out, _ = extracted
    document = Planner("basis", [str(out)]).plan(SHELF_FAR, timeout=60, validate=True)
    assert document["status"] == "solved" and document["replay"]["goal_reached"]
    assert [entry["mechanism"] for entry in document["plan"]] == ["shelf-pull"] * 3
    assert document["stats"]["proposals"]["anchored"].get("push-motion", 0) >= 1


def test_extraction_says_in_plain_words_what_the_mechanism_needs_and_what_it_left_open(tmp_path):
    done, _, _ = _extract(tmp_path)
    err = done.stderr
    assert "shelf-pull needs: the hand is empty; ?tool (hook) rests on ?support (table)" in err
    assert "shelf-pull certifies: ?target rests on ?support; the hand is empty" in err
    assert "may be one object or two: ?support and ?target-support" in err
