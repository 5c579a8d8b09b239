"""`python -m pdsketch_mech.learn extract DEMO`: a recorded demonstration -> a mechanism fragment.

    extract DEMO [--name NAME] [--out FILE.pddl] [--render FILE.png] [--force]
        Segment the recording DEMO (NAME.npz, NAME.json or NAME) by contact modes, map the
        segments to basis operators, lift them to a mechanism and write it with the
        language's writer to FILE (default domains/mechanisms/NAME.pddl; NAME defaults to the
        recording's task). The timeline (frames, time, contact mode, supports, basis step) is
        printed on stdout. --render draws it under key frames. An existing FILE that differs
        from what would be written is kept (exit 2, saying what differs) unless --force.

Exit status: 0 written (or already up to date), 1 the demonstration cannot be turned into a
mechanism (e.g. cut off before its goal holds), 2 bad input (one `error:` line).
"""
from __future__ import annotations

import os
import re
import sys
import time
from typing import List, Optional, Sequence

from .cli import EXIT_BAD_INPUT, EXIT_OK, EXIT_UNSOLVED, ArgumentParser, output_error, run_and_exit
from .lang.errors import PddlError, escape

NAME = re.compile(r"^[a-z][a-z0-9_-]*$")


def _fail(message: str, status: int = EXIT_BAD_INPUT) -> int:
    print(escape(f"error: {message}"), file=sys.stderr)
    return status


def _parser() -> ArgumentParser:
    parser = ArgumentParser(prog="python -m pdsketch_mech.learn", description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", parser_class=ArgumentParser)
    ext = commands.add_parser("extract", help="a recorded demonstration -> domains/mechanisms/NAME.pddl")
    ext.add_argument("demo", metavar="DEMO", help="a recording (NAME.npz, NAME.json or NAME)")
    ext.add_argument("--name", help="the mechanism's (and fragment's domain) name (default: the recording's task)")
    ext.add_argument("--out", metavar="FILE.pddl", help="where to write (default domains/mechanisms/NAME.pddl)")
    ext.add_argument("--render", metavar="FILE.png", help="draw the timeline under key frames")
    ext.add_argument("--force", action="store_true", help="replace an existing fragment that differs")
    return parser


def _command_line(demo: str, name: str, out: str, default_out: str) -> str:
    """How to re-run this extraction, with paths relative to the repository when inside it."""
    from .learning.extract import REPO_ROOT

    def rel(path: str) -> str:
        full = os.path.abspath(path)
        inside = os.path.commonpath([full, REPO_ROOT]) == REPO_ROOT
        return os.path.relpath(full, REPO_ROOT) if inside else full

    words = ["python -m pdsketch_mech.learn extract", rel(demo), "--name", name]
    if os.path.abspath(out) != os.path.abspath(default_out):
        words += ["--out", rel(out)]
    return " ".join(words)


def extract_command(args) -> int:
    from .learning.extract import MECHANISMS_DIR
    from .learning.recording import load_recording, recording_paths

    npz, js = recording_paths(args.demo)
    for path in (npz, js):
        if not os.path.isfile(path):
            return _fail(f"{path}: no such file")
    if args.name is not None and not NAME.match(args.name):
        return _fail(f"--name {args.name}: a name is a lower-case letter, then letters, digits, '-' or '_'")
    try:
        recording = load_recording(args.demo)
    except (ValueError, OSError, KeyError) as exc:
        return _fail(f"{args.demo}: cannot read the recording: {exc}")
    name = args.name or str(recording.header.get("task") or recording.header.get("name") or "")
    if not NAME.match(name):
        return _fail(f"{args.demo}: no usable name in the recording ({name!r}); give --name")
    default_out = os.path.join(MECHANISMS_DIR, f"{name}.pddl")
    out = args.out or default_out
    for error in (output_error(out, "--out", (npz, js), (".pddl",)),
                  output_error(args.render, "--render", (npz, js, out), (".png",))):
        if error is not None:
            return _fail(error.message)
    return _extract(args, recording, name, out, _command_line(npz, name, out, default_out))


def _extract(args, recording, name: str, out: str, command: str) -> int:
    from .learning.extract import check_fragment, extract, fragment_text, write_atomically
    from .learning.steps import ExtractionError
    from .learning.timeline import timeline_text

    start = time.perf_counter()
    try:
        extraction = extract(recording, name, args.demo)
    except ExtractionError as exc:
        return _fail(f"{args.demo}: {exc}", EXIT_UNSOLVED)
    except (KeyError, ValueError, IndexError) as exc:
        return _fail(f"{args.demo}: the recording is malformed ({type(exc).__name__}: {exc})")
    print(timeline_text(extraction))
    text = fragment_text(extraction, out, command)
    try:
        fragment = check_fragment(text, out)
    except PddlError as exc:  # a bug, not the user's fault: say so plainly
        return _fail(f"the extracted fragment does not check: {exc}")
    status = "wrote"
    if os.path.exists(out):
        with open(out, encoding="utf-8") as handle:
            existing_text = handle.read()
        if existing_text == text:
            status = "unchanged"
        elif not args.force:
            why = _what_differs(out, existing_text, text, fragment)
            return _fail(f"{os.path.relpath(out)} exists and differs: {why} (use --force to replace it)")
    if status == "wrote":
        write_atomically(out, text)
    steps = " ".join(st.text(extraction.names) for st in extraction.explanation.steps)
    print(f"{status} {os.path.relpath(out)}: mechanism {name}, {len(extraction.explanation.steps)} steps {steps}; "
          f"{time.perf_counter() - start:.1f} s", file=sys.stderr)
    if args.render:
        frames = _render(extraction, args.render)
        print(f"wrote {args.render} (key frames {', '.join(map(str, frames))})", file=sys.stderr)
    return EXIT_OK


def _what_differs(out: str, existing_text: str, new_text: str, fragment) -> str:
    """The mechanism-level differences, or else the first line where the texts differ."""
    from .lang.nodes import Domain
    from .lang.parser import parse_text
    from .learning.compare import differences

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
    what = "comments differ" if all(t.lstrip().startswith(";") for t in old[line:line + 1] + new[line:line + 1]) \
        else "text differs"
    return (f"the mechanism is the same up to variable names, but the {what} from line {line + 1} "
            f"({(old[line] if line < len(old) else '<end of file>').strip()[:60]!r})")


def _render(extraction, path: str) -> List[int]:
    import numpy as np

    from .envs.demos.show import camera_for, draw_contacts, replay_world, set_frame
    from .learning.timeline import key_frames, render_timeline
    from .world.render import render

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


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = _parser().parse_args(argv)
    if args.command is None:
        return _fail("give a command: extract")
    return {"extract": extract_command}[args.command](args)


if __name__ == "__main__":
    run_and_exit(main)
