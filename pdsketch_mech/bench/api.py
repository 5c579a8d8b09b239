"""`bench api`: what the Python API saves. N generated problems of one task (dev split) are
planned twice, one after the other on one core: through one `api.Planner` in this process,
and as N `plan` processes (each pays the interpreter, the imports, parsing and checkpoints).
Every plan must be found and replayed both ways; the figure is the wall time per problem."""
from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Dict, List

from .ipc import BenchError


def _problems(task: str, count: int, seed: int, folder: str) -> List[str]:
    from ..envs.generate import sample
    from ..envs.tasks import get_task

    paths = []
    for index in range(count):
        instance = sample(get_task(task), "dev", seed + index)
        path = os.path.join(folder, f"{instance.name}.pddl")
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(instance.problem_text())
        paths.append(path)
    return paths


def _in_process(fragment: str, problems: List[str], timeout: float, seed: int) -> List[float]:
    from ..api import Planner

    started = time.perf_counter()
    planner = Planner(fragment)   # loading once is part of what the API costs
    times = []
    for index, problem in enumerate(problems):
        document = planner.plan(problem, timeout=timeout, seed=seed + index, validate=True)
        if document["status"] != "solved" or not document["replay"]["goal_reached"]:
            raise BenchError(f"api: {os.path.basename(problem)}: {document['reason']}")
        now = time.perf_counter()
        times.append(now - started)
        started = now
    return times


def _processes(fragment: str, problems: List[str], timeout: float, seed: int) -> List[float]:
    times = []
    for index, problem in enumerate(problems):
        command = [sys.executable, "-m", "pdsketch_mech.plan", fragment, problem, "--timeout", str(timeout),
                   "--seed", str(seed + index), "--validate"]
        started = time.perf_counter()
        done = subprocess.run(command, capture_output=True, text=True)
        times.append(time.perf_counter() - started)
        if done.returncode != 0:
            last = (done.stderr.strip().splitlines() or ["no output"])[-1]
            raise BenchError(f"plan {os.path.basename(problem)}: exit {done.returncode}: {last}")
    return times


def measure_api(task: str, count: int, seed: int, timeout: float) -> Dict[str, object]:
    """Per-problem wall times both ways, and what the API saves per problem (median)."""
    from ..learning.paths import resolve_domain

    fragment = resolve_domain(task)
    with tempfile.TemporaryDirectory(prefix="bench-api-") as folder:
        problems = _problems(task, count, seed, folder)
        api = _in_process(fragment, problems, timeout, seed)
        processes = _processes(fragment, problems, timeout, seed)
    return {"task": task, "problems": count, "seed": seed, "split": "dev",
            "api_s": [round(t, 3) for t in api], "processes_s": [round(t, 3) for t in processes],
            "api_total_s": round(sum(api), 2), "processes_total_s": round(sum(processes), 2),
            "saved_per_problem_s": round(statistics.median(processes) - statistics.median(api), 3)}


def report(figures: Dict[str, object]) -> List[str]:
    api, processes = figures["api_s"], figures["processes_s"]
    return [f"api: {figures['problems']} {figures['task']} problems (dev split, seeds {figures['seed']}..), "
            "each planned and replayed",
            f"  one process, api.Planner: {figures['api_total_s']:.2f} s in all, median "
            f"{statistics.median(api):.2f} s a problem (the first, with loading: {api[0]:.2f} s)",
            f"  {figures['problems']} `plan` processes:     {figures['processes_total_s']:.2f} s in all, median "
            f"{statistics.median(processes):.2f} s a problem",
            f"  saved per problem (medians): {figures['saved_per_problem_s']:.2f} s"]
