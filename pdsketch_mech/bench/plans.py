"""`bench plan`: solve manipulation problems over several seeds, each run in its own process
(`python -m pdsketch_mech.plan ... --json`), and summarise time and samples per sampler.

The subprocess runner here (`plan_once`, `replay_once`) is shared with `bench task` and
`bench reach` (tasks.py, reach.py), which also replay every solved plan in a fresh process
(`python -m pdsketch_mech.replay`): a plan that does not replay is not counted as solved.
"""
from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence, Tuple
from ..symbolic.optimistic import is_placeholder

# Seconds a planner process may overrun its own --timeout (start-up, writing the JSON)
# before it is killed; a replay gets REPLAY_TIMEOUT.
OVERRUN = 30.0
REPLAY_TIMEOUT = 300.0


@dataclass
class Run:
    problem: str
    domain: str
    seed: int
    status: str                      # "solved" | "unsolved" | "crashed" (no JSON) | "invalid" (did not replay)
    time_s: float
    samples: Dict[str, int] = field(default_factory=dict)
    steps: int = 0
    skeletons: int = 0               # created
    refined: int = 0
    pruned: int = 0
    rejected: int = 0
    rank: Optional[int] = None       # creation rank of the skeleton that solved it
    reason: str = ""                 # the planner's reason, or why the run crashed / did not replay
    replay: str = ""                 # "" (not replayed), "ok", or what went wrong
    exit_code: Optional[int] = None
    failures: Dict[str, int] = field(default_factory=dict)
    label: str = ""                  # what varies between rows (bench task: the asset)


@dataclass
class RunOutcome:
    """One planner process: its JSON document ({} if none was written), exit code and stderr."""

    document: Dict[str, Any]
    exit_code: Optional[int]         # None: killed after overrunning
    stderr: str


def plan_command(domain: str, problem: str, seed: int, timeout: float, out: str,
                 basis_only: bool = False, extra: Sequence[str] = ()) -> List[str]:
    command = [sys.executable, "-m", "pdsketch_mech.plan", domain, problem, "--seed", str(seed),
               "--timeout", str(timeout), "--json", out]
    return command + (["--basis-only"] if basis_only else []) + list(extra)


def plan_once(domain: str, problem: str, seed: int, timeout: float, out: str, basis_only: bool = False,
              extra: Sequence[str] = ()) -> RunOutcome:
    """Run the planner in its own process, writing its JSON to `out`; killed `OVERRUN` s late."""
    if os.path.exists(out):
        os.unlink(out)  # a stale document from an earlier run must not be read as this one's
    try:
        done = subprocess.run(plan_command(domain, problem, seed, timeout, out, basis_only, extra),
                              capture_output=True, text=True, timeout=timeout + OVERRUN)
        code, stderr = done.returncode, done.stderr
    except subprocess.TimeoutExpired as expired:
        code, stderr = None, _text(expired.stderr) + f"\nkilled after {timeout + OVERRUN:.0f} s"
    try:
        with open(out, encoding="utf-8") as handle:
            document = json.load(handle)
    except (OSError, ValueError):
        document = {}
    return RunOutcome(document, code, stderr)


def replay_once(domain: str, problem: str, plan_json: str, render: Optional[str] = None,
                timeout: float = REPLAY_TIMEOUT, mechanisms: Sequence[str] = ()) -> Tuple[bool, str]:
    """Re-execute a saved plan in a fresh process and world (`python -m pdsketch_mech.replay`),
    with the fragments it was planned with: (goal reached, its summary line or the reason it failed)."""
    command = [sys.executable, "-m", "pdsketch_mech.replay", problem, plan_json, domain, *mechanisms]
    command += ["--render", render] if render else []
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return False, f"replay killed after {timeout:.0f} s"
    return done.returncode == 0, last_line(done.stderr) or f"replay exit {done.returncode}"


def make_run(problem: str, domain: str, seed: int, outcome: RunOutcome) -> Run:
    """A Run from a planner process's outcome (status "crashed" when it wrote no JSON)."""
    document, stats = outcome.document, outcome.document.get("stats", {})
    status = document.get("status", "crashed")
    reason = document.get("reason", "") if document else (last_line(outcome.stderr) or "no JSON written")
    return Run(problem, domain, seed, status, document.get("time_s", float("nan")), dict(stats.get("samples", {})),
               len(document.get("plan", [])), int(stats.get("skeletons", 0)), int(stats.get("refined", 0)),
               int(stats.get("pruned", 0)), int(stats.get("rejected", 0)),
               solving_rank(document) if status == "solved" else None, reason, "", outcome.exit_code,
               dict(stats.get("failures", {})))


def run_plans(cases: Sequence[Tuple[str, str]], seeds: Sequence[int], timeout: float, progress: bool = True) -> List[Run]:
    """Every (domain, problem) case for every seed; a run that overruns by 30 s is killed."""
    runs: List[Run] = []
    for domain, problem in cases:
        for seed in seeds:
            with tempfile.TemporaryDirectory() as tmp:
                outcome = plan_once(domain, problem, seed, timeout, os.path.join(tmp, "plan.json"))
            run = make_run(problem, domain, seed, outcome)
            runs.append(run)
            if progress:
                print(f"  {os.path.basename(problem)} seed {seed}: {run.status} in {run.time_s:.2f} s",
                      file=sys.stderr)
    return runs


def table(runs: Sequence[Run]) -> Tuple[List[str], List[List[str]]]:
    """One row per problem: solved/total, median and max time (of solved runs), mean samples."""
    by_problem: Dict[Tuple[str, str], List[Run]] = defaultdict(list)
    for run in runs:
        by_problem[(run.domain, run.problem)].append(run)
    header = ["problem", "domain", "solved", "median s", "max s", "mean samples per sampler"]
    rows = []
    for (domain, problem), group in by_problem.items():
        solved = [r for r in group if r.status == "solved"]
        times = [r.time_s for r in solved]
        rows.append([os.path.splitext(os.path.basename(problem))[0], os.path.basename(domain),
                     f"{len(solved)}/{len(group)}", f"{statistics.median(times):.2f}" if times else "-",
                     f"{max(times):.2f}" if times else "-", mean_samples(group)])
    return header, rows


def mean_samples(group: Sequence[Run]) -> str:
    """"grasp 12, placement 3, ...": samples per sampler, mean over the runs (all of them)."""
    names = sorted({k for r in group for k in r.samples})
    return ", ".join(f"{k} {statistics.mean(r.samples.get(k, 0) for r in group):.0f}" for k in names) or "-"


# ----------------------------------------------------------------------------- skeletons
def skeleton_ops(text: str) -> List[Tuple[str, Tuple[str, ...]]]:
    """"(grasp hook table #grasp2 #traj3) (place ...)" -> [("grasp", ("hook", "table")), ...]:
    each operator's name and its object arguments (stream placeholders `#...` dropped).
    Plain names ("grasp move-cont place grasp") give empty argument tuples."""
    if "(" not in text:
        return [(name, ()) for name in text.split()]
    ops = []
    for group in text.replace(")", "").split("(")[1:]:
        words = group.split()
        if words:
            ops.append((words[0], tuple(w for w in words[1:] if not is_placeholder(w))))
    return ops


def solving_rank(document: Dict[str, Any]) -> Optional[int]:
    """The creation rank (in `stats.skeleton_log`) of the skeleton a solved plan refines.

    Uses `stats.solved_rank` if the planner reports it. Otherwise the plan's steps are
    matched to the logged skeletons: a basis step by name and arguments (placeholders
    included, as both print them), a mechanism's steps (`"mechanism"` set) as one macro
    operator of that name. None when nothing matches."""
    stats = document.get("stats", {})
    if isinstance(stats.get("solved_rank"), int):
        return stats["solved_rank"]
    plan = document.get("plan", [])
    mechanisms = {e.get("mechanism") for e in plan if e.get("mechanism")}
    wanted = _collapse([(e["mechanism"],) if e.get("mechanism") else (e["name"], *e.get("args", ())) for e in plan])
    for entry in stats.get("skeleton_log", []):
        ops = entry.get("skeleton", "").replace(")", "").split("(")[1:]
        tokens = [tuple(op.split()) for op in ops if op.strip()]
        tokens = _collapse([(t[0],) if t[0] in mechanisms else t for t in tokens])
        if tokens == wanted:
            return entry.get("rank")
    return None


def _collapse(tokens: List[tuple]) -> List[tuple]:
    """Runs of one mechanism's steps become one token (the plan lists each basis step)."""
    out: List[tuple] = []
    for token in tokens:
        if not (len(token) == 1 and out and out[-1] == token):
            out.append(token)
    return out


def last_line(text: str) -> str:
    lines = [line for line in (text or "").splitlines() if line.strip()]
    return lines[-1].strip() if lines else ""


def _text(data) -> str:
    if data is None:
        return ""
    return data.decode("utf-8", "replace") if isinstance(data, bytes) else data


def check_domain(domain: str, problem: Optional[str] = None) -> None:
    """The files exist and parse (a located error, exit 2, before any planning)."""
    from ..lang.loader import load_domain, load_problem
    from .ipc import BenchError

    for path in [domain] + ([problem] if problem else []):
        if not os.path.isfile(path):
            raise BenchError(f"{path}: no such file")
    loaded = load_domain([domain])
    if problem:
        load_problem(problem, [loaded])
