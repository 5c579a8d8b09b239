"""`python -m pdsketch_mech.check FILE ...`: parse and type-check domain and problem files.

Domain files are checked with everything they `:extends`; a problem is checked against the
domain it names, found among the given files or beside the problem. Then everything `plan`
validates before it searches: a domain's streams name samplers that exist, a problem for a
domain with streams has a `:scene`, a mechanism's learned samplers load (its `:sampler`
checkpoint exists, is readable and was trained for this definition of the mechanism; not with
`--no-learned-samplers`, as in `plan`), and a scene builds into a simulated world (assets exist,
no object is inside another or the robot, far away or below the table: `world/build.py`).
Where the scene and `:init` disagree on the contact graph, or a movable object starts above
what is under it (it would fall), check warns as `plan` does.
Exit 0 when every file is clean (warnings allowed), 2 otherwise, with one
`FILE:LINE:COL: error: ...` line per failing file (a problem whose domain is not found is
not reported when a domain file given failed: that error is the one to read). Only a problem
with a scene (or a domain with streams) loads the simulator: checking classical PDDL stays fast.
A problem whose grounding is estimated above `--max-ground` is refused, as `plan` refuses it
(`symbolic/ground_size.py`, docs/limits.md).
"""
from __future__ import annotations

from typing import List, Optional, Sequence

from ..lang.errors import PddlError, PddlWarning, did_you_mean
from ..lang.loader import DomainNotFound, LoadedDomain, declared_domain_name, load_domain, load_problem
from ..lang.nodes import Problem
from ..learning.paths import resolve_shipped
from ..symbolic.ground_size import check_ground_size
from .common import ArgumentParser, EXIT_BAD_INPUT, EXIT_OK, max_ground_option, print_error, print_warning


def _plural(count: int, word: str) -> str:
    return f"{count} {word}{'s' * (count != 1)}"


def describe_domain(loaded: LoadedDomain) -> str:
    d = loaded.domain
    fragments = len(loaded.files) - 1
    extended = f" (+{_plural(fragments, 'fragment')})" if fragments else ""
    return (f"domain '{d.name}'{extended}: {_plural(len(d.types) + len(d.value_types), 'type')}, "
            f"{_plural(len(d.predicates), 'predicate')}, {_plural(len(d.actions), 'action')}, "
            f"{_plural(len(d.streams), 'stream')}, {_plural(len(d.mechanisms), 'mechanism')}")


def check_samplers(loaded: LoadedDomain) -> None:
    """Every stream is implemented by a sampler the planner has, and the vocabulary the
    domain names exists."""
    if not loaded.domain.streams:
        return
    from ..operators.vocabulary import vocabulary_of   # loads the simulator: only with streams
    from ..samplers.registry import GENERIC_SAMPLERS as SAMPLERS

    vocabulary_of(loaded.domain)

    for stream in loaded.domain.streams:
        name = stream.sampler or stream.name
        if name not in SAMPLERS:
            raise PddlError(f"stream '{stream.name}' uses sampler '{name}', which does not exist"
                            f"{did_you_mean(name, SAMPLERS)}; known: {', '.join(sorted(SAMPLERS))}", stream.loc)


def check_learned_samplers(loaded: LoadedDomain) -> None:
    """The mechanisms' learned samplers load as `plan` loads them before it searches (it does
    for a domain with streams); the same error otherwise."""
    if not loaded.domain.streams or not any(m.sampler for m in loaded.domain.mechanisms):
        return
    from ..samplers.learned.checkpoint import CheckpointError
    from ..samplers.learned.ranked import load_learned

    try:
        load_learned(loaded.domain.mechanisms)
    except CheckpointError as error:
        raise error.as_pddl_error() from None


def check_scene(loaded: LoadedDomain, problem: Problem, path: str) -> List[PddlWarning]:
    """What `plan` checks of a problem's scene before searching; returns the warnings."""
    streams = bool(loaded.domain.streams)
    if streams and problem.scene is None:
        raise PddlError(f"problem '{problem.name}' has no :scene; domain '{loaded.domain.name}' has "
                        "streams, so the planner needs the physical scene", problem.loc)
    if problem.scene is None:
        return []
    from ..world.build import build_world  # PyBullet: only a problem with a scene needs it

    warnings: List[PddlWarning] = []  # objects that would fall, as plan warns of them
    with build_world(problem, warnings=warnings) as world:
        if not streams:
            return warnings  # a classical plan never looks at the scene
        from ..planner.bilevel import prepare_task
        from ..planner.execute import settle_moves
        from ..planner.run_stats import initial_mismatch

        task, _ = prepare_task(loaded, problem)
        entries = {e.name: e for e in problem.scene}
        # Settled as the planner does before it compares: a tilted object that tips over says
        # so (one already said to fall is not warned of twice).
        warned = {w.loc for w in warnings}
        warnings += [PddlWarning(f"scene object '{name}': moves {distance * 100:.1f} cm as the scene settles "
                                 "(it does not rest at its scene pose: it falls, tips over or slides)",
                                 entries[name].loc) for name, distance in settle_moves(world)
                     if entries[name].loc not in warned]
        mismatch = initial_mismatch(task, world)
    return warnings + ([PddlWarning(mismatch, file=path)] if mismatch else [])


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = ArgumentParser(
        prog="python -m pdsketch_mech.check",
        description="Parse and type-check .pddl domain and problem files (exit 0 clean, 2 on errors).")
    parser.add_argument("files", nargs="+", metavar="FILE", help="domain and problem files, in any order; a shipped domain, mechanism or "
                                                               "example problem may be named (basis, hook-use)")
    parser.add_argument("-q", "--quiet", action="store_true", help="print errors and warnings only")
    parser.add_argument("--no-learned-samplers", action="store_true",
                        help="as plan's: do not load the mechanisms' learned samplers (a missing one is a warning)")
    parser.add_argument("--reach", action="store_true",
                        help="for a problem with a scene, say per movable object whether the hand can grasp it "
                             "where it stands (docs/first-problem.md: reach)")
    max_ground_option(parser)
    args = parser.parse_args(argv)
    learned = not args.no_learned_samplers
    try:
        args.files = [resolve_shipped(f) for f in args.files]
    except PddlError as error:
        print_error(error)
        return EXIT_BAD_INPUT

    domain_files = [f for f in args.files if declared_domain_name(f) is not None]
    problem_files = [f for f in args.files if f not in domain_files]
    loaded: List[LoadedDomain] = []
    failures = 0
    for path in domain_files:
        try:
            domain = load_domain([path], samplers_required=learned)
            for warning in domain.warnings:
                print_warning(warning)
            check_samplers(domain)
        except PddlError as error:
            print_error(error)
            failures += 1
            continue
        loaded.append(domain)  # its problems are checked against it even if its checkpoints fail
        try:
            if learned:
                check_learned_samplers(domain)
        except PddlError as error:
            print_error(error)
            failures += 1
            continue
        if not args.quiet:
            print(f"{path}: ok: {describe_domain(domain)}")
    domain_failed = failures > 0
    for path in problem_files:
        try:
            domain, problem = load_problem(path, loaded, samplers_required=learned)
            if all(domain is not d for d in loaded):  # found beside the problem: not checked above
                for warning in domain.warnings:
                    print_warning(warning)
                check_samplers(domain)
                if learned:
                    check_learned_samplers(domain)
            check_ground_size(domain.domain, problem, domain.types, args.max_ground)  # as plan refuses it
            for warning in check_scene(domain, problem, path):
                print_warning(warning)
        except DomainNotFound as error:
            if not domain_failed:  # else most likely the domain that failed: its error is the one to read
                print_error(error)
            failures += 1
            continue
        except PddlError as error:
            print_error(error)
            failures += 1
            continue
        if not args.quiet:
            scene = f", {_plural(len(problem.scene), 'scene object')}" if problem.scene is not None else ""
            print(f"{path}: ok: problem '{problem.name}' for domain '{domain.domain.name}': "
                  f"{_plural(len(problem.objects), 'object')}, {_plural(len(problem.init), 'initial fact')}"
                  f"{scene}")
        if args.reach and problem.scene is not None:
            from .check_reach import reach_report
            for line in reach_report(problem):
                print(f"  reach: {line}")
    return EXIT_BAD_INPUT if failures else EXIT_OK
