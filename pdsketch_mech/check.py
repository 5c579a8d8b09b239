"""`python -m pdsketch_mech.check FILE ...`: parse and type-check domain and problem files.

Domain files are checked with everything they `:extends`; a problem is checked against the
domain it names, found among the given files or beside the problem, and its scene's assets
must exist. Exit 0 when every file
is clean, 2 otherwise, with one `FILE:LINE:COL: error: ...` line per failing file.
"""
from __future__ import annotations

import argparse
import sys
from typing import List, Optional, Sequence

from .cli import EXIT_BAD_INPUT, EXIT_OK, print_error, run
from .lang.errors import PddlError
from .lang.loader import LoadedDomain, declared_domain_name, load_domain, load_problem
from .world.build import resolve_scene_assets


def _plural(count: int, word: str) -> str:
    return f"{count} {word}{'s' * (count != 1)}"


def describe_domain(loaded: LoadedDomain) -> str:
    d = loaded.domain
    fragments = len(loaded.files) - 1
    extended = f" (+{_plural(fragments, 'fragment')})" if fragments else ""
    return (f"domain '{d.name}'{extended}: {_plural(len(d.types) + len(d.value_types), 'type')}, "
            f"{_plural(len(d.predicates), 'predicate')}, {_plural(len(d.actions), 'action')}, "
            f"{_plural(len(d.streams), 'stream')}, {_plural(len(d.mechanisms), 'mechanism')}")


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m pdsketch_mech.check",
        description="Parse and type-check .pddl domain and problem files (exit 0 clean, 2 on errors).")
    parser.add_argument("files", nargs="+", metavar="FILE", help="domain and problem files, in any order")
    parser.add_argument("-q", "--quiet", action="store_true", help="print errors only")
    args = parser.parse_args(argv)

    domain_files = [f for f in args.files if declared_domain_name(f) is not None]
    problem_files = [f for f in args.files if f not in domain_files]
    loaded: List[LoadedDomain] = []
    failures = 0
    for path in domain_files:
        try:
            loaded.append(load_domain([path]))
        except PddlError as error:
            print_error(error)
            failures += 1
            continue
        if not args.quiet:
            print(f"{path}: ok: {describe_domain(loaded[-1])}")
    for path in problem_files:
        try:
            domain, problem = load_problem(path, loaded)
            resolve_scene_assets(problem)
        except PddlError as error:
            print_error(error)
            failures += 1
            continue
        if not args.quiet:
            scene = f", {_plural(len(problem.scene), 'scene object')}" if problem.scene is not None else ""
            print(f"{path}: ok: problem '{problem.name}' for domain '{domain.domain.name}': "
                  f"{_plural(len(problem.objects), 'object')}, {_plural(len(problem.init), 'initial fact')}"
                  f"{scene}")
    return EXIT_BAD_INPUT if failures else EXIT_OK


if __name__ == "__main__":
    sys.exit(run(main))
