"""`bench reach DOMAIN PROBLEM --skeleton "OP OP ..."`: does the adaptive planner get to a given
skeleton, and when?

For each seed the planner runs in its own process (plans.plan_once); its `stats.skeleton_log`
lists every skeleton it created, with the creation rank and the time (seconds after the
planner started, i.e. after start-up and building the world); a skeleton is refined from the
moment it is created. A skeleton pattern is either operator names ("grasp move-cont place
grasp": any arguments) or operators with object arguments ("(grasp hook table) (move-cont
hook box table) ..."; stream placeholders such as #grasp2 may be given or left out); it
matches a logged skeleton with the same number of operators that agree one by one.
Solved plans are replayed in a fresh process, as in `bench task`.

The symbolic enumeration alone (no sampling) also says where the pattern first comes in the
order the planner creates skeletons: `enumeration_rank`.
"""
from __future__ import annotations

import os
import sys
import tempfile
import time
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple

from .plans import Run, make_run, plan_once, replay_once, skeleton_ops

Ops = List[Tuple[str, Tuple[str, ...]]]


@dataclass
class Reached:
    pattern: str
    rank: Optional[int] = None        # creation rank of the first matching skeleton (None: never created)
    created_s: Optional[float] = None
    skeleton: str = ""


@dataclass
class ReachRun:
    run: Run
    reached: List[Reached] = field(default_factory=list)
    last_created_s: Optional[float] = None   # when the last skeleton was created


def matches(pattern: Ops, skeleton: Ops) -> bool:
    """Same length; each operator has the pattern's name and, if the pattern gives
    arguments, exactly those object arguments."""
    return len(pattern) == len(skeleton) and all(
        name == got_name and (not args or args == got_args)
        for (name, args), (got_name, got_args) in zip(pattern, skeleton))


def first_match(pattern: str, log: Sequence[Dict[str, Any]]) -> Reached:
    """The first entry of a `skeleton_log` that matches `pattern`."""
    wanted = skeleton_ops(pattern)
    for entry in log:
        if matches(wanted, skeleton_ops(entry.get("skeleton", ""))):
            return Reached(pattern, entry.get("rank"), entry.get("created_s"), entry.get("skeleton", ""))
    return Reached(pattern)


def check_patterns(patterns: Sequence[str], domain: str, problem: str) -> None:
    """Every operator named is an action or mechanism of the domain and every argument an
    object of the problem; a PddlError (or ValueError) otherwise. Also checks both files."""
    from ..lang.loader import load_domain, load_problem

    loaded, parsed = load_problem(problem, [load_domain([domain])])
    operators = {a.name for a in loaded.domain.actions} | {m.name for m in loaded.domain.mechanisms}
    objects = {o.name for o in parsed.objects} | {c.name for c in loaded.domain.constants}
    for pattern in patterns:
        ops = skeleton_ops(pattern)
        if not ops:
            raise ValueError(f"--skeleton {pattern!r}: no operators given")
        for name, args in ops:
            if name not in operators:
                raise ValueError(f"--skeleton {pattern!r}: '{name}' is not an operator of the domain "
                                 f"(operators: {', '.join(sorted(operators))})")
            unknown = [a for a in args if a not in objects]
            if unknown:
                raise ValueError(f"--skeleton {pattern!r}: '{unknown[0]}' is not an object of the problem "
                                 f"(objects: {', '.join(sorted(objects))})")


def enumeration_rank(patterns: Sequence[str], domain: str, problem: str, basis_only: bool, limit: int,
                     seconds: float) -> Tuple[Dict[str, Optional[int]], int]:
    """Where each pattern first comes in the planner's skeleton order, by enumerating up to
    `limit` skeletons (or `seconds`) symbolically, as the planner does (prepare_task +
    planner_order). Returns ({pattern: rank or None}, skeletons enumerated)."""
    from ..lang.loader import load_domain, load_problem
    from ..planner.bilevel import prepare_task
    from ..planner.supply import planner_order

    loaded, parsed = load_problem(problem, [load_domain([domain])])
    task, _ = prepare_task(loaded, parsed, use_mechanisms=not basis_only)
    wanted = {p: skeleton_ops(p) for p in patterns}
    found: Dict[str, Optional[int]] = {p: None for p in patterns}
    count = 0
    for plan in planner_order(task, time.perf_counter() + seconds):
        count += 1
        ops = skeleton_ops(" ".join(task.operators[o].label for o in plan))
        for p, pattern in wanted.items():
            if found[p] is None and matches(pattern, ops):
                found[p] = count
        if count >= limit or all(v is not None for v in found.values()):
            break
    return found, count


def run_reach(domain: str, problem: str, patterns: Sequence[str], seeds: Sequence[int], timeout: float,
              basis_only: bool = False, keep: Optional[str] = None, progress: bool = True) -> List[ReachRun]:
    out: List[ReachRun] = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = keep or tmp
        for seed in seeds:
            stem = os.path.join(folder, f"{os.path.splitext(os.path.basename(problem))[0]}-seed{seed}")
            outcome = plan_once(domain, problem, seed, timeout, stem + ".json", basis_only)
            run = make_run(problem, domain, seed, outcome)
            if run.status == "solved":
                ok, message = replay_once(domain, problem, stem + ".json")
                run.replay = "ok" if ok else message
                if not ok:
                    run.status = "invalid"
            log = outcome.document.get("stats", {}).get("skeleton_log", [])
            item = ReachRun(run, [first_match(p, log) for p in patterns],
                            log[-1].get("created_s") if log else None)
            out.append(item)
            if progress:
                print(progress_line(item), file=sys.stderr, flush=True)
    return out


def _reached(r: Reached) -> str:
    return f"#{r.rank} at {r.created_s:.1f} s" if r.rank is not None else "not created"


def progress_line(item: ReachRun) -> str:
    run = item.run
    return (f"  seed {run.seed}: " + "; ".join(_reached(r) for r in item.reached)
            + f"; {run.skeletons} skeletons; {run.status} in {run.time_s:.1f} s")


def table(items: Sequence[ReachRun], patterns: Sequence[str],
          enumerated: Optional[Tuple[Dict[str, Optional[int]], int]] = None
          ) -> Tuple[List[str], List[List[str]], List[str]]:
    """One row per seed: per pattern the rank and time its first match was created; the
    skeletons created / refined / pruned; whether and when the run solved, with which skeleton."""
    letters = [chr(ord("A") + i) for i in range(len(patterns))]
    header = ["seed"] + [f"{x}: rank" for x in letters] + [f"{x}: created s" for x in letters] + [
        "skeletons c/r/p", "last created s", "status", "time s", "solving rank"]
    rows = []
    for item in items:
        run = item.run
        rows.append([str(run.seed)] + [str(r.rank) if r.rank is not None else "-" for r in item.reached]
                    + [f"{r.created_s:.1f}" if r.created_s is not None else "-" for r in item.reached]
                    + [f"{run.skeletons}/{run.refined}/{run.pruned}",
                       f"{item.last_created_s:.1f}" if item.last_created_s is not None else "-", run.status,
                       f"{run.time_s:.1f}", str(run.rank) if run.rank is not None else "-"])
    lines = []
    for i, (x, pattern) in enumerate(zip(letters, patterns)):
        reached = [item.reached[i] for item in items if item.reached[i].rank is not None]
        where = ""
        if enumerated is not None:
            rank = enumerated[0].get(pattern)
            where = (f"; enumerated as skeleton #{rank}" if rank is not None
                     else f"; not among the first {enumerated[1]} skeletons enumerated")
        times = sorted(r.created_s for r in reached)
        lines.append(f"{x} = {pattern}: created in {len(reached)}/{len(items)} runs"
                     + (f", at {', '.join(f'{t:.1f}' for t in times)} s" if times else "") + where)
        if reached:
            lines.append(f"    first match: {reached[0].skeleton}")
    lines.append("times are seconds after the planner started (process start-up and building the world excluded); "
                 "a skeleton is refined from the moment it is created")
    for item in items:
        if item.run.status == "invalid":
            lines.append(f"seed {item.run.seed}: the plan did not replay: {item.run.replay}")
        elif item.run.status == "crashed":
            lines.append(f"seed {item.run.seed}: crashed: {item.run.reason}")
    return header, rows, lines
