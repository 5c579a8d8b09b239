"""`python -m pdsketch_mech.envs TASK --seed N [--split train|dev|test] [--out FILE [--force]]`: a
problem file drawn from a task distribution, built in or a distribution file NAME.dist.json
(`--canonical`: the canonical instance; `--list`: the tasks; `--export TASK`: a built-in
task written as a distribution file).

The same task, split and seed always give the same bytes. An existing --out file is replaced
only with --force. Exit 0, or 2 with one `error:` line on stderr for a bad request.
"""
from __future__ import annotations

import os
import sys
from typing import Optional, Sequence

from ..util.files import write_text
from .common import ArgumentParser, EXIT_BAD_INPUT, EXIT_OK, output_error, whole


def main(argv: Optional[Sequence[str]] = None) -> int:
    from ..envs.spec import SPLITS
    from ..envs.task_names import task_names

    parser = ArgumentParser(prog="python -m pdsketch_mech.envs", description=__doc__.split("\n\n")[0])
    parser.add_argument("task", nargs="?", metavar="TASK", help=f"one of: {', '.join(task_names())}; or a distribution "
                                                                "file (NAME.dist.json, docs/distributions.md)")
    parser.add_argument("--seed", type=whole, help="which instance (a whole number >= 0)")
    parser.add_argument("--split", default="train", choices=SPLITS,
                        help="train: self-play; dev: tuning; test: reported tables only (default train)")
    parser.add_argument("--canonical", action="store_true",
                        help="the canonical instance: first train assets at their canonical poses")
    parser.add_argument("--canonical-assets", action="store_true",
                        help="with --seed: keep the canonical assets, perturb only the poses (the demos' check)")
    parser.add_argument("--out", metavar="FILE", help="write here (default: stdout)")
    parser.add_argument("--force", action="store_true", help="replace an existing --out file")
    parser.add_argument("--list", action="store_true", help="list the tasks and exit")
    parser.add_argument("--export", action="store_true",
                        help="write TASK as a distribution file (every object in full) instead of an instance")
    args = parser.parse_args(argv)

    if args.list:
        from ..envs.task_names import resolve_task
        for name in task_names():
            task = resolve_task(name)
            print(f"{task.name:14s} {task.title}: {task.description}")
        return EXIT_OK
    from ..envs.task_file import TaskFileError, dump_document, task_document
    from ..envs.task_names import resolve_task

    error, task = None, None
    if args.task is not None:
        try:
            task = resolve_task(args.task)
        except KeyError as exc:
            error = exc.args[0]
        except TaskFileError as exc:
            print(exc, file=sys.stderr)
            return EXIT_BAD_INPUT
    if args.task is None:
        error = "name a task (--list shows them)"
    elif error:
        pass
    elif args.canonical == (args.seed is not None) and not args.export:
        error = "give exactly one of --seed N and --canonical"
    elif args.out:
        unwritable = output_error(args.out, "--out")
        if unwritable is not None:
            error = unwritable.message
        elif os.path.exists(args.out) and not args.force:  # e.g. a trained fragment: never replaced silently
            error = f"{args.out} exists (use --force to replace it)"
    if error:
        print(f"error: {error}", file=sys.stderr)
        return EXIT_BAD_INPUT
    from ..envs.generate import sample

    if args.export:
        text, what = dump_document(task_document(task)), f"task {task.name}"
    else:
        instance = sample(task, args.split, args.seed, vary_assets=not args.canonical_assets)
        text, what = instance.problem_text(), instance.name
        placed = sum(o.role == "distractor" for o in instance.objects)
        wanted = task.distractors.count[0] if task.distractors is not None and args.seed is not None else 0
        if not args.canonical_assets and placed < wanted:
            print(f"warning: {instance.name}: {placed} distractors placed, fewer than the {wanted} asked for: "
                  "their region has no more room clear of the other objects", file=sys.stderr)
    if args.out:
        write_text(args.out, text)
        print(f"wrote {args.out}: {what}", file=sys.stderr)
    else:
        sys.stdout.write(text)
    return EXIT_OK
