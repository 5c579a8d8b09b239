"""`demo record FILE.demo.json|FILE.py`: a user's demonstration, performed in the scene of its
problem file, recorded in the format `learn extract` reads."""
from __future__ import annotations

import argparse
import os
import sys
import time
from typing import TYPE_CHECKING, Any, Dict, Optional

from ..lang.errors import PddlError
from .common import EXIT_OK, EXIT_UNSOLVED, existing_recording, fail, folder_ok, output_folder, print_error, shown_path

if TYPE_CHECKING:
    from ..envs.demos.demo_file import HandCommand
    from ..envs.demos.run import DemoResult
    from ..envs.demos.user import UserDemo
    from ..lang.nodes import Problem


def record_user(args: argparse.Namespace) -> int:
    """`demo record FILE`: perform the user's demonstration in its problem's scene and record
    it beside the file (or in --out); the command's exit status."""
    from ..envs.demos.demo_file import DemoFileError, default_stem
    from ..envs.demos.user import load_problem, load_user_demo

    refused = _refused_option(args)
    if refused is not None:
        return fail(refused)
    progress = _StepProgress()
    try:
        demo = load_user_demo(args.name, progress)
        problem = load_problem(demo)
    except DemoFileError as exc:
        print(str(exc), file=sys.stderr)
        return 2
    except PddlError as exc:
        print_error(exc)
        return 2
    out = os.path.abspath(args.out or os.path.dirname(os.path.abspath(args.name)))
    problem_folder = output_folder(out, "--out") if args.out is not None else None
    if problem_folder is not None:
        return fail(problem_folder)
    stem = default_stem(args.name) + ("" if args.seed is None else f"-seed-{args.seed}")
    base = os.path.join(out, stem)
    taken = None if args.force else existing_recording(base)
    if taken:
        return fail(taken)
    return _perform_and_record(args, demo, problem, progress, stem, base)


def _refused_option(args: argparse.Namespace) -> Optional[str]:
    """Why the options do not go with a demonstration of the user's own, or None."""

    if args.variant:
        return "--variant is for the built-in demonstrations"
    if args.split not in (None, "train"):
        return "--split is for the built-in demonstrations (a demonstration of your own has its own scene)"
    for extra in (args.render, args.strip):
        if not folder_ok(extra):
            return f"{extra}: its folder does not exist"
    return None


class _StepProgress:
    """Told of each step as the demonstration starts it: a terminal's progress bar over the
    steps, made once the demonstration is loaded (a script's steps are not counted)."""

    def __init__(self) -> None:
        self.bar = None

    def start(self, demo: "UserDemo", name: str) -> None:
        """Show the bar, on a terminal, for a demonstration file's steps."""
        from ..util.progress import progress_bar

        if demo.steps and sys.stderr.isatty():
            self.bar = progress_bar(total=demo.steps, desc=f"demo {name}", unit="step", leave=False)

    def __call__(self, step: "HandCommand") -> None:
        if self.bar is not None:
            self.bar.set_postfix_str(f"step {step.number} ({step.kind})", refresh=False)
            self.bar.update(1 if step.number > 1 else 0)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _perform_and_record(args: argparse.Namespace, demo: "UserDemo", problem: "Problem", progress: _StepProgress,
                        stem: str, base: str) -> int:
    """Perform the demonstration and save its recording to `base`.npz + .json if every step
    was done and the goal holds at the end; the command's exit status."""
    from ..envs.demos.demo_file import default_stem
    from ..envs.demos.user import perform_user_demo
    from ..lang.writer import formula
    from ..world.recording import RecordingExists, load_recording, save_recording

    start = time.perf_counter()
    progress.start(demo, default_stem(args.name))
    try:
        result = perform_user_demo(demo, problem, args.seed)
    except PddlError as exc:   # the scene does not build (objects overlap, out of reach)
        print_error(exc)
        return 2
    finally:
        progress.close()
    goal = formula(result.problem.goal)
    header = _header(args, demo, result, stem, goal)
    if result.error or not result.goal_reached:
        return _report_failure(args, demo, result, header, goal)
    try:
        npz, js = save_recording(base, result.extra["arrays"], header, force=args.force)
    except RecordingExists as exc:
        return fail(str(exc))
    size = os.path.getsize(npz) + os.path.getsize(js)
    print(f"wrote {shown_path(npz)} + .json: {header['frames']} frames ({header['duration_s']:.1f} s simulated), "
          f"{size / 1e6:.2f} MB; goal {goal} holds; {time.perf_counter() - start:.1f} s", file=sys.stderr)
    if args.render or args.strip:
        _draw(load_recording(npz), args.render, args.strip)
    return EXIT_OK


def _header(args: argparse.Namespace, demo: "UserDemo", result: "DemoResult", stem: str, goal: str) -> Dict[str, Any]:
    """The recording's header: the simulation's, with what `learn extract` reads about the
    demonstration, its scene (the problem file's text, or the perturbed problem's with --seed)
    and how to record it again."""
    from ..lang.writer import write_problem

    if args.seed is None:
        with open(demo.problem_path, encoding="utf-8") as handle:
            problem_text = handle.read()
    else:
        problem_text = write_problem(result.problem)
    header = result.extra["header"]
    command = "python -m pdsketch_mech.demo record " + args.name + ("" if args.seed is None else f" --seed {args.seed}")
    header.update({
        "name": stem,
        "task": demo.name,
        "mechanism": demo.name,
        "description": demo.description,
        "split": None,
        "seed": args.seed,
        "instance": stem,
        "problem_file": os.path.basename(demo.problem_path),
        "problem": problem_text,
        "goal": goal,
        "goal_achieved": result.goal_reached,
        "final_contacts": result.facts_text(),
        "demonstration": os.path.basename(demo.path),
        "demonstration_text": demo.text,
        "command": command,
    })
    return header


def _report_failure(args: argparse.Namespace, demo: "UserDemo", result: "DemoResult", header: Dict[str, Any],
                    goal: str) -> int:
    """Say which step failed, or that the goal does not hold at the end; draw what happened up
    to there when asked (nothing is recorded). EXIT_UNSOLVED."""
    from ..world.recording import Recording

    if result.error:
        print(result.error if ": error: " in result.error else f"error: {demo.path}: {result.error}",
              file=sys.stderr)
    else:
        print(f"{demo.path}: error: every step was done, but the goal {goal} does not hold at the end; "
              f"contacts: {result.facts_text()}", file=sys.stderr)
    if args.render or args.strip:   # to see why
        _draw(Recording(header, result.extra["arrays"]), args.render, args.strip)
    return EXIT_UNSOLVED


def _draw(recording, gif, strip) -> None:
    from ..envs.demos.show import render_gif, render_strip

    if gif:
        print(f"wrote {gif} ({render_gif(recording, gif)} frames)", file=sys.stderr)
    if strip:
        print(f"wrote {strip} (frames {', '.join(map(str, render_strip(recording, strip)))})", file=sys.stderr)
