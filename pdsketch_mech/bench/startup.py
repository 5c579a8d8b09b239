"""`bench startup`: how long the command-line tools take to start, each run a fresh process.

A classical problem must not pay for the simulator: `plan` on a 5-block blocksworld problem
and `check` on a classical domain and problem each have a target of `TARGET_S` (the median
of the runs' wall time, imports and interpreter start included). A manipulation `plan` has
the same target for its start-up before planning begins (`stats.startup_s`: interpreter,
imports, parsing, the world, checkpoints), on the Center-of-Mass example with its learned
samplers. `check` on a problem with a scene builds the simulated world, as `plan` does
before searching: it is reported without a target.
"""
from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Dict, List, Optional, Tuple

from .ipc import BenchError

TARGET_S = 0.3
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BLOCKS = ("tests/data/ipc/blocks/domain.pddl", "tests/data/ipc/blocks/p01.pddl")  # p01: 5 blocks

COM = ("domains/mechanisms/com.pddl", "problems/com.pddl")

# (name, arguments after `python`, target in seconds or None, what is timed: the process's
# wall time, or the start-up a manipulation plan reports)
CASES: List[Tuple[str, Tuple[str, ...], Optional[float], str]] = [
    ("plan blocksworld, 5 blocks", ("-m", "pdsketch_mech.plan", *BLOCKS), TARGET_S, "wall"),
    ("check classical domain + problem", ("-m", "pdsketch_mech.check", *BLOCKS), TARGET_S, "wall"),
    ("plan com, start-up before planning", ("-m", "pdsketch_mech.plan", *COM), TARGET_S, "startup_s"),
    ("check scene problem (hook-use)", ("-m", "pdsketch_mech.check", "domains/basis.pddl",
                                        "problems/hook-use.pddl"), None, "wall"),
]


def time_command(args: Tuple[str, ...]) -> float:
    """Seconds from starting `python ARGS` in the repository to its exit; it must succeed."""
    start = time.perf_counter()
    done = subprocess.run([sys.executable, *args], cwd=ROOT, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["no output"])[-1]
        raise BenchError(f"python {' '.join(args)} exited with {done.returncode}: {last}")
    return elapsed


def plan_startup(args: Tuple[str, ...]) -> float:
    """The `stats.startup_s` a manipulation `plan ARGS --json` reports."""
    with tempfile.TemporaryDirectory(prefix="pdsketch-startup-") as folder:
        out = os.path.join(folder, "plan.json")
        time_command(args + ("--json", out))
        with open(out, encoding="utf-8") as handle:
            return float(json.load(handle)["stats"]["startup_s"])


def measure_startup(runs: int = 7) -> Dict[str, object]:
    """Median, min and max of `runs` timed runs per case, after one untimed run that warms
    the file cache and the parser's grammar cache."""
    if runs < 1:
        raise BenchError(f"--runs must be at least 1, got {runs}")
    cases = []
    for name, args, target, timed in CASES:
        measure = plan_startup if timed == "startup_s" else time_command
        measure(args)
        times = [measure(args) for _ in range(runs)]
        median = statistics.median(times)
        cases.append({"name": name, "command": "python " + " ".join(args), "median_s": round(median, 4),
                      "min_s": round(min(times), 4), "max_s": round(max(times), 4), "target_s": target,
                      "ok": None if target is None else median <= target})
    return {"runs": runs, "cases": cases}


def report(figures: Dict[str, object]) -> List[str]:
    """One line per case: the median against its target."""
    lines = [f"startup: median of {figures['runs']} fresh processes (target {TARGET_S:.2f} s: classical runs' "
             "wall time, a manipulation plan's start-up before planning)"]
    width = max(len(case["name"]) for case in figures["cases"])
    for case in figures["cases"]:
        verdict = "no target" if case["ok"] is None else ("ok" if case["ok"] else "OVER TARGET")
        lines.append(f"  {case['name']:<{width}}  {case['median_s']:.3f} s  "
                     f"(min {case['min_s']:.3f}, max {case['max_s']:.3f})  {verdict}")
    return lines
