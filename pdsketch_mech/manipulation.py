"""`plan` for manipulation domains: build the scene's world, run the bilevel planner, print
the plan, and optionally save it as JSON and as a GIF of its replay in a fresh world."""
from __future__ import annotations

import argparse
import sys
import time
from typing import Any, Dict, List

from .cli import EXIT_BAD_INPUT, EXIT_OK, EXIT_UNSOLVED, print_error, write_plan_json
from .lang.errors import PddlError
from .lang.loader import LoadedDomain
from .lang.nodes import Problem
from .operators.execution import Recorder
from .planner.bilevel import PlanResult, bilevel_plan
from .planner.replay import replay
from .planner.serialize import to_json
from .world.build import build_world
from .world.motion import seed_motion_planning
from .world.render import save_gif

# Seconds before the limit at which the planner stops taking new work: the step in flight
# (one sample and simulation, up to ~0.5 s) and writing the results end near the limit.
FINISH_MARGIN = 0.25


def plan_manipulation(args: argparse.Namespace, loaded: LoadedDomain, problem: Problem, started: float) -> int:
    """Plan within `args.timeout` seconds counted from `started` (a time.perf_counter() value:
    the start of the process for the command line)."""
    if problem.scene is None:
        print_error(PddlError(f"problem '{problem.name}' has no :scene; domain '{loaded.domain.name}' has "
                              "streams, so the planner needs the physical scene", problem.loc))
        return EXIT_BAD_INPUT
    seed_motion_planning(args.seed)
    try:
        world = build_world(problem)
    except PddlError as error:
        print_error(error)
        return EXIT_BAD_INPUT
    with world:
        remaining = max(0.1, args.timeout - (time.perf_counter() - started) - FINISH_MARGIN)
        result = bilevel_plan(loaded, problem, world, timeout=remaining, seed=args.seed,
                              use_mechanisms=not args.basis_only)
    result.time_s = time.perf_counter() - started  # what the user waited, start-up included
    entries = plan_entries(result)
    for entry in entries:
        note = f"  ; {entry['mechanism']}" if entry["mechanism"] else ""
        print("(" + " ".join([entry["name"]] + entry["args"]) + ")" + note)
    print(summary(result), file=sys.stderr)
    if "warning" in result.stats:
        print(f"warning: {result.stats['warning']}", file=sys.stderr)
    if args.json:
        try:
            write_plan_json(args.json, result.status, result.reason or result.status, result.time_s, args.seed,
                            entries, result.stats)
        except OSError as exc:
            print_error(PddlError(f"--json {args.json}: cannot write: {exc.strerror or exc}"))
            return EXIT_BAD_INPUT
    if args.render and result.status == "solved":
        recorder = Recorder()
        replayed = replay(loaded, problem, entries, seed=args.seed, recorder=recorder)
        save_gif(recorder.frames, args.render)
        print(f"render: {args.render} ({len(recorder.frames)} frames); replay: {replayed.message}", file=sys.stderr)
    return EXIT_OK if result.status == "solved" else EXIT_UNSOLVED


def plan_entries(result: PlanResult) -> List[Dict[str, Any]]:
    return [{"name": step.name, "args": list(step.args), "mechanism": step.mechanism,
             "params": {name: to_json(value) for name, value in values.items()}}
            for step, values in zip(result.steps, result.values)]


def summary(result: PlanResult) -> str:
    s = result.stats
    samples = ", ".join(f"{k} {v}" for k, v in s["samples"].items()) or "none"
    head = (f"solved: {len(result.steps)} steps" if result.status == "solved" else f"unsolved: {result.reason}")
    return (f"{head} in {result.time_s:.2f} s ({s['symbolic_s']:.2f} s symbolic, {s['continuous_s']:.2f} s "
            f"sampling and simulation); {s['skeletons']} skeletons, {s['executions']} executed steps, "
            f"{s['sim_steps']} physics steps; "
            f"samples: {samples}")
