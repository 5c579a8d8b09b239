"""The bilevel half of `python -m pdsketch_mech.plan`: build the scene's world, run the
planner, print the plan, and optionally save it as JSON, validate it and render its replay."""
from __future__ import annotations

import argparse
import sys
import time
from typing import Dict, List

from ..cli import EXIT_BAD_INPUT, EXIT_OK, EXIT_UNSOLVED, print_error, write_plan_json
from ..lang.errors import PddlError
from ..lang.loader import LoadedDomain
from ..lang.nodes import Problem
from ..operators.execution import Recorder
from ..samplers.learned.checkpoint import CheckpointError
from ..world.build import build_world
from ..world.render import save_gif
from .bilevel import PlanResult, bilevel_plan
from .replay import replay
from .serialize import plan_entries

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
    try:
        world = build_world(problem, visual=False)  # the GIF is rendered from a fresh replay
    except PddlError as error:
        print_error(error)
        return EXIT_BAD_INPUT
    notes: List[str] = []
    with world:
        try:
            learned = learned_samplers(loaded, use_learned=not args.no_learned_samplers,
                                       use_mechanisms=not args.basis_only)
        except CheckpointError as error:  # a clear line, no fallback
            print_error(error.as_pddl_error())
            return EXIT_BAD_INPUT
        planning_began = time.perf_counter()
        remaining = max(0.1, args.timeout - (planning_began - started) - FINISH_MARGIN)
        result = bilevel_plan(loaded, problem, world, timeout=remaining, seed=args.seed,
                              use_mechanisms=not args.basis_only, learned=learned)
        planning_ended = time.perf_counter()
    result.time_s = time.perf_counter() - started  # what the user waited, start-up included
    # The planning algorithm's own time, apart from the process's start-up (interpreter,
    # imports, parsing, world building, checkpoints): what a paper's planning time measures.
    result.stats["startup_s"] = round(planning_began - started, 3)
    result.stats["planning_s"] = round(planning_ended - planning_began, 3)
    result.stats["learned_samplers"] = sorted(learned) if learned else "off"
    entries = plan_entries(result.steps, result.values)
    for entry in entries:
        note = f"  ; {entry['mechanism']}" if entry["mechanism"] else ""
        print("(" + " ".join([entry["name"]] + entry["args"]) + ")" + note)
    print(summary(result), file=sys.stderr)
    for warning in notes + list(result.stats.get("warnings", ())):
        print(f"warning: {warning}", file=sys.stderr)
    status = EXIT_OK if result.status == "solved" else EXIT_UNSOLVED
    if (args.validate or args.render) and result.status == "solved":
        recorder = Recorder() if args.render else None
        replayed = replay(loaded, problem, entries, recorder=recorder)
        if args.render:
            save_gif(recorder.frames, args.render)
            print(f"render: {args.render} ({len(recorder.frames)} frames)", file=sys.stderr)
        print(f"validate: replayed in a fresh world: {replayed.message}", file=sys.stderr)
        status = status if replayed.goal_reached else EXIT_UNSOLVED
    if args.json:
        try:
            write_plan_json(args.json, result.status, result.reason or result.status, result.time_s, args.seed,
                            entries, result.stats, problem.name)
        except OSError as exc:
            print(f"{args.json}: error: cannot write: {exc.strerror}", file=sys.stderr)
            return EXIT_BAD_INPUT
    return status


def learned_samplers(loaded: LoadedDomain, use_learned: bool, use_mechanisms: bool) -> Dict[str, object]:
    """The mechanisms' learned samplers (scored in numpy: planning never imports torch);
    none with `--no-learned-samplers` or `--basis-only`."""
    if not use_learned or not use_mechanisms or not any(m.sampler for m in loaded.domain.mechanisms):
        return {}
    from ..samplers.learned.ranked import load_learned
    return load_learned(loaded.domain.mechanisms)


def summary(result: PlanResult) -> str:
    s = result.stats
    samples = ", ".join(f"{k} {v}" for k, v in s["samples"].items()) or "none"
    head = (f"solved: {len(result.steps)} steps" if result.status == "solved" else f"unsolved: {result.reason}")
    return (f"{head} in {result.time_s:.2f} s ({s['startup_s']:.2f} s start-up, {s['symbolic_s']:.2f} s "
            f"symbolic, {s['continuous_s']:.2f} s sampling and simulation); {s['skeletons']} skeletons, "
            f"{s['executions']} executed steps, {s['sim_steps']} physics steps, "
            f"{s['rejected']} refinements rejected by re-execution; samples: {samples}")
