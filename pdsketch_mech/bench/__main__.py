"""`python -m pdsketch_mech.bench SUBCOMMAND ...`: benchmark entry point.

Exit codes: 0 the benchmark ran, 1 one of our plans failed validation or the fuzzer found
a failure (a correctness bug), 2 bad input (one `error: ...` line on stderr).
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import os
from dataclasses import asdict
from typing import Optional, Sequence

from ..commands.common import (
    ArgumentParser, EXIT_BAD_INPUT, EXIT_OK, EXIT_UNSOLVED, count, output_error, print_error, run_and_exit,
    seconds, seed, whole,
)
from ..lang.errors import PddlError
from ..symbolic.solve import SEARCHES
from ..util.files import write_json, write_text
from . import contract, ipc, paper_commands
from .plans import check_domain
from .tables import render_markdown, render_text

INSTALL_HINT = "pyperplan is not installed; it is a benchmark-only dependency: pip install -e '.[bench]'"


def run_ipc_command(args: argparse.Namespace) -> int:
    """`ipc`: check the input, run, print the table and summary, write the files asked for."""
    if args.peer and importlib.util.find_spec(args.peer) is None:
        raise ipc.BenchError(INSTALL_HINT)
    if args.plot and not args.peer:
        raise ipc.BenchError("--plot compares with a peer planner: add --peer pyperplan")
    trials = ipc.run_ipc(args.dir, args.timeout, args.peer, args.search)
    header, cells = ipc.table(trials, args.peer)
    summary = ipc.summarize(trials, args.peer)
    lines = ipc.summary_lines(summary)
    print(render_text(header, cells, lines), end="")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump({"dir": args.dir, "timeout_s": args.timeout, "search": args.search, "peer": args.peer,
                       "trials": [asdict(t) for t in trials], "summary": summary}, handle, indent=2)
    if args.markdown:
        with open(args.markdown, "w", encoding="utf-8") as handle:
            handle.write(render_markdown(header, cells, lines))
    if args.plot:
        ipc.plot(trials, args.peer, args.plot)
    return EXIT_UNSOLVED if summary["ours_invalid"] else EXIT_OK


def run_world_command(args: argparse.Namespace) -> int:
    """`world`: measure the simulator primitives and print them against their targets."""
    from . import world  # imports PyBullet and OMPL: only when asked for

    figures = world.measure_world(seed=args.seed)
    print("\n".join(world.report(figures)))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump({"seed": args.seed, **figures}, handle, indent=2)
    return EXIT_OK


def run_api_command(args: argparse.Namespace) -> int:
    """`api`: N problems through one api.Planner against N `plan` processes."""
    from . import api

    figures = api.measure_api(args.task, args.problems, args.seed, args.timeout)
    print("\n".join(api.report(figures)))
    if args.json:
        write_json(args.json, figures)
    return EXIT_OK


def run_startup_command(args: argparse.Namespace) -> int:
    """`startup`: time plan and check in fresh processes and print them against the target."""
    from . import startup

    figures = startup.measure_startup(args.runs)
    print("\n".join(startup.report(figures)))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump(figures, handle, indent=2)
    return EXIT_OK


def run_fuzz_command(args: argparse.Namespace) -> int:
    """`fuzz`: check mutants of every shipped .pddl file; exit 1 on any crash, hang or error
    without a line and column."""
    from . import fuzz

    report = fuzz.run_fuzz(args.mutants, args.seed, args.subprocess_every, progress=True)
    for failure in report.failures:
        print(f"{failure.kind}: {failure.file} ({' + '.join(failure.mutations)}): {failure.detail}")
    print(report.summary())
    if args.json:
        write_json(args.json, {"seed": args.seed, "counts": dict(report.counts), "seconds": report.seconds,
                               "subprocess_runs": report.subprocess_runs,
                               "failures": [asdict(f) for f in report.failures]})
    return EXIT_UNSOLVED if report.failures else EXIT_OK


def run_big_inputs_command(args: argparse.Namespace) -> int:
    """`big-inputs`: check (and plan) huge files, print time and peak memory per case."""
    from . import big_inputs

    results = big_inputs.run_big_inputs(args.case)
    if not results:
        raise ipc.BenchError(f"no case matches {', '.join(args.case)}")
    print("\n".join(big_inputs.report(results)))
    if args.json:
        write_json(args.json, {"targets": {"seconds": big_inputs.TARGET_S, "mb": big_inputs.TARGET_MB,
                                           "init_seconds": big_inputs.INIT_TARGET_S},
                               "cases": [asdict(r) for r in results]})
    return EXIT_OK


def run_plan_command(args: argparse.Namespace) -> int:
    """`plan`: solve each PROBLEM (with DOMAIN) over N seeds and print the summary table."""
    from . import plans

    missing = [f for f in [args.domain, *args.problems] if not os.path.isfile(f)]
    if missing:
        raise ipc.BenchError(f"{missing[0]}: no such file")
    runs = plans.run_plans([(args.domain, p) for p in args.problems], range(args.seeds), args.timeout)
    header, cells = plans.table(runs)
    print(render_text(header, cells, []), end="")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump([asdict(r) for r in runs], handle, indent=1)
    return EXIT_OK


def _write_document(path: Optional[str], document) -> None:
    if path:
        write_json(path, document)


def _keep_folder(keep: Optional[str]) -> Optional[str]:
    """--keep DIR: created if missing (its parent must exist); None without --keep."""
    if keep is None:
        return None
    if os.path.exists(keep) and not os.path.isdir(keep):
        raise ipc.BenchError(f"--keep {keep}: is not a folder")
    parent = os.path.dirname(os.path.abspath(keep))
    if not os.path.isdir(parent):
        raise ipc.BenchError(f"--keep {keep}: folder {os.path.dirname(keep) or '.'} does not exist")
    os.makedirs(keep, exist_ok=True)
    return keep


def run_task_command(args: argparse.Namespace) -> int:
    """`task`: a task distribution with one object's asset pinned, N seeds per asset."""
    from . import tasks

    try:
        role, assets = tasks.parse_vary(args.vary)
        tasks.check_vary(args.task, role, assets)
    except tasks.TaskBenchError as error:
        raise ipc.BenchError(str(error)) from None
    if args.gif and not args.keep:
        raise ipc.BenchError("--gif saves replays beside the kept files: add --keep DIR")
    check_domain(args.domain)
    keep = _keep_folder(args.keep)
    runs = tasks.run_task(args.task, role, assets, range(args.seeds), args.timeout, args.domain,
                          args.basis_only, keep, args.gif)
    header, cells, lines = tasks.table(runs)
    print(render_text(header, cells, lines), end="")
    _write_document(args.json, {"task": args.task, "role": role, "assets": list(assets), "domain": args.domain,
                                "basis_only": args.basis_only, "seeds": args.seeds, "timeout_s": args.timeout,
                                "runs": [asdict(r) for r in runs], "lines": lines})
    return EXIT_UNSOLVED if any(r.status == "invalid" for r in runs) else EXIT_OK


def run_reach_command(args: argparse.Namespace) -> int:
    """`reach`: when does the planner create (and start refining) the given skeletons?"""
    from . import reach

    check_domain(args.domain, args.problem)
    try:
        reach.check_patterns(args.skeleton, args.domain, args.problem)
    except ValueError as error:
        raise ipc.BenchError(str(error)) from None
    keep = _keep_folder(args.keep)
    enumerated = (reach.enumeration_rank(args.skeleton, args.domain, args.problem, args.basis_only,
                                         args.enumerate, 60.0) if args.enumerate else None)
    items = reach.run_reach(args.domain, args.problem, args.skeleton, range(args.seeds), args.timeout,
                            args.basis_only, keep)
    header, cells, lines = reach.table(items, args.skeleton, enumerated)
    print(render_text(header, cells, lines), end="")
    _write_document(args.json, {
        "domain": args.domain, "problem": args.problem, "skeletons": args.skeleton, "basis_only": args.basis_only,
        "seeds": args.seeds, "timeout_s": args.timeout,
        "enumeration_rank": enumerated[0] if enumerated else None,
        "enumerated": enumerated[1] if enumerated else None,
        "runs": [{**asdict(item.run), "reached": [asdict(r) for r in item.reached],
                  "last_created_s": item.last_created_s} for item in items], "lines": lines})
    return EXIT_UNSOLVED if any(item.run.status == "invalid" for item in items) else EXIT_OK


def run_samplers_command(args: argparse.Namespace) -> int:
    """`samplers`: a mechanism's learned samplers against its generic ones on test instances."""
    from ..learning.selfplay import default_fragment, task_of
    from . import samplers
    from .trials import checkout_commit

    fragment = args.fragment or default_fragment(args.name)
    if not os.path.isfile(fragment):
        raise ipc.BenchError(f"{fragment}: no such file")
    check_domain(fragment)
    task = args.task or task_of(fragment, args.name)
    if task is None:
        raise ipc.BenchError(f"{args.name}: no task distribution of that name or of its demonstration; give --task")
    from ..envs.task_file import TaskFileError
    from ..envs.task_names import resolve_task
    try:
        resolve_task(task)
    except (KeyError, TaskFileError) as exc:
        raise ipc.BenchError(str(exc).strip("'\"").split(": error: ")[-1]) from None
    report = samplers.report_of(fragment, args.name) if args.report else None
    paper_commands.warn_if_test(args.split)
    keep = _keep_folder(args.keep)
    trials = samplers.run_samplers(task, fragment, args.instances, args.split, args.seed, args.timeout, keep,
                                   workers=args.workers, runs=args.runs)
    fewest = samplers.fewest_values(fragment, args.name)
    header, cells, lines = samplers.table(trials, fewest)
    print(render_text(header, cells, lines), end="")
    if args.markdown:
        write_text(args.markdown, render_markdown(header, cells, lines))
    if args.plot:
        samplers.plot(trials, args.plot, f"mechanism {args.name}: generic vs learned samplers, "
                                         f"{args.instances} {args.split} instances x {args.runs} runs")
    if report:
        # The options that shape the figures: the seeds, and the load the times were taken under.
        options = [f"--instances {args.instances}", f"--runs {args.runs}", f"--timeout {args.timeout:g}"]
        if args.seed:
            options.append(f"--seed {args.seed}")
        if args.workers > 1:
            options.append(f"--workers {args.workers}")
        if args.split != "dev":
            options.append(f"--split {args.split}")
        command = " ".join([f"python -m pdsketch_mech.bench samplers {args.name}"] + options + ["--report"])
        png = samplers.add_to_report(trials, report, args.name, command, checkout_commit(), fewest, args.split)
        print(f"added the comparison to {report} ({png})")
    _write_document(args.json, {"mechanism": args.name, "task": task, "fragment": fragment, "split": args.split,
                                "instances": args.instances, "runs": args.runs, "seed": args.seed,
                                "timeout_s": args.timeout, "fewest_values": fewest,
                                "trials": [asdict(t) for t in trials], "lines": lines})
    return EXIT_UNSOLVED if any(t.status == "invalid" for t in trials) else EXIT_OK


def build_parser() -> argparse.ArgumentParser:
    """The argument parser, one sub-parser per benchmark."""
    parser = ArgumentParser(prog="python -m pdsketch_mech.bench", description="Planner benchmarks.")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    run = commands.add_parser("ipc", help="time the classical planner on IPC problems (DIR/*/domain.pddl)")
    run.add_argument("dir", metavar="DIR", help="folder with one sub-folder per domain: domain.pddl + problems")
    run.add_argument("--timeout", type=seconds, default=60.0, metavar="S",
                     help="seconds per trial (parse + ground + search; default 60)")
    run.add_argument("--peer", choices=ipc.PEERS, help="also run this planner on every problem")
    run.add_argument("--search", choices=SEARCHES, default="gbfs",
                     help="our search (default gbfs); the peer uses its nearest: gbf or wastar, with h_FF")
    run.add_argument("--json", metavar="FILE", help="write every trial and the summary as JSON")
    run.add_argument("--markdown", metavar="FILE", help="write the table and summary as markdown")
    run.add_argument("--plot", metavar="FILE.png", help="log-log scatter of peer time vs our time")
    run.set_defaults(func=run_ipc_command)
    world = commands.add_parser("world", help="collision checks, IK, motion planning, snapshots on a tabletop")
    world.add_argument("--seed", type=seed, default=0, metavar="N", help="random seed (default 0)")
    world.add_argument("--json", metavar="FILE", help="write the figures as JSON")
    world.set_defaults(func=run_world_command)
    api = commands.add_parser("api", help="N problems planned through the Python API in one process vs N plan "
                                          "processes")
    api.add_argument("task", nargs="?", default="com", help="a shipped mechanism's task (default com)")
    api.add_argument("--problems", type=count, default=20, metavar="N", help="problems (default 20)")
    api.add_argument("--seed", type=seed, default=0, metavar="S", help="dev instances S..S+N-1 (default 0)")
    api.add_argument("--timeout", type=seconds, default=120.0, metavar="S", help="per problem (default 120)")
    api.add_argument("--json", metavar="FILE", help="write the figures as JSON")
    api.set_defaults(func=run_api_command)
    startup = commands.add_parser("startup", help="wall time of plan and check, fresh processes (target 0.3 s)")
    startup.add_argument("--runs", type=count, default=7, metavar="N", help="timed runs per command (default 7)")
    startup.add_argument("--json", metavar="FILE", help="write the figures as JSON")
    startup.set_defaults(func=run_startup_command)
    fuzz = commands.add_parser("fuzz", help="hostile input: check mutants of every shipped .pddl file")
    fuzz.add_argument("--mutants", type=count, default=3000, metavar="N", help="how many (default 3000)")
    fuzz.add_argument("--seed", type=seed, default=0, metavar="N", help="random seed (default 0)")
    fuzz.add_argument("--subprocess-every", type=count, default=100, metavar="K",
                      help="also run every K-th mutant as a separate process (default 100)")
    fuzz.add_argument("--json", metavar="FILE", help="write the counts and failures as JSON")
    fuzz.set_defaults(func=run_fuzz_command)
    big = commands.add_parser("big-inputs", help="time and peak memory of check and plan on huge files "
                                                 "(120,000 objects, 1.2 M predicates, 300,000 facts)")
    big.add_argument("--case", action="append", metavar="TEXT", help="only the cases whose name contains TEXT")
    big.add_argument("--json", metavar="FILE", help="write the figures as JSON")
    big.set_defaults(func=run_big_inputs_command)
    solve = commands.add_parser("plan", help="manipulation problems over several seeds: time and samples")
    solve.add_argument("domain", metavar="DOMAIN", help="domain file (e.g. domains/basis.pddl or a mechanism)")
    solve.add_argument("problems", nargs="+", metavar="PROBLEM", help="problem files")
    solve.add_argument("--seeds", type=count, default=5, metavar="N", help="seeds 0..N-1 (default 5)")
    solve.add_argument("--timeout", type=seconds, default=300.0, metavar="S", help="seconds per run (default 300)")
    solve.add_argument("--json", metavar="FILE", help="write every run as JSON")
    solve.set_defaults(func=run_plan_command)
    task = commands.add_parser("task", help="a task distribution, one object's asset pinned: solved, time, skeletons")
    task.add_argument("task", metavar="TASK", help="a task of python -m pdsketch_mech.envs --list (e.g. hook, edge)")
    task.add_argument("--vary", required=True, metavar="ROLE=ASSET[,ASSET...]",
                      help="the object to pin and its assets, one row each (e.g. tool=spoon/0,hammer/0)")
    task.add_argument("--domain", default="domains/basis.pddl", metavar="FILE",
                      help="domain file (default domains/basis.pddl)")
    task.add_argument("--basis-only", action="store_true", help="plan with basis operators only")
    task.add_argument("--seeds", type=count, default=5, metavar="N",
                      help="instances and planner seeds 0..N-1 per asset (default 5)")
    task.add_argument("--timeout", type=seconds, default=300.0, metavar="S", help="seconds per run (default 300)")
    task.add_argument("--keep", metavar="DIR", help="keep the problems and plan JSONs here (default: a temp folder)")
    task.add_argument("--gif", action="store_true", help="with --keep: also save each solved plan's replay as a GIF")
    task.add_argument("--json", metavar="FILE", help="write every run and the summary as JSON")
    task.set_defaults(func=run_task_command)
    reach = commands.add_parser("reach", help="when the planner creates (and refines) a given skeleton")
    reach.add_argument("domain", metavar="DOMAIN", help="domain file")
    reach.add_argument("problem", metavar="PROBLEM", help="problem file")
    reach.add_argument("--skeleton", action="append", required=True, metavar="OPS",
                       help='operator names ("grasp move-cont place grasp") or operators with objects '
                            '("(grasp hook table) (move-cont hook box table) ..."); repeat for several')
    reach.add_argument("--basis-only", action="store_true", help="plan with basis operators only")
    reach.add_argument("--seeds", type=count, default=5, metavar="N", help="planner seeds 0..N-1 (default 5)")
    reach.add_argument("--timeout", type=seconds, default=120.0, metavar="S", help="seconds per run (default 120)")
    reach.add_argument("--enumerate", type=whole,  default=2000, metavar="N",
                       help="also find each skeleton's place in the symbolic enumeration, up to N skeletons "
                            "or 60 s (default 2000; 0: skip)")
    reach.add_argument("--keep", metavar="DIR", help="keep the plan JSONs here (default: a temp folder)")
    reach.add_argument("--json", metavar="FILE", help="write every run and the figures as JSON")
    reach.set_defaults(func=run_reach_command)
    learned = commands.add_parser("samplers", help="a mechanism's learned samplers vs its generic ones (Macro+Sampler "
                                                   "vs Macro) on dev (or test) instances")
    learned.add_argument("name", metavar="NAME", help="the mechanism (domains/mechanisms/NAME.pddl)")
    learned.add_argument("--instances", type=count, default=10, metavar="N", help="instances (default 10)")
    learned.add_argument("--split", choices=("train", "dev", "test"), default="dev",
                         help="dev: for tuning (default); test: for a reported figure only (docs/evaluation.md)")
    learned.add_argument("--seed", type=seed, default=0, metavar="S", help="instance seeds S..S+N-1 (default 0)")
    learned.add_argument("--runs", type=count, default=1, metavar="K",
                         help="plans per instance and method, with planner seeds S+k, S+k+1000, ... (default 1)")
    learned.add_argument("--timeout", type=seconds, default=120.0, metavar="S", help="seconds per run (default 120)")
    learned.add_argument("--workers", type=count, default=1, metavar="K",
                         help="plans run at a time, each in its own process (default 1; times are measured under "
                              "that load)")
    learned.add_argument("--fragment", metavar="FILE", help="the fragment (default domains/mechanisms/NAME.pddl)")
    learned.add_argument("--task", help="the task distribution (default: NAME's, or its demonstration's)")
    learned.add_argument("--keep", metavar="DIR", help="keep the problems and plan JSONs here (default: a temp folder)")
    learned.add_argument("--json", metavar="FILE", help="write every trial and the figures as JSON")
    learned.add_argument("--markdown", metavar="FILE", help="write the table as markdown")
    learned.add_argument("--plot", metavar="FILE.png", help="per-sampler breakdown, generic vs learned (Fig. 8)")
    learned.add_argument("--report", action="store_true",
                         help="also put the table and Fig. 8 into the mechanism's learning report (the .md beside "
                              "its checkpoint; a comparison written before is replaced)")
    learned.set_defaults(func=run_samplers_command)
    paper_commands.add_parsers(commands)
    contract.add_parser(commands)
    return parser


# Output options of the sub-commands and the file names they take.
OUTPUTS = {"json": (".json",), "markdown": (".md",), "plot": (".png",)}


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = build_parser().parse_args(argv)
    for option, suffixes in OUTPUTS.items():
        error = output_error(getattr(args, option, None), f"--{option}", suffixes=suffixes)
        if error is not None:
            print_error(error)
            return EXIT_BAD_INPUT
    try:
        return args.func(args)
    except ipc.BenchError as error:
        print_error(PddlError(str(error)))
        return EXIT_BAD_INPUT
    except PddlError as error:  # a domain or problem file that does not load
        print_error(error)
        return EXIT_BAD_INPUT


if __name__ == "__main__":
    run_and_exit(main)
