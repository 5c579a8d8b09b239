"""The bilevel half of `python -m pdsketch_mech.plan`: build the scene's world, run the
planner, print the plan, and optionally save it as JSON, validate it and render its replay."""
from __future__ import annotations

import argparse
import sys
import time

from ..api.planner import learned_samplers, mechanism_anchors, plan_scene, replay_entries
from ..lang.errors import PddlError
from ..lang.loader import LoadedDomain
from ..lang.nodes import Problem
from ..planner.bilevel import PlanResult
from ..samplers.learned.checkpoint import CheckpointError
from .common import EXIT_BAD_INPUT, EXIT_OK, EXIT_UNSOLVED, camera_view, print_error, print_warning, write_plan_json

# Seconds before the limit at which the planner stops taking new work: the step in flight
# (one sample and simulation, up to ~0.5 s) and writing the results end near the limit.
FINISH_MARGIN = 0.25


def plan_manipulation(args: argparse.Namespace, loaded: LoadedDomain, problem: Problem, started: float) -> int:
    """Plan within `args.timeout` seconds counted from `started` (a time.perf_counter() value:
    the start of the process for the command line)."""
    try:
        learned = learned_samplers(loaded, use_learned=not args.no_learned_samplers,
                                   use_mechanisms=not args.basis_only)
        anchors = mechanism_anchors(loaded, use_learned=not args.no_learned_samplers, use_mechanisms=not args.basis_only)
        result, entries = plan_scene(loaded, problem, started, started + args.timeout - FINISH_MARGIN, args.seed,
                                     args.basis_only, learned, on_warning=print_warning, anchors=anchors)
    except CheckpointError as error:  # a clear line, no fallback
        print_error(error.as_pddl_error())
        return EXIT_BAD_INPUT
    except PddlError as error:
        print_error(error)
        return EXIT_BAD_INPUT
    result.time_s = time.perf_counter() - started  # what the user waited, start-up included
    for entry in entries:
        note = f"  ; {entry['mechanism']}" if entry["mechanism"] else ""
        print("(" + " ".join([entry["name"]] + entry["args"]) + ")" + note)
    print(summary(result), file=sys.stderr)
    for warning in result.stats.get("warnings", ()):
        print(f"warning: {warning}", file=sys.stderr)
    status = EXIT_OK if result.status == "solved" else EXIT_UNSOLVED
    if (args.validate or args.render) and result.status == "solved":
        replayed = replay_entries(loaded, problem, entries, args.render, camera_view(args))
        if args.render:
            print(f"render: {args.render}", file=sys.stderr)
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


def summary(result: PlanResult) -> str:
    """The summary line; an unsolved run's hint (the steps that failed most, and whether a
    mechanism may help) follows on a second line."""
    s = result.stats
    samples = ", ".join(f"{k} {v}" for k, v in s["samples"].items()) or "none"
    head = (f"solved: {len(result.steps)} steps" if result.status == "solved" else f"unsolved: {result.reason}")
    line = (f"{head} in {result.time_s:.2f} s ({s['startup_s']:.2f} s start-up, {s['symbolic_s']:.2f} s "
            f"symbolic, {s['continuous_s']:.2f} s sampling and simulation); {s['skeletons']} skeletons, "
            f"{s['executions']} executed steps, {s['sim_steps']} physics steps, "
            f"{s['rejected']} refinements rejected by re-execution; samples: {samples}")
    return line + (f"\nhint: {s['hint']}" if result.status != "solved" and s.get("hint") else "")
