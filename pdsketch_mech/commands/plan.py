"""`python -m pdsketch_mech.plan DOMAIN PROBLEM`: find a plan.

Prints the plan on stdout, one `(action arg ...)` a line, and a one-line summary on stderr.
Exit 0 solved, 1 no plan within the limits, 2 bad input (one `FILE:LINE:COL: error:` line).
Classical PDDL is planned directly; a domain with streams (and a problem with a :scene) goes
to the bilevel planner, which samples and simulates continuous parameters.
`--skeletons N` prints the first N symbolic skeletons with placeholder values.
"""
from __future__ import annotations

import argparse
import sys
import time
from typing import List, Optional, Sequence

from ..lang.errors import PddlError
from ..lang.loader import LoadedDomain, load_domain, load_problem
from ..lang.nodes import Problem
from ..learning.paths import resolve_domain, resolve_mechanisms, resolve_problem
from ..symbolic.ground_size import check_ground_size
from ..symbolic.solve import ClassicalResult, SEARCHES, solve
from ..symbolic.validate import validate_plan
from ..util import process
from .common import (
    EXIT_BAD_INPUT, EXIT_OK, EXIT_UNSOLVED, ArgumentParser, camera_options, count, number_in, output_error,
    print_error, max_ground_option, print_warning, seconds, seed, write_plan_json,
)


def _parser() -> argparse.ArgumentParser:
    parser = ArgumentParser(prog="python -m pdsketch_mech.plan", description=__doc__.split("\n\n")[0])
    parser.add_argument("domain", metavar="DOMAIN",
                        help="domain file (fragments load what they :extends), or `basis` for the shipped one")
    parser.add_argument("problem", metavar="PROBLEM", help="problem file, or a shipped example's name (hook-use)")
    parser.add_argument("--mechanisms", nargs="+", default=[], metavar="NAME",
                        help="domain fragments merged into DOMAIN: paths, shipped mechanisms' names "
                             "(edge, hook-use, ...), or `all` for every shipped one (with yours: `all my-trick.pddl`)")
    parser.add_argument("--timeout", type=seconds, default=600.0, metavar="S",
                        help="seconds from the start of the command (default 600)")
    parser.add_argument("--seed", type=seed, default=0, metavar="N", help="random seed (default 0)")
    parser.add_argument("--search", choices=SEARCHES, default="gbfs",
                        help="gbfs: lazy greedy best-first with preferred operators (default); "
                             "wastar: weighted A*")
    parser.add_argument("--weight", type=number_in(1.0), default=2.0, metavar="W",
                        help="weight for wastar, >= 1 (default 2)")
    parser.add_argument("--json", metavar="FILE", help="write the result as JSON")
    parser.add_argument("--validate", action="store_true", help="re-check the plan against the domain")
    parser.add_argument("--skeletons", type=count, metavar="N",
                        help="print the first N symbolic skeletons (placeholders for stream outputs)")
    parser.add_argument("--render", metavar="FILE.gif", help="replay the plan in a fresh world and save a GIF")
    camera_options(parser)   # for --render
    parser.add_argument("--basis-only", action="store_true", help="ignore mechanisms: basis operators only")
    parser.add_argument("--no-learned-samplers", action="store_true",
                        help="use the generic samplers inside mechanisms too (the paper's 'Macro' ablation)")
    max_ground_option(parser)
    return parser


def main(argv: Optional[Sequence[str]] = None) -> int:
    started = process.started()  # the time limit covers start-up, loading and world building too
    args = _parser().parse_args(argv)
    # A checkpoint that will not be loaded need not exist (a warning says it is missing).
    samplers_required = not (args.no_learned_samplers or args.basis_only)
    try:
        args.problem = resolve_problem(args.problem)
        loaded = load_domain([resolve_domain(args.domain), *resolve_mechanisms(args.mechanisms)], samplers_required)
        for warning in loaded.warnings:
            print_warning(warning)
        loaded, problem = load_problem(args.problem, [loaded], samplers_required)
        check_ground_size(loaded.domain, problem, loaded.types, args.max_ground)  # before it fills the memory
        inputs = [*loaded.files, args.problem]
        for error in (output_error(args.json, "--json", inputs, (".json",)),
                      output_error(args.render, "--render", inputs, (".gif",))):
            if error is not None:
                raise error
    except PddlError as error:
        print_error(error)
        return EXIT_BAD_INPUT
    try:  # grounding may still find a formula it cannot expand (too many alternatives)
        if args.skeletons is not None:
            return _print_skeletons(loaded, problem, args.skeletons, started + args.timeout)
        if loaded.domain.streams:
            from .plan_scene import plan_manipulation  # imports PyBullet: only for scenes
            return plan_manipulation(args, loaded, problem, started)
        remaining = args.timeout - (time.perf_counter() - started)
        result = solve(loaded.domain, problem, loaded.types, args.search, args.weight, max(remaining, 1e-3))
    except PddlError as error:
        print_error(error)
        return EXIT_BAD_INPUT
    result.time_s = time.perf_counter() - started
    for name, plan_args in result.plan:
        print(f"({' '.join((name,) + plan_args)})")
    print(_summary(result), file=sys.stderr)
    status = EXIT_OK if result.status == "solved" else EXIT_UNSOLVED
    if args.validate and result.status == "solved":
        check = validate_plan(loaded.domain, problem, result.plan)
        print(f"validate: {check.message}", file=sys.stderr)
        status = status if check.ok else EXIT_UNSOLVED
    if args.json:
        try:
            write_plan_json(args.json, "solved" if result.status == "solved" else "unsolved", result.status,
                            result.time_s, args.seed,
                            [{"name": name, "args": list(a), "params": {}} for name, a in result.plan],
                            {"skeletons": 1, "samples": {}, **result.stats}, problem.name)
        except OSError as exc:
            print_error(PddlError(f"--json {args.json}: cannot write: {exc.strerror or exc}"))
            return EXIT_BAD_INPUT
    return status


def _summary(result: ClassicalResult) -> str:
    s = result.stats
    what = (f"solved: {len(result.plan)} steps" if result.status == "solved"
            else "unsolved: " + ("no plan exists" if result.status == "unsolvable" else "timed out"))
    return (f"{what} in {result.time_s:.3f} s (ground {s['ground_s']:.3f} s, search {s['search_s']:.3f} s); "
            f"{s['operators']} operators, {s['facts']} facts, {s['expansions']} expansions, "
            f"{s['evaluations']} evaluations")


def _print_skeletons(loaded: LoadedDomain, problem: Problem, wanted: int, deadline: float) -> int:
    from ..planner.bilevel import prepare_task
    from ..planner.supply import planner_order  # as the bilevel planner searches

    task, _ = prepare_task(loaded, problem)
    found: List[str] = []
    for plan in planner_order(task, deadline):
        found.append(" ".join(task.operators[o].label for o in plan))
        print(f"{len(found)}: {found[-1]}")
        if len(found) >= wanted:
            break
    print(f"{len(found)} skeleton{'s' * (len(found) != 1)}", file=sys.stderr)
    return EXIT_OK if found else EXIT_UNSOLVED
