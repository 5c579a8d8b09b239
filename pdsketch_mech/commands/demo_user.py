"""`demo record FILE.demo.json|FILE.py`: a user's demonstration, performed in the scene of its
problem file, recorded in the format `learn extract` reads."""
from __future__ import annotations

import os
import sys
import time

from ..lang.errors import PddlError
from .common import EXIT_OK, EXIT_UNSOLVED, fail, output_folder, print_error, shown_path


def record_user(args) -> int:
    from ..envs.demos.demo_file import DemoFileError, default_stem
    from ..envs.demos.user import load_problem, load_user_demo, perform_user_demo
    from ..lang.writer import formula, write_problem
    from ..util.progress import progress_bar
    from ..world.recording import Recording, RecordingExists, load_recording, save_recording
    from .demo import _folder_ok, existing_recording

    if args.variant:
        return fail("--variant is for the built-in demonstrations")
    if args.split not in (None, "train"):
        return fail("--split is for the built-in demonstrations (a demonstration of your own has its own scene)")
    for extra in (args.render, args.strip):
        if not _folder_ok(extra):
            return fail(f"{extra}: its folder does not exist")
    bar = None

    def on_step(step) -> None:
        if bar is not None:
            bar.set_postfix_str(f"step {step.number} ({step.kind})", refresh=False)
            bar.update(1 if step.number > 1 else 0)

    try:
        demo = load_user_demo(args.name, on_step)
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

    start = time.perf_counter()
    bar = progress_bar(total=demo.steps, desc=f"demo {default_stem(args.name)}", unit="step", leave=False) \
        if demo.steps and sys.stderr.isatty() else None
    try:
        result = perform_user_demo(demo, problem, args.seed)
    except PddlError as exc:   # the scene does not build (objects overlap, out of reach)
        print_error(exc)
        return 2
    finally:
        if bar is not None:
            bar.close()
    goal = formula(result.problem.goal)
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
    if result.error or not result.goal_reached:
        if result.error:
            print(result.error if ": error: " in result.error else f"error: {demo.path}: {result.error}",
                  file=sys.stderr)
        else:
            print(f"{demo.path}: error: every step was done, but the goal {goal} does not hold at the end; "
                  f"contacts: {result.facts_text()}", file=sys.stderr)
        if args.render or args.strip:   # what happened up to there, to see why (nothing is recorded)
            _draw(Recording(header, result.extra["arrays"]), args.render, args.strip)
        return EXIT_UNSOLVED
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


def _draw(recording, gif, strip) -> None:
    from ..envs.demos.show import render_gif, render_strip

    if gif:
        print(f"wrote {gif} ({render_gif(recording, gif)} frames)", file=sys.stderr)
    if strip:
        print(f"wrote {strip} (frames {', '.join(map(str, render_strip(recording, strip)))})", file=sys.stderr)
