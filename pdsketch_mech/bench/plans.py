"""`bench plan`: solve manipulation problems over several seeds, each run in its own process
(`python -m pdsketch_mech.plan ... --json`), and summarise time and samples per sampler."""
from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Dict, List, Sequence, Tuple


@dataclass
class Run:
    problem: str
    domain: str
    seed: int
    status: str
    time_s: float
    samples: Dict[str, int] = field(default_factory=dict)
    steps: int = 0


def run_plans(cases: Sequence[Tuple[str, str]], seeds: Sequence[int], timeout: float, progress: bool = True) -> List[Run]:
    """Every (domain, problem) case for every seed; a run that overruns by 30 s is killed."""
    runs: List[Run] = []
    for domain, problem in cases:
        for seed in seeds:
            with tempfile.TemporaryDirectory() as tmp:
                out = os.path.join(tmp, "plan.json")
                command = [sys.executable, "-m", "pdsketch_mech.plan", domain, problem, "--seed", str(seed),
                           "--timeout", str(timeout), "--json", out]
                try:
                    subprocess.run(command, capture_output=True, text=True, timeout=timeout + 30)
                    document = json.load(open(out)) if os.path.exists(out) else {}
                except subprocess.TimeoutExpired:
                    document = {}
            stats = document.get("stats", {})
            run = Run(problem, domain, seed, document.get("status", "crashed"), document.get("time_s", float("nan")),
                      stats.get("samples", {}), len(document.get("plan", [])))
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
        names = sorted({k for r in group for k in r.samples})
        samples = ", ".join(f"{k} {statistics.mean(r.samples.get(k, 0) for r in group):.0f}" for k in names)
        rows.append([os.path.splitext(os.path.basename(problem))[0], os.path.basename(domain),
                     f"{len(solved)}/{len(group)}", f"{statistics.median(times):.2f}" if times else "-",
                     f"{max(times):.2f}" if times else "-", samples or "-"])
    return header, rows
