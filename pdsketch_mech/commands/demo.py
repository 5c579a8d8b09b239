"""`python -m pdsketch_mech.demo record|show|list`: scripted demonstrations, recorded as raw
simulation data, and pictures of recordings.

    record FILE.demo.json|FILE.py [--seed N] [--out DIR] [--force] [--render FILE.gif] [--strip FILE.png]
        Perform a demonstration of your own (docs/demonstrations.md) in the scene of its problem
        file and record it into DIR/STEM.npz + STEM.json (default DIR: the demonstration's
        folder; with --seed, on a perturbed scene, STEM-seed-N.*). Exit 2 with one located
        line for a malformed file, 1 if a step cannot be done or the goal does not hold.
    record NAME [--seed N] [--split train|dev|test] [--variant V] [--out DIR] [--force] [--render FILE.gif] [--strip FILE.png]
        Run the built-in scripted demonstration NAME (a task: edge, hook, lever, poking, com,
        slope-blocker) on the task's canonical instance, or with --seed on one with perturbed
        poses, recording the world at 60 Hz into DIR/NAME.npz + DIR/NAME.json (default DIR:
        domains/mechanisms/demos; created with its parents if missing; with --seed the files
        are NAME-SPLIT-SEED.*). Exit 1 with
        one line if the script fails or the goal does not hold in the contact graph at the
        end (nothing is written); an existing recording is only replaced with --force.
        --variant distractor-push adds a block the hand pushes aside before the script runs
        (files NAME-distractor-push[-SPLIT-SEED].*), to test extraction on a demo that does
        more than the trick.
    show FILE [--render FILE.gif] [--strip FILE.png] [--every K]
        Replay a recording's poses in a world built from its own problem text: a GIF (every
        K-th frame, default 8) and/or a strip of key frames with the contact points drawn
        (red: robot-object, blue: object-object).
    list
        The demonstrations and what they do.

Exit status: 0 done, 1 the demonstration failed, 2 bad input (one `error:` line).
"""
from __future__ import annotations

import os
import sys
import time
from typing import Optional, Sequence

from ..util.data import data_path
from .common import (
    ArgumentParser, EXIT_OK, EXIT_UNSOLVED, existing_recording, fail, folder_ok, output_folder, whole,
)

DEMOS_DIR = data_path("domains", "mechanisms", "demos")


def is_user_demo(name: str) -> bool:
    """A demonstration file or script (a path), not a built-in demonstration's name."""
    return name.endswith((".json", ".py")) or os.sep in name or os.path.isfile(name)


def record(args) -> int:
    from ..envs.demos.run import DEMOS
    from ..envs.tasks import TASKS
    from ..world.recording import RecordingExists, save_recording

    if is_user_demo(args.name):
        from .demo_user import record_user
        return record_user(args)
    args.split = args.split or "train"
    if args.name in TASKS and args.name not in DEMOS:
        return fail(f"task '{args.name}' has no demonstration: it is solved by composing the learned "
                    f"mechanisms; demonstrations: {', '.join(DEMOS)}")
    if args.name not in DEMOS:
        return fail(f"unknown demonstration '{args.name}'; demonstrations: {', '.join(DEMOS)}")
    for extra in (args.render, args.strip):
        if not folder_ok(extra):
            return fail(f"{extra}: its folder does not exist")
    out = os.path.abspath(args.out or DEMOS_DIR)
    problem = output_folder(out, "--out") if args.out is not None else None
    if problem is not None:
        return fail(problem)
    stem = args.name + (f"-{args.variant}" if args.variant else "")
    stem += "" if args.seed is None else f"-{args.split}-{args.seed}"
    base = os.path.join(out, stem)
    taken = None if args.force else existing_recording(base)
    if taken:
        return fail(taken)

    from ..envs.demos.run import demo_instance, run_demo
    from ..envs.demos.variants import VARIANTS

    start = time.perf_counter()
    instance = demo_instance(args.name, args.split, args.seed)
    before = None
    if args.variant:
        change, before_script = VARIANTS[args.variant]
        instance = change(instance)
        before = (lambda world: before_script(world, instance))
    result = run_demo(args.name, instance, on_world=before)
    task = TASKS[args.name]
    if result.error:
        return fail(f"demo {args.name} ({instance.name}) failed: {result.error}", EXIT_UNSOLVED)
    if not result.goal_reached:
        return fail(f"demo {args.name} ({instance.name}): the goal {task.goal} does not hold at the end; "
                    f"contacts: {result.facts_text()}", EXIT_UNSOLVED)
    header = result.extra["header"]
    header.update({
        "name": stem,
        "task": task.name,
        "mechanism": task.title,
        "split": args.split,
        "seed": args.seed,
        "instance": instance.name,
        "problem_command": instance.command(),
        "problem_file": f"{instance.name}.pddl",
        "problem": instance.problem_text(),
        "goal": task.goal,
        "goal_achieved": True,
        "final_contacts": result.facts_text(),
        "script": f"pdsketch_mech/envs/demos/{'slope' if task.name == 'slope-blocker' else task.name}.py",
        "command": "python -m pdsketch_mech.demo record " + args.name
                   + ("" if args.seed is None else f" --seed {args.seed} --split {args.split}")
                   + (f" --variant {args.variant}" if args.variant else ""),
    })
    if args.variant:
        header["variant"] = args.variant
    try:
        npz, js = save_recording(base, result.extra["arrays"], header, force=args.force)
    except RecordingExists as exc:  # appeared meanwhile
        return fail(str(exc))
    size = os.path.getsize(npz) + os.path.getsize(js)
    print(f"wrote {os.path.relpath(npz)} + .json: {header['frames']} frames at {header['rate_hz']:g} Hz "
          f"({header['duration_s']:.1f} s simulated), {header['contacts']} contact points, {size / 1e6:.2f} MB; "
          f"goal {task.goal} holds; {time.perf_counter() - start:.1f} s", file=sys.stderr)
    if args.render or args.strip:
        return _show(npz, args.render, args.strip, 8)
    return EXIT_OK


def _show(path: str, gif: Optional[str], strip: Optional[str], every: int) -> int:
    from ..envs.demos.show import render_gif, render_strip
    from ..world.recording import load_recording

    recording = load_recording(path)
    if gif:
        n = render_gif(recording, gif, every=every)
        print(f"wrote {gif} ({n} frames)", file=sys.stderr)
    if strip:
        frames = render_strip(recording, strip)
        print(f"wrote {strip} (frames {', '.join(map(str, frames))})", file=sys.stderr)
    return EXIT_OK


def show(args) -> int:
    from ..world.recording import recording_paths

    npz, js = recording_paths(args.file)
    for path in (npz, js):
        if not os.path.isfile(path):
            return fail(f"{path}: no such file")
    for extra in (args.render, args.strip):
        if not folder_ok(extra):
            return fail(f"{extra}: its folder does not exist")
    if not (args.render or args.strip):
        return fail("nothing to do: give --render FILE.gif and/or --strip FILE.png")
    try:
        return _show(args.file, args.render, args.strip, args.every)
    except ValueError as exc:
        return fail(str(exc))


def list_demos(args) -> int:
    from ..envs.demos.run import DEMOS
    from ..envs.tasks import TASKS

    for task in TASKS.values():
        if task.name in DEMOS:
            print(f"{task.name:14s} {task.title}: {task.demo}")
    return EXIT_OK


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = ArgumentParser(prog="python -m pdsketch_mech.demo", description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", parser_class=ArgumentParser)
    rec = commands.add_parser("record", help="run and record a scripted demonstration")
    rec.add_argument("name", metavar="NAME|FILE", help="a built-in demonstration (a task name), or a demonstration "
                                                       "file (.demo.json) or script (.py) of your own")
    rec.add_argument("--seed", type=whole, help="perturb the canonical instance's poses with this seed")
    rec.add_argument("--split", choices=("train", "dev", "test"), help="built-in demonstrations: the split whose "
                                                                         "random stream --seed draws from (default train)")
    rec.add_argument("--variant", choices=("distractor-push",),
                     help="record a variant of the demo (distractor-push: push an extra block aside first)")
    rec.add_argument("--out", metavar="DIR", help="folder, created if missing (default: domains/mechanisms/demos, "
                                                  "or your demonstration's folder)")
    rec.add_argument("--force", action="store_true", help="replace an existing recording")
    rec.add_argument("--render", metavar="FILE.gif", help="also render the recording")
    rec.add_argument("--strip", metavar="FILE.png", help="also draw its key frames with contacts")
    sh = commands.add_parser("show", help="render a recording")
    sh.add_argument("file", metavar="FILE", help="a recording (NAME.npz, NAME.json or NAME)")
    sh.add_argument("--render", metavar="FILE.gif")
    sh.add_argument("--strip", metavar="FILE.png")
    sh.add_argument("--every", type=whole, default=8, help="GIF: every K-th recorded frame (default 8)")
    commands.add_parser("list", help="list the demonstrations")
    args = parser.parse_args(argv)
    if args.command is None:
        return fail("give a command: record, show or list")
    if args.command == "show" and args.every < 1:
        return fail("--every must be >= 1")
    return {"record": record, "show": show, "list": list_demos}[args.command](args)
