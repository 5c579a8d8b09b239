"""`python -m pdsketch_mech.replay PROBLEM PLAN.json [DOMAIN ...] [--render out.gif]`:
re-execute a saved plan (from `plan --json`) in a fresh world and report whether the goal
holds. Exit 0 when it does, 1 when it does not, 2 on bad input."""
from __future__ import annotations

import argparse
import json
import sys
from typing import Optional, Sequence

from .cli import EXIT_BAD_INPUT, EXIT_OK, EXIT_UNSOLVED, print_error, run
from .lang.errors import PddlError
from .lang.loader import load_domain, load_problem
from .operators.execution import Recorder
from .planner.replay import replay
from .world.render import save_gif


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pdsketch_mech.replay", description=__doc__.split("\n\n")[0])
    parser.add_argument("problem", metavar="PROBLEM", help="the problem the plan was made for")
    parser.add_argument("plan", metavar="PLAN.json", help="a plan written by `plan --json`")
    parser.add_argument("domains", nargs="*", metavar="DOMAIN", help="its domain (default: found beside it)")
    parser.add_argument("--render", metavar="FILE.gif", help="save the replay as a GIF")
    args = parser.parse_args(argv)
    try:
        with open(args.plan, encoding="utf-8") as handle:
            document = json.load(handle)
        steps = document["plan"]
        if not isinstance(steps, list) or any("name" not in s or "args" not in s for s in steps):
            raise ValueError("each plan step needs a name and args")
    except (OSError, ValueError, KeyError, TypeError) as exc:
        print(f"{args.plan}: error: not a plan written by `plan --json`: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        domains = [load_domain([d]) for d in args.domains]
        domain, problem = load_problem(args.problem, domains)
        recorder = Recorder() if args.render else None
        result = replay(domain, problem, steps, recorder=recorder)
    except PddlError as error:
        print_error(error)
        return EXIT_BAD_INPUT
    if args.render:
        save_gif(recorder.frames, args.render)
    print(f"replay: {len(steps)} steps; {result.message}", file=sys.stderr)
    return EXIT_OK if result.goal_reached else EXIT_UNSOLVED


if __name__ == "__main__":
    sys.exit(run(main))
