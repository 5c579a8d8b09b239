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
from typing import List, Optional, Sequence

from ..cli import (
    EXIT_BAD_INPUT, EXIT_OK, EXIT_UNSOLVED, ArgumentParser, count, output_error, print_error, run_and_exit,
    seconds, seed, write_json,
)
from ..lang.errors import PddlError
from ..symbolic.solve import SEARCHES
from . import ipc

INSTALL_HINT = "pyperplan is not installed; it is a benchmark-only dependency: pip install -e '.[bench]'"


def render_text(header: List[str], cells: List[List[str]], lines: List[str]) -> str:
    """Fixed-width table (first column left-aligned, the rest right-aligned), then `lines`."""
    widths = [max(len(row[i]) for row in [header] + cells) for i in range(len(header))]

    def fmt(row: List[str]) -> str:
        return "  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(row, widths)))

    rule = "-" * len(fmt(header))
    return "\n".join([fmt(header), rule] + [fmt(row) for row in cells] + [rule] + lines) + "\n"


def render_markdown(header: List[str], cells: List[List[str]], lines: List[str]) -> str:
    """The same table and lines as markdown (a pipe table and a bullet list)."""
    rows = [header, [":---"] + ["---:"] * (len(header) - 1)] + cells
    return "\n".join("| " + " | ".join(row) + " |" for row in rows) + "\n\n" + "".join(f"- {x}\n" for x in lines)


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
    solve = commands.add_parser("plan", help="manipulation problems over several seeds: time and samples")
    solve.add_argument("domain", metavar="DOMAIN", help="domain file (e.g. domains/basis.pddl or a mechanism)")
    solve.add_argument("problems", nargs="+", metavar="PROBLEM", help="problem files")
    solve.add_argument("--seeds", type=count, default=5, metavar="N", help="seeds 0..N-1 (default 5)")
    solve.add_argument("--timeout", type=seconds, default=300.0, metavar="S", help="seconds per run (default 300)")
    solve.add_argument("--json", metavar="FILE", help="write every run as JSON")
    solve.set_defaults(func=run_plan_command)
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


if __name__ == "__main__":
    run_and_exit(main)
