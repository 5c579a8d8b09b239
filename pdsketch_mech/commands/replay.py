"""`python -m pdsketch_mech.replay PROBLEM PLAN.json [DOMAIN ...] [--render out.gif]`:
re-execute a saved plan (from `plan --json`) in a fresh world and report whether the goal
holds. Exit 0 when it does, 1 when it does not, 2 on bad input — including a plan that does
not fit the problem, found before any world is built."""
from __future__ import annotations

import sys
from typing import Optional, Sequence

from ..lang.errors import PddlError
from ..lang.loader import load_domain, load_problem
from ..learning.paths import resolve_domain, resolve_problem
from ..planner.plan_document import load_plan
from .common import ArgumentParser, EXIT_BAD_INPUT, EXIT_OK, EXIT_UNSOLVED, output_error, print_error, print_warning


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = ArgumentParser(prog="python -m pdsketch_mech.replay", description=__doc__.split("\n\n")[0])
    parser.add_argument("problem", metavar="PROBLEM", help="the problem the plan was made for (a file, or a shipped example's name)")
    parser.add_argument("plan", metavar="PLAN.json", help="a plan written by `plan --json`")
    parser.add_argument("domains", nargs="*", metavar="DOMAIN", help="its domain: a file, `basis`, or a shipped mechanism's name (default: found beside the problem)")
    parser.add_argument("--render", metavar="FILE.gif", help="save the replay as a GIF")
    args = parser.parse_args(argv)
    try:
        args.problem = resolve_problem(args.problem)
        args.domains = [resolve_domain(d) for d in args.domains]
        # A plan's values are in its JSON: no checkpoint is loaded, a missing one is a warning.
        domains = [load_domain([d], samplers_required=False) for d in args.domains]
        for warning in (w for d in domains for w in d.warnings):
            print_warning(warning)
        domain, problem = load_problem(args.problem, domains, samplers_required=False)
        error = output_error(args.render, "--render", [*domain.files, args.problem, args.plan], (".gif",))
        if error is not None:
            raise error
        steps = load_plan(args.plan, domain, problem)
    except PddlError as error:
        print_error(error)
        return EXIT_BAD_INPUT
    from ..operators.execution import FrameRecorder  # the simulator: only for a valid plan
    from ..planner.replay import replay
    from ..world.render import save_gif

    try:
        recorder = FrameRecorder() if args.render else None
        result = replay(domain, problem, steps, recorder=recorder)
    except PddlError as error:
        print_error(error)
        return EXIT_BAD_INPUT
    if args.render:
        save_gif(recorder.frames, args.render)
    print(f"replay: {len(steps)} steps; {result.message}", file=sys.stderr)
    return EXIT_OK if result.goal_reached else EXIT_UNSOLVED
