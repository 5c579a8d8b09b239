"""`bench mechanisms` (Table 1) and `bench compose` (Table 2): their arguments and runs.

Both write into --out DIR: config.json and trials.jsonl as trials finish (`--resume` picks
up an interrupted run), then results.json (every trial and the table), table.md and, for
Table 1, table.png.
"""
from __future__ import annotations

import argparse
import glob
import importlib.util
import os
import sys
from collections import Counter
from dataclasses import asdict
from typing import List, Sequence

from ..commands.common import EXIT_OK, EXIT_UNSOLVED, count, seconds, seed
from ..envs.spec import SPLITS
from ..envs.task_names import task_names
from ..util.files import write_json, write_text
from ..util.progress import progress_bar
from . import compose, mechanisms
from .ipc import BenchError
from .plans import check_domain
from .tables import render_markdown, render_text
from .trials import ALL_MECHANISMS, Job, METHODS, PAPER_METHODS, Trial, TrialsError, open_store, run_all

MECHANISMS_DIR = os.path.join("domains", "mechanisms")
BASIS = os.path.join("domains", "basis.pddl")


def _names(text: str, allowed: Sequence[str], what: str) -> List[str]:
    names = [n.strip() for n in text.split(",") if n.strip()]
    unknown = [n for n in names if n not in allowed]
    if unknown or not names:
        raise BenchError(f"--{what} {text}: unknown {', '.join(unknown) or 'empty list'}; choose from {','.join(allowed)}")
    return list(dict.fromkeys(names))


def _add_common(parser: argparse.ArgumentParser, tasks: Sequence[str], default_out: str,
                methods: Sequence[str]) -> None:
    parser.add_argument("--tasks", default=",".join(tasks), metavar="T,...", help=f"(default {','.join(tasks)})")
    parser.add_argument("--methods", default=",".join(methods), metavar="M,...", help=f"(default {','.join(methods)})")
    parser.add_argument("--split", choices=SPLITS[1:], default="dev",
                        help="dev: for tuning (default); test: for a reported table only (docs/evaluation.md)")
    parser.add_argument("--trials", type=count, default=10, metavar="N",
                        help="instances per task, seeds S..S+N-1, the same for every method (default 10)")
    parser.add_argument("--seed", type=seed, default=0, metavar="S", help="first instance and planner seed (default 0)")
    parser.add_argument("--planner-seed-offset", type=seed, default=0, metavar="K",
                        help="plan instance S+i with planner seed S+i+K (default 0): the same instances with "
                             "other seeds, to see how far a cell moves with the planner's luck")
    parser.add_argument("--timeout", type=seconds, default=600.0, metavar="S", help="seconds per plan (default 600)")
    parser.add_argument("--workers", type=count, default=1, metavar="K",
                        help="plans at a time, each its own process (default 1; times are measured under that load)")
    parser.add_argument("--backend", choices=("local", "ray"), default="local",
                        help="local: K processes; ray: K Ray tasks at a time (a local instance, or RAY_ADDRESS's "
                             "cluster, whose nodes hold this checkout at the same path)")
    parser.add_argument("--mechanisms-dir", default=MECHANISMS_DIR, metavar="DIR",
                        help=f"the mechanism fragments (default {MECHANISMS_DIR})")
    parser.add_argument("--out", default=default_out, metavar="DIR", help=f"results folder (default {default_out})")
    parser.add_argument("--resume", action="store_true", help="continue the run whose results --out holds")
    parser.add_argument("--table-only", action="store_true",
                        help="write the table from the trials --out holds, running none (a run in progress or "
                             "unfinished: a cell without trials is '-', a partial one says n/k)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def add_parsers(commands) -> None:
    table1 = commands.add_parser("mechanisms", help="the paper's Table 1: each mechanism's task by basis operators, "
                                                    "Macro and Macro+Sampler")
    _add_common(table1, [c.task for c in mechanisms.TABLE1], os.path.join("out", "bench", "mechanisms"), METHODS)
    table1.set_defaults(func=run_mechanisms_command)
    table2 = commands.add_parser("compose", help="the paper's Table 2: the compositional tasks, every mechanism loaded")
    _add_common(table2, [c.task for c in compose.TABLE2], os.path.join("out", "bench", "compose"), PAPER_METHODS)
    table2.set_defaults(func=run_compose_command)


def _check(args: argparse.Namespace, fragments: Sequence[str]) -> None:
    if args.backend == "ray" and importlib.util.find_spec("ray") is None:
        raise BenchError("--backend ray: ray is not installed (pip install -e '.[ray]')")
    for path in fragments:
        check_domain(path)


def _run(args: argparse.Namespace, jobs: List[Job], kind: str) -> List[Trial]:
    config = {"kind": kind, "split": args.split, "seed": args.seed, "planner_seed_offset": args.planner_seed_offset,
              "timeout_s": args.timeout, "mechanisms_dir": args.mechanisms_dir}
    try:
        store = open_store(args.out, config, args.resume, args.table_only)
    except TrialsError as error:
        raise BenchError(str(error)) from None
    todo = store.pending(jobs)
    if args.table_only:
        print(f"{kind}: {len(jobs) - len(todo)} of {len(jobs)} trials in {args.out}; none run (--table-only)",
              file=sys.stderr)
        return [store.trials[job.key] for job in jobs if job.key in store.trials]
    print(f"{kind}: {len(jobs)} trials, {len(jobs) - len(todo)} done before, {len(todo)} to run "
          f"({args.workers} at a time, {args.timeout:g} s each at most); results in {args.out}", file=sys.stderr)
    with progress_bar(total=len(todo), unit="trial", desc=kind, disable=args.quiet,
                      dynamic_ncols=True) as bar:
        def landed(trial: Trial) -> None:
            bar.update(1)
            bar.set_postfix_str(f"{trial.task} {trial.method} #{trial.index}: {trial.status} {trial.time_s:.1f} s")
        return run_all(store, jobs, args.workers, args.backend, landed)


def _write(args: argparse.Namespace, trials: Sequence[Trial], header, rows, lines, extra: dict) -> None:
    lines = lines + [physics_line(trials), commits_line(trials)]
    print(render_text(header, rows, lines), end="")
    write_text(os.path.join(args.out, "table.md"), render_markdown(header, rows, lines))
    write_json(os.path.join(args.out, "results.json"),
               {**extra, "trials": [asdict(t) for t in trials], "table": {"header": header, "rows": rows},
                "lines": lines, "command": " ".join(["python -m pdsketch_mech.bench"] + sys.argv[1:])})


def warn_if_test(split: str) -> None:
    """The one-line reminder a run on the test split prints."""
    if split == "test":
        print("note: the test split is for reported tables only: one run, at one commit, never to tune on "
              "(docs/evaluation.md)", file=sys.stderr)


def physics_line(trials: Sequence[Trial]) -> str:
    """Physics steps per executed step and the median start-up: where a plan's time goes
    besides search (each executed step is simulated until its outcome is at rest)."""
    executions, steps = sum(t.executions for t in trials), sum(t.sim_steps for t in trials)
    startups = sorted(t.startup_s for t in trials if t.startup_s is not None)
    per_step = f"{steps / executions:.0f} physics steps per executed step ({executions} executed)" \
        if executions else "no executed steps recorded"
    startup = f"; median start-up {startups[len(startups) // 2]:.2f} s" if startups else ""
    return f"simulation: {per_step}{startup}"


def commits_line(trials: Sequence[Trial]) -> str:
    """Which checkouts planned the trials (a run resumed across commits says so)."""
    counts = Counter(t.commit or "unknown" for t in trials)
    if len(counts) == 1:
        return f"run at commit {next(iter(counts))}"
    return "run at commit " + ", ".join(f"{c} ({n} trial{'s' if n > 1 else ''})" for c, n in sorted(counts.items()))


def run_mechanisms_command(args: argparse.Namespace) -> int:
    warn_if_test(args.split)
    tasks = _names(args.tasks, task_names(), "tasks")
    methods = _names(args.methods, METHODS, "methods")
    columns = [mechanisms.column_of(t) for t in tasks]
    fragments = {c.task: mechanisms.fragment_of(c, args.mechanisms_dir) for c in columns}
    _check(args, list(fragments.values()))
    own = [m for m in methods if m != ALL_MECHANISMS]
    every: tuple = ()
    if ALL_MECHANISMS in methods:
        every = tuple(sorted(glob.glob(os.path.join(args.mechanisms_dir, "*.pddl"))))
        if not every:
            raise BenchError(f"--mechanisms-dir {args.mechanisms_dir}: no .pddl fragments there")
        _check(args, every)
    common = dict(planner_seed_offset=args.planner_seed_offset, split=args.split)
    jobs = []
    for c in columns:   # the same instances and planner seeds for every method
        jobs += mechanisms.instance_jobs(c.task, own, args.trials, args.seed, args.timeout, fragments[c.task], **common)
        if every:
            jobs += mechanisms.instance_jobs(c.task, [ALL_MECHANISMS], args.trials, args.seed, args.timeout, BASIS,
                                             every, **common)
    trials = _run(args, jobs, "mechanisms")
    header, rows, lines = mechanisms.table(trials, columns, methods, args.timeout)
    png = os.path.join(args.out, "table.png")
    mechanisms.plot(trials, columns, methods, args.timeout, png,
                    f"Table 1: {args.trials} {args.split} instances per task, {args.timeout:g} s limit; hatched: the paper's")
    _write(args, trials, header, rows, lines, {"tasks": tasks, "methods": methods, "trials_per_task": args.trials})
    print(f"wrote {args.out}/table.md, table.png, results.json", file=sys.stderr)
    return EXIT_UNSOLVED if any(t.status == "invalid" for t in trials) else EXIT_OK


def run_compose_command(args: argparse.Namespace) -> int:
    warn_if_test(args.split)
    tasks = _names(args.tasks, task_names(), "tasks")
    methods = _names(args.methods, PAPER_METHODS, "methods")
    fragments = tuple(sorted(glob.glob(os.path.join(args.mechanisms_dir, "*.pddl"))))
    if not fragments:
        raise BenchError(f"--mechanisms-dir {args.mechanisms_dir}: no .pddl fragments there")
    _check(args, (BASIS,) + fragments)
    jobs = [job for t in tasks for job in mechanisms.instance_jobs(t, methods, args.trials, args.seed, args.timeout,
                                                                   BASIS, fragments, args.planner_seed_offset,
                                                                   split=args.split)]
    trials = _run(args, jobs, "compose")
    columns = [compose.column_of(t) for t in tasks]
    header, rows, lines = compose.table(trials, columns, methods)
    compose.plot(trials, columns, methods, args.timeout, os.path.join(args.out, "table.png"),
                 f"Table 2: {args.trials} {args.split} instances per task, {args.timeout:g} s limit, all mechanisms loaded")
    _write(args, trials, header, rows, lines, {"tasks": tasks, "methods": methods, "trials_per_task": args.trials,
                                                "mechanisms": list(fragments)})
    print(f"wrote {args.out}/table.md, table.png, results.json", file=sys.stderr)
    return EXIT_UNSOLVED if any(t.status == "invalid" for t in trials) else EXIT_OK
