"""Mechanism extraction (`learning/`): segmentation of the committed recordings by contact
modes, the basis steps they map to, lifting to fragments, and the `learn extract` command.

The expected step sequences below were written from the demo scripts (and the paper's
descriptions of the six mechanisms) before extraction was run on the recordings; steps are
grounded on the demo's objects here, which the extractor itself never reads by name."""
from __future__ import annotations

import os

import pytest

from conftest import ROOT

DEMOS_DIR = os.path.join(ROOT, "domains", "mechanisms", "demos")

# (operator, object arguments...) per committed demonstration.
EXPECTED_STEPS = {
    # push the flat object with the bare (closed) fingers towards the edge, then pinch the overhang
    "edge": [("transit-cont", "flat", "table"), ("grasp", "flat", "table")],
    # the paper's Fig. 3b: grasp the tool, pull the target with it, put the tool back, grasp the target
    "hook": [("grasp", "tool", "table"), ("move-cont", "tool", "target", "table"),
             ("place", "tool", "table"), ("grasp", "target", "table")],
    # put the heavy object on the plate's overhang (the plate tips up), grasp the plate off its ledge
    "lever": [("grasp", "weight", "table"), ("place", "weight", "plate"), ("grasp", "plate", "ledge")],
    # the same contact sequence as Hook: the held stick pushes the block out of the tunnel
    "poking": [("grasp", "tool", "table"), ("move-cont", "tool", "target", "table"),
               ("place", "tool", "table"), ("grasp", "target", "table")],
    # grasp the overhanging plate, put it on the small block
    "com": [("grasp", "flat", "table"), ("place", "flat", "pedestal")],
    # lay the blocker on the slope, then put the block on the slope (it slides onto the blocker)
    "slope-blocker": [("grasp", "blocker", "table"), ("place", "blocker", "slope"),
                      ("grasp", "block", "table"), ("place", "block", "slope")],
    # Beyond the paper, demonstrated as files (NAME.demo.json): push a box across a gap with a
    # held stick (no grasp of the box: it ends beyond reach) ...
    "gap-push": [("grasp", "stick", "table"), ("move-cont", "stick", "target", "table"),
                 ("place", "stick", "table")],
    # ... and let a block go on a ramp it slides off onto a platform beyond reach: the place is
    # grounded on the ramp, where the robot let go; the goal says where it ends up.
    "ramp-slide": [("grasp", "block", "table"), ("place", "block", "ramp")],
}

import json
import re
import subprocess
import sys

import numpy as np

from pdsketch_mech.commands import learn_extract as extract_command
from pdsketch_mech.lang import nodes as n
from pdsketch_mech.lang.loader import load_domain, load_problem, read_domain_file
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.learning.compare import differences, equivalent
from pdsketch_mech.learning.extract import extract, fragment_text
from pdsketch_mech.learning.paths import MECHANISMS_DIR
from pdsketch_mech.world.recording import load_recording, save_recording
from pdsketch_mech.learning.segmentation import debounce
from pdsketch_mech.learning.steps import ExtractionError

FRAGMENT = {"hook": "hook-use"}          # the Hook mechanism keeps the paper's name
BASIS = os.path.join(ROOT, "domains", "basis.pddl")

# The hand-written fragment of the paper's Fig. 3b that the extracted hook-use.pddl replaced.
HAND_WRITTEN_HOOK_USE = """
(define (domain hook-use)
  (:extends "../basis.pddl")
  (:requirements :mechanisms)
  (:mechanism hook-use
    :parameters (?tool - item ?target - item ?support - item
                 ?g1 - grasp ?t1 - traj
                 ?c - contact ?t2 - traj
                 ?p - placement ?t3 - traj
                 ?g2 - grasp ?t4 - traj)
    :precondition (and (handempty) (support ?tool ?support) (support ?target ?support)
                       (not (= ?tool ?target)))
    :certified (holding ?target)
    :actions (
      (grasp ?tool ?support ?g1 ?t1)
      (move-cont ?tool ?target ?support ?c ?t2)
      (place ?tool ?support ?p ?t3)
      (grasp ?target ?support ?g2 ?t4))))
"""

_cache = {}


def extracted(demo: str):
    if demo not in _cache:
        path = os.path.join(DEMOS_DIR, demo)
        _cache[demo] = extract(load_recording(path), FRAGMENT.get(demo, demo), path)
    return _cache[demo]


def grounded(extraction):
    names = extraction.names
    return [(st.operator, *(names[o] for o in st.objects)) for st in extraction.explanation.steps]


def run_cli(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "pdsketch_mech.learn", *args], cwd=cwd, capture_output=True,
                          text=True, env={**os.environ, "PYTHONPATH": ROOT})


# ----------------------------------------------------------------------------- segmentation
def test_debounce_removes_flicker_and_keeps_long_runs():
    signal = np.array([0] * 20 + [1] * 3 + [0] * 20 + [1] * 30 + [0] * 2 + [1] * 30, dtype=bool)
    out = debounce(signal, 9)
    assert not out[:43].any()                  # the 3-frame blip is gone
    assert out[43:].all()                      # the 2-frame gap inside the long contact is filled
    assert debounce(np.ones(5, bool), 9).all() and not debounce(np.zeros(5, bool), 9).any()


@pytest.mark.parametrize("demo", sorted(EXPECTED_STEPS))
def test_committed_demo_yields_the_expected_steps(demo):
    assert grounded(extracted(demo)) == EXPECTED_STEPS[demo]


def test_brushes_and_release_grazes_make_no_segments():
    # Lever: a finger grazes the falling weight for 5 frames after the release, and one touches
    # the plate for 2 frames on the way to the rim grasp. Edge: one finger reaches the plate's
    # rim 3 frames before the other. None of these is a segment of its own.
    lever = extracted("lever").segmentation
    assert [s.mode.describe(lever.bodies.names) for s in lever.segments] == [
        "free", "holds weight", "free", "holds plate"]
    edge = extracted("edge").segmentation
    assert [s.mode.describe(edge.bodies.names) for s in edge.segments] == [
        "free", "hand pushes flat", "free", "holds flat"]


def test_a_closed_hand_pushing_with_both_fingertips_is_not_a_grasp():
    seg = extracted("edge").segmentation
    push = seg.segments[1]
    assert push.mode.held is None and seg.time(push.end) - seg.time(push.start) > 1.0


def test_extraction_reads_no_object_names(tmp_path):
    """Renaming (and swapping) the demo's objects changes nothing but the comments."""
    recording = load_recording(os.path.join(DEMOS_DIR, "hook"))
    swap = {"table": "b1", "tool": "target", "target": "tool"}
    header = json.loads(json.dumps(recording.header))
    for body in header["bodies"]:
        body["name"] = swap.get(body["name"], body["name"])
    header["objects"] = [swap.get(o, o) for o in header["objects"]]
    header["problem"] = re.sub(r"\b(table|tool|target)\b(?!\")", lambda m: swap[m.group(1)], header["problem"])
    save_recording(str(tmp_path / "renamed"), recording.arrays, header)
    renamed = extract(load_recording(str(tmp_path / "renamed")), "hook-use")
    assert renamed.lifted.mechanism == extracted("hook").lifted.mechanism
    assert grounded(renamed)[0] == ("grasp", "target", "b1")   # the demo's "tool" is now called target


# ----------------------------------------------------------------------------- lifting
def test_hook_use_is_the_papers_fig_3b_up_to_variable_names():
    hand = parse_text(HAND_WRITTEN_HOOK_USE).mechanisms[0]
    mechanism = extracted("hook").lifted.mechanism
    assert equivalent(hand, mechanism)
    assert mechanism == hand  # even the variable names agree


def test_differences_are_reported():
    hook = extracted("hook").lifted.mechanism
    fewer = n.Mechanism(hook.name, hook.parameters, n.And(hook.precondition.parts[:-1]), hook.certified, hook.actions)
    assert differences(fewer, hook) == ["the precondition: only the extracted one has (not (= ?tool ?target))"]
    renamed = parse_text(HAND_WRITTEN_HOOK_USE.replace("?tool", "?stick")).mechanisms[0]
    assert differences(renamed, hook) == []
    shorter = n.Mechanism(hook.name, hook.parameters, hook.precondition, hook.certified, hook.actions[:3])
    assert differences(shorter, hook)[0].startswith("the steps:")


@pytest.mark.parametrize("demo", sorted(EXPECTED_STEPS))
def test_committed_fragment_is_what_extraction_writes(demo):
    name = FRAGMENT.get(demo, demo)
    path = os.path.join(MECHANISMS_DIR, f"{name}.pddl")
    npz = os.path.join(DEMOS_DIR, f"{demo}.npz")
    command = extract_command.command_line(npz, name, path, path)
    sampler = extract_command.named_sampler(path, name)   # `learn train` adds it; extraction keeps it
    with open(path, encoding="utf-8") as handle:
        assert handle.read() == fragment_text(extracted(demo), path, command, sampler=sampler)
    loaded = load_domain([path])                  # parses and type-checks with the basis
    assert loaded.names == {"mech-basis", name} and [m.name for m in loaded.domain.mechanisms] == [name]


def test_roles_name_the_variables():
    params = {demo: [p.name for p in extracted(demo).lifted.mechanism.parameters if p.type == "item"]
              for demo in EXPECTED_STEPS}
    assert params == {
        "edge": ["?target", "?support"],
        "hook": ["?tool", "?target", "?support"],
        "lever": ["?weight", "?target", "?support", "?target-support"],
        "poking": ["?tool", "?target", "?support"],
        "com": ["?target", "?support", "?surface"],
        "slope-blocker": ["?blocker", "?target", "?support", "?surface"],
        "gap-push": ["?tool", "?target", "?support", "?landing"],
        "ramp-slide": ["?target", "?support", "?surface", "?landing"],
    }
    # The ramp neither the start nor the goal mentions is pinned by what the demonstration
    # shows of it: fixed, and none of the other objects.
    ramp = extracted("ramp-slide").lifted.mechanism.precondition.parts
    assert n.Atom("fixed", (n.Var("?surface"),)) in ramp
    assert n.Not(n.Equals(n.Var("?surface"), n.Var("?landing"))) in ramp
    # The platform the box is pushed onto, which only the goal names, is pinned likewise:
    # fixed, and neither the table it started on nor the box.
    gap = extracted("gap-push").lifted.mechanism.precondition.parts
    assert n.Atom("fixed", (n.Var("?landing"),)) in gap
    assert n.Not(n.Equals(n.Var("?landing"), n.Var("?support"))) in gap
    com = extracted("com").lifted.mechanism
    assert n.Not(n.Atom("support", (n.Var("?target"), n.Var("?support")))) in com.certified.parts


def test_each_fragment_grounds_in_its_canonical_problem_as_the_demonstrated_steps(tmp_path):
    """The problem's (:domain mech-basis) resolves to the fragment, and one of the mechanism's
    macros grounded on the problem's objects is the demonstration's step sequence."""
    from pdsketch_mech.envs import sample
    from pdsketch_mech.envs.task_names import resolve_task
    from pdsketch_mech.planner.bilevel import prepare_task
    for demo, expected in EXPECTED_STEPS.items():
        problem_path = tmp_path / f"{demo}.pddl"
        problem_path.write_text(sample(resolve_task(demo), "train", None).problem_text())
        domain = load_domain([os.path.join(MECHANISMS_DIR, f"{FRAGMENT.get(demo, demo)}.pddl")])
        loaded, problem = load_problem(str(problem_path), [domain])
        assert loaded is domain
        task, _ = prepare_task(loaded, problem, use_mechanisms=True)
        grounded = [[_objects_of(task.operators[step]) for step in macro.steps]
                    for macro in task.operators if macro.steps]
        assert expected in grounded, (demo, grounded)


def _objects_of(operator) -> tuple:
    """(name, object arguments...) of a grounded operator: its continuous values left out."""
    return (operator.name,) + tuple(arg for arg in operator.args if not arg.startswith("#"))


# ----------------------------------------------------------------------------- bad recordings
def _cut(tmp_path, fraction: float, fix_header: bool = True) -> str:
    recording = load_recording(os.path.join(DEMOS_DIR, "hook"))
    frames = int(recording.frames * fraction)
    a = recording.arrays
    offsets = a["contact_offsets"][:frames + 1]
    arrays = {k: (v[:frames] if k in ("time", "step", "joints", "fingers", "gripper_opening", "poses") else v)
              for k, v in a.items()}
    arrays["contact_offsets"] = offsets
    for k in a:
        if k.startswith("contact_") and k != "contact_offsets":
            arrays[k] = a[k][:offsets[-1]]
    header = dict(recording.header, frames=frames if fix_header else recording.frames)
    path = str(tmp_path / f"cut-{fraction}-{fix_header}")
    save_recording(path, arrays, header)
    return path


def test_a_recording_cut_off_midway_is_an_error_not_a_fragment(tmp_path):
    with pytest.raises(ExtractionError, match=r"the goal \(holding target\) does not hold when the recording ends"):
        extract(load_recording(_cut(tmp_path, 0.6)), "hook-use")
    with pytest.raises(ExtractionError, match="header says"):
        extract(load_recording(_cut(tmp_path, 0.6, fix_header=False)), "hook-use")


def test_cli_refuses_a_cut_off_recording(tmp_path):
    out = tmp_path / "frag.pddl"
    result = run_cli("extract", _cut(tmp_path, 0.5), "--name", "cut", "--out", str(out))
    assert result.returncode == 1 and not out.exists()
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("error: ") and "cut off" in result.stderr
    assert "Traceback" not in result.stderr


# ----------------------------------------------------------------------------- the command
def test_cli_writes_the_timeline_and_the_fragment_and_keeps_a_different_one(tmp_path):
    out = tmp_path / "hook-use.pddl"
    first = run_cli("extract", os.path.join(DEMOS_DIR, "hook.npz"), "--name", "hook-use", "--out", str(out))
    assert first.returncode == 0, first.stderr
    lines = first.stdout.splitlines()
    assert lines[0].split()[:3] == ["frames", "time", "(s)"] and len(lines) == 7
    assert "2 (move-cont tool target table)" in lines[3] and "holds tool, tool pushes target" in lines[3]
    assert first.stderr.startswith("wrote ")
    fragment = read_domain_file(str(out))
    assert fragment.mechanisms[0] == extracted("hook").lifted.mechanism
    # Wherever the fragment is written (a checkout under /tmp shares /tmp with tmp_path), its
    # :extends names this checkout's basis file.
    # Outside the shipped domains, a fragment names the shipped basis, not this checkout's path.
    assert fragment.extends == ("basis",)
    again = run_cli("extract", os.path.join(DEMOS_DIR, "hook.npz"), "--name", "hook-use", "--out", str(out))
    assert again.returncode == 0 and again.stderr.startswith("unchanged ")
    out.write_text(out.read_text().replace("(not (= ?tool ?target))", ""))
    refused = run_cli("extract", os.path.join(DEMOS_DIR, "hook.npz"), "--name", "hook-use", "--out", str(out))
    assert refused.returncode == 2 and refused.stderr.count("\n") == 1
    assert "differs: the precondition: only the extracted one has (not (= ?tool ?target))" in refused.stderr
    assert "--force" in refused.stderr and "(not (= ?tool ?target))" not in out.read_text()
    forced = run_cli("extract", os.path.join(DEMOS_DIR, "hook.npz"), "--name", "hook-use", "--out", str(out),
                     "--force")
    assert forced.returncode == 0 and "(not (= ?tool ?target))" in out.read_text()
    # A new recording of the same demonstration changes only the step times in the comments.
    as_extracted = out.read_text()
    out.write_text(as_extracted.replace(" at ", " at 1", 1))
    retimed = run_cli("extract", os.path.join(DEMOS_DIR, "hook.npz"), "--name", "hook-use", "--out", str(out))
    assert retimed.returncode == 2 and "the mechanism is the same, only the comments differ" in retimed.stderr
    out.write_text(as_extracted)
    # A fragment that names a learned sampler keeps naming it when re-extracted.
    (tmp_path / "hook-use.samplers.safetensors").write_bytes(b"")
    out.write_text(out.read_text().replace("(grasp ?target ?support ?g2 ?t4))))",
                                           '(grasp ?target ?support ?g2 ?t4))\n    :sampler "hook-use.samplers.safetensors"))'))
    assert read_domain_file(str(out)).mechanisms[0].sampler == "hook-use.samplers.safetensors"
    kept = run_cli("extract", os.path.join(DEMOS_DIR, "hook.npz"), "--name", "hook-use", "--out", str(out), "--force")
    assert kept.returncode == 0 and kept.stderr.startswith("unchanged "), kept.stderr


@pytest.mark.parametrize("args, message", [
    (["extract", "nowhere.npz"], "nowhere.npz: no such file"),
    (["extract", "HOOK", "--out", "frag.txt"], "the file name must end in .pddl"),
    (["extract", "HOOK", "--out", "no/such/dir/f.pddl"], "does not exist"),
    (["extract", "HOOK", "--out", "f.pddl", "--render", "t.gif"], "must end in .png"),
    (["extract", "HOOK", "--name", "Bad Name", "--out", "f.pddl"], "--name Bad Name"),
    (["extract"], "the following arguments are required"),
    ([], "give a command"),
])
def test_cli_bad_input_is_one_line_and_exit_2(tmp_path, args, message):
    args = [os.path.join(DEMOS_DIR, "hook.npz") if a == "HOOK" else a for a in args]
    result = run_cli(*args, cwd=str(tmp_path))
    assert result.returncode == 2, result.stderr
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("error: ") and message in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_cli_renders_the_timeline(tmp_path):
    png = tmp_path / "timeline.png"
    result = run_cli("extract", os.path.join(DEMOS_DIR, "com.npz"), "--out", str(tmp_path / "com.pddl"),
                     "--render", str(png))
    assert result.returncode == 0, result.stderr
    from PIL import Image
    with Image.open(png) as image:
        assert image.size[0] > 800 and image.size[1] > 400
