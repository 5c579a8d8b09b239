"""`learn extract DEMO`: a recorded demonstration -> a mechanism fragment, written with the
language's writer, its timeline printed and (with --render) drawn under key frames. An
existing fragment that differs is kept unless --force, saying what differs."""
from __future__ import annotations

import os
import sys
import time
from typing import List, Optional, Tuple

from ..lang.errors import PddlError
from ..learning.paths import NAME, repo_path
from ..util.files import write_text
from .common import EXIT_OK, EXIT_UNSOLVED, fail, output_error, shown_path


def command_line(demo: str, name: str, out: str, default_out: str) -> str:
    """How to re-run this extraction."""
    words = ["python -m pdsketch_mech.learn extract", repo_path(demo), "--name", name]
    if os.path.abspath(out) != os.path.abspath(default_out):
        words += ["--out", repo_path(out)]
    return " ".join(words)


def extract_command(args) -> int:
    from ..learning.paths import MECHANISMS_DIR
    from ..world.recording import load_recording, recording_paths

    npz, js = recording_paths(args.demo)
    for path in (npz, js):
        if not os.path.isfile(path):
            return fail(f"{path}: no such file")
    if args.name is not None and not NAME.match(args.name):
        return fail(f"--name {args.name}: a name is a lower-case letter, then letters, digits, '-' or '_'")
    try:
        recording = load_recording(args.demo)
    except (ValueError, OSError, KeyError) as exc:
        return fail(f"{args.demo}: cannot read the recording: {exc}")
    name = args.name or str(recording.header.get("task") or recording.header.get("name") or "")
    if not NAME.match(name):
        return fail(f"{args.demo}: no usable name in the recording ({name!r}); give --name")
    default_out = os.path.join(MECHANISMS_DIR, f"{name}.pddl")
    out = args.out or default_out
    for error in (output_error(out, "--out", (npz, js), (".pddl",)),
                  output_error(args.render, "--render", (npz, js, out), (".png",))):
        if error is not None:
            return fail(error.message)
    return _extract(args, recording, name, out, command_line(npz, name, out, default_out))


def _extract(args, recording, name: str, out: str, command: str) -> int:
    from ..learning.extract import check_fragment, extract, fragment_text
    from ..learning.summary import mechanism_summary
    from ..learning.steps import ExtractionError
    from ..learning.timeline import timeline_text

    start = time.perf_counter()
    try:
        extraction = extract(recording, name, args.demo)
    except ExtractionError as exc:
        return fail(f"{args.demo}: {exc}", EXIT_UNSOLVED)
    except (KeyError, ValueError, IndexError) as exc:
        return fail(f"{args.demo}: the recording is malformed ({type(exc).__name__}: {exc})")
    print(timeline_text(extraction))
    text = fragment_text(extraction, out, command, sampler=named_sampler(out, name))
    try:
        fragment, actions = check_fragment(text, out)
    except PddlError as exc:  # a bug, not the user's fault: say so plainly
        return fail(f"the extracted fragment does not check: {exc}")
    status = "wrote"
    if os.path.exists(out):
        with open(out, encoding="utf-8") as handle:
            existing_text = handle.read()
        if existing_text == text:
            status = "unchanged"
        elif not args.force:
            why = _what_differs(out, existing_text, text, fragment)
            return fail(f"{shown_path(out)} exists and differs: {why} (use --force to replace it)")
    anchors_out, anchors = _anchors(extraction, out)
    anchors_status = "wrote"
    if os.path.exists(anchors_out):
        with open(anchors_out, encoding="utf-8") as handle:
            anchors_status = "unchanged" if handle.read() == anchors else anchors_status
        if anchors_status == "wrote" and not args.force:
            return fail(f"{shown_path(anchors_out)} exists and differs: another demonstration's values "
                        "(use --force to replace it)")
    if status == "wrote":
        write_text(out, text)
    if anchors_status == "wrote":
        write_text(anchors_out, anchors)
    steps = " ".join(st.text(extraction.names) for st in extraction.explanation.steps)
    print(f"{status} {shown_path(out)}: mechanism {name}, {len(extraction.explanation.steps)} steps {steps}; "
          f"{time.perf_counter() - start:.1f} s", file=sys.stderr)
    print(f"{anchors_status} {shown_path(anchors_out)}: what the demonstration did, which its samplers try first",
          file=sys.stderr)
    demo_objects = {variable: extraction.names[body] for body, variable in extraction.lifted.roles.items()}
    for line in mechanism_summary(fragment.mechanisms[0], demo_objects, actions):
        print("  " + line, file=sys.stderr)
    if args.render:
        frames = _render(extraction, args.render)
        print(f"wrote {args.render} (key frames {', '.join(map(str, frames))})", file=sys.stderr)
    return EXIT_OK


def _anchors(extraction, out: str) -> Tuple[str, str]:
    """(path, text) of the mechanism's anchors: what the demonstration did, beside the fragment."""
    from ..envs.demos.show import replay_world
    from ..learning.anchors import anchors_text, demonstration_anchors
    from ..learning.extract import load_basis
    from ..samplers.anchored import anchors_path

    with replay_world(extraction.segmentation.recording) as world:
        anchors = demonstration_anchors(extraction, load_basis(), world)
    return anchors_path(out, extraction.name), anchors_text(anchors)


def named_sampler(path: str, name: str) -> Optional[str]:
    """The learned sampler an existing fragment's mechanism `name` names (kept on re-extraction)."""
    from ..lang.nodes import Domain
    from ..lang.parser import parse_file
    try:
        existing = parse_file(path) if os.path.isfile(path) else None
    except PddlError:
        return None
    if not isinstance(existing, Domain):
        return None
    return next((m.sampler for m in existing.mechanisms if m.name == name), None)


def _what_differs(out: str, existing_text: str, new_text: str, fragment) -> str:
    """The mechanism-level differences, or else the first line where the texts differ."""
    from ..lang.nodes import Domain
    from ..lang.parser import parse_text
    from ..learning.compare import differences
    from ..samplers.learned.definition import mechanism_hash

    try:
        existing = parse_text(existing_text, file=out)
    except PddlError as exc:
        return f"it does not parse ({exc})"
    if not isinstance(existing, Domain) or len(existing.mechanisms) != 1:
        return "it is not a fragment with one mechanism"
    found = differences(existing.mechanisms[0], fragment.mechanisms[0])
    if found:
        return "; ".join(found)
    if existing.extends != fragment.extends:
        return f"it extends {', '.join(existing.extends)} instead of {', '.join(fragment.extends)}"
    old, new = existing_text.splitlines(), new_text.splitlines()
    line = next((i for i, (a, b) in enumerate(zip(old, new)) if a != b), min(len(old), len(new)))
    changed = [text for a, b in zip(old, new) if a != b for text in (a, b)]
    comments_only = len(old) == len(new) and all(t.lstrip().startswith(";") for t in changed)
    exact = mechanism_hash(existing.mechanisms[0]) == mechanism_hash(fragment.mechanisms[0])
    same = "the same" if exact else "the same up to variable names"
    shown = (old[line] if line < len(old) else "<end of file>").strip()[:60]
    if comments_only:
        return (f"the mechanism is {same}, only the comments differ (from line {line + 1}: {shown!r}; "
                "a new recording of the same demonstration changes its times)")
    return f"the mechanism is {same}, but the text differs from line {line + 1} ({shown!r})"


def _render(extraction, path: str) -> List[int]:
    import numpy as np

    from ..envs.demos.show import camera_for, draw_contacts, replay_world, set_frame
    from ..learning.timeline import key_frames, render_timeline
    from ..world.render import render

    recording = extraction.segmentation.recording
    frames = key_frames(extraction)
    camera = camera_for(recording, 320, 240)
    images = []
    with replay_world(recording) as world:
        for frame in frames:
            set_frame(world, recording, frame)
            images.append(np.asarray(draw_contacts(render(world, camera), world, camera, recording, frame)))
    render_timeline(extraction, path, frames, images)
    return frames
