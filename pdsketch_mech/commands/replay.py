"""`python -m pdsketch_mech.replay PROBLEM PLAN.json [DOMAIN ...] [--render out.gif]`:
re-execute a saved plan (from `plan --json`) in a fresh world and report whether the goal
holds. Exit 0 when it does, 1 when it does not, 2 on bad input — including a plan that does
not fit the problem, found before any world is built.

The files may come in any order (`plan` takes DOMAIN PROBLEM): the plan is the JSON
document, a domain is a file with a `(define (domain` header, the problem is the rest. A
shipped name takes the role its position gives it in the documented order, unless it names
only a domain (`basis`, a mechanism that is no example problem)."""
from __future__ import annotations

import json
import os
import sys
from typing import List, Optional, Sequence, Tuple

from ..lang.errors import PddlError
from ..lang.loader import declared_domain_name, load_domain, load_problem
from ..learning.paths import resolve_domain, resolve_problem, shipped_mechanisms, shipped_problems
from ..lang.source import read_text
from ..planner.plan_document import load_plan, stale_model_note
from .common import (
    ArgumentParser, EXIT_BAD_INPUT, EXIT_OK, EXIT_UNSOLVED, camera_options, camera_view, output_error, print_error,
    print_warning,
)

JSON_START = (b"{", b"[")   # how a JSON document (a plan) begins, after blanks


def looks_like_json(path: str) -> bool:
    """Whether `path` names a JSON document: by its first character, or by its name when it
    cannot be read (its reader then says why)."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(4096).removeprefix(b"\xef\xbb\xbf").lstrip()
    except OSError:
        return path.lower().endswith(".json")
    return head[:1] in JSON_START


def sort_inputs(files: Sequence[str]) -> Tuple[str, str, List[str]]:
    """(problem, plan, domains) among `files`, whatever their order; a PddlError when there
    is no plan or problem, or two of either."""
    plans = [f for f in files if looks_like_json(f)]
    if not plans:
        raise PddlError("no plan given: replay needs the JSON file `plan --json` wrote, with its problem "
                        "(and domain) files, in any order")
    if len(plans) > 1:
        raise PddlError(f"two plans given ({plans[0]}, {plans[1]}): replay takes one plan JSON")
    problems: List[str] = []
    domains: List[str] = []
    for name in (f for f in files if f not in plans):
        if os.path.isfile(name):
            (domains if declared_domain_name(name) is not None else problems).append(name)
        elif _names_only_a_domain(name) or problems:
            domains.append(name)   # the documented order: PROBLEM first, then domains
        else:
            problems.append(name)
    if not problems:
        raise PddlError("no problem given: replay needs the problem the plan was made for "
                        f"(given: {', '.join(files)})")
    if len(problems) > 1:
        raise PddlError(f"two problems given ({problems[0]}, {problems[1]}): replay takes one problem; "
                        "a domain file starts with (define (domain")
    return problems[0], plans[0], domains


def _names_only_a_domain(name: str) -> bool:
    """`basis`, or a shipped mechanism's name that is no shipped example problem's."""
    return name == "basis" or (name in shipped_mechanisms() and name not in shipped_problems())


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = ArgumentParser(prog="python -m pdsketch_mech.replay", description=__doc__.split("\n\n")[0])
    parser.add_argument("files", nargs="+", metavar="FILE",
                        help="in any order: the problem the plan was made for (a file, or a shipped example's name), "
                             "the plan written by `plan --json`, and its domain: a file, `basis`, or a shipped "
                             "mechanism's name (default: found beside the problem)")
    parser.add_argument("--render", metavar="FILE.gif", help="save the replay as a GIF")
    camera_options(parser)
    args = parser.parse_args(argv)
    try:
        args.problem, args.plan, args.domains = sort_inputs(args.files)
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
    from ..api.planner import replay_entries   # the simulator: only for a valid plan

    try:
        result = replay_entries(domain, problem, steps, args.render, camera_view(args))
    except PddlError as error:
        print_error(error)
        return EXIT_BAD_INPUT
    if args.render:
        print(f"wrote {args.render}", file=sys.stderr)
    print(f"replay: {len(steps)} steps; {result.message}", file=sys.stderr)
    note = None if result.goal_reached else stale_model_note(json.loads(read_text(args.plan)))
    if note:
        print(f"note: {args.plan}: {note}", file=sys.stderr)
    return EXIT_OK if result.goal_reached else EXIT_UNSOLVED
