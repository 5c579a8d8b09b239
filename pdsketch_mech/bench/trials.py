"""Benchmark trials that survive interruption: one (task, method, instance) planned in its own
process and replayed in a fresh one, K at a time locally or as Ray tasks, each finished trial
appended to OUT/trials.jsonl at once so that a rerun with `--resume` skips it.

A trial carries its problem as text: a Ray worker on another machine writes it to its own
temporary folder (the domain files are read from the same checkout path on every node).
"""
from __future__ import annotations

import functools
import json
import os
import subprocess
import tempfile
from dataclasses import asdict, dataclass, field
from typing import Callable, Dict, Iterable, Iterator, List, Optional, Sequence, Tuple

from ..util.files import write_text
from .plans import make_run, plan_once, replay_once

# method -> how the planner is told: the paper's three rows of Table 1, and Macro+Sampler with
# every mechanism loaded (as a user plans), not only the one the task needs.
ALL_MECHANISMS = "all-mechanisms"
METHOD_FLAGS: Dict[str, Tuple[str, ...]] = {
    "basis": ("--basis-only",),
    "macro": ("--no-learned-samplers",),
    "macro+sampler": (),
    ALL_MECHANISMS: (),
}
METHODS = tuple(METHOD_FLAGS)
PAPER_METHODS = METHODS[:3]   # the paper's rows; Table 2 loads every mechanism in each
METHOD_TITLES = {"basis": "Basis only", "macro": "Macro", "macro+sampler": "Macro+Sampler",
                 ALL_MECHANISMS: "Macro+Sampler, all mechanisms loaded"}
METHOD_COLOURS = {"basis": "#9e9e9e", "macro": "#4c72b0", "macro+sampler": "#dd8452",
                  ALL_MECHANISMS: "#c44e52"}   # both tables' plots


class TrialsError(ValueError):
    """A results folder that cannot be used as asked (one `error:` line, exit 2)."""


@dataclass(frozen=True)
class Job:
    """What one trial plans: `domain` (+ `mechanisms` merged into it) on `problem_text`."""

    task: str
    method: str
    index: int                       # trial number within (task, method); instance seed = seed + index
    instance: str
    problem_text: str
    domain: str
    mechanisms: Tuple[str, ...] = ()
    seed: int = 0                    # the planner's --seed
    timeout: float = 600.0

    @property
    def key(self) -> Tuple[str, str, int]:
        return self.task, self.method, self.index


@dataclass
class Trial:
    """One finished trial, as trials.jsonl stores it."""

    task: str
    method: str
    index: int
    instance: str
    seed: int
    status: str                      # solved | unsolved | crashed | invalid (did not replay)
    time_s: float
    skeletons: int = 0
    refined: int = 0
    steps: int = 0
    proposals: Dict[str, Dict[str, int]] = field(default_factory=dict)   # generic/learned -> sampler -> n
    simulated: Dict[str, int] = field(default_factory=dict)             # sampler -> values simulated
    reason: str = ""
    score_ms: Optional[float] = None  # median time to score a batch with learned samplers
    commit: str = ""                  # the checkout that planned it (a resumed run may span several)
    planning_s: Optional[float] = None  # the planner's own time: time_s less the process's start-up
    startup_s: Optional[float] = None   # the process's start-up: imports, loading, world building
    executions: int = 0                 # steps executed in simulation (values tried, and replays)
    sim_steps: int = 0                  # physics steps those executions took

    @property
    def key(self) -> Tuple[str, str, int]:
        return self.task, self.method, self.index

    @property
    def samples(self) -> int:
        """Values simulated over all samplers (the paper's "samples evaluated")."""
        return sum(self.simulated.values())


@functools.lru_cache(maxsize=None)
def checkout_commit() -> str:
    """The git commit of the checkout this package runs from, "-dirty" if it has local
    changes; "" outside a git checkout (an installed copy)."""
    here = os.path.dirname(os.path.abspath(__file__))
    try:
        done = subprocess.run(["git", "-C", here, "describe", "--always", "--dirty", "--abbrev=7"],
                              capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.TimeoutExpired):
        return ""
    return done.stdout.strip() if done.returncode == 0 else ""


def run_job(job: Job, folder: Optional[str] = None) -> Trial:
    """Plan `job` in its own process and replay a solved plan in a fresh one; the problem
    and the plan JSON are kept in `folder` if given (INSTANCE.pddl, INSTANCE-METHOD.json)."""
    if folder is None:
        with tempfile.TemporaryDirectory(prefix="pdsketch-trial-") as tmp:
            return run_job(job, tmp)
    problem = os.path.join(folder, job.instance + ".pddl")
    write_text(problem, job.problem_text)  # atomic: another method's planner may be reading it
    out = os.path.join(folder, f"{job.instance}-{job.method}.json")
    extra = METHOD_FLAGS[job.method] + (("--mechanisms",) + job.mechanisms if job.mechanisms else ())
    outcome = plan_once(job.domain, problem, job.seed, job.timeout, out, extra=extra)
    run = make_run(problem, job.domain, job.seed, outcome)
    stats = outcome.document.get("stats", {})
    trial = Trial(job.task, job.method, job.index, job.instance, job.seed, run.status, round(run.time_s, 3),
                  run.skeletons, run.refined, run.steps,
                  {k: {s: int(n) for s, n in v.items()} for k, v in stats.get("proposals", {}).items()},
                  {k: int(v) for k, v in stats.get("simulated", {}).items()}, run.reason,
                  (stats.get("score_ms") or {}).get("median"), checkout_commit(), stats.get("planning_s"),
                  stats.get("startup_s"), int(stats.get("executions", 0)), int(stats.get("sim_steps", 0)))
    if trial.status == "solved":
        ok, message = replay_once(job.domain, problem, out, mechanisms=job.mechanisms)
        if not ok:
            trial.status, trial.reason = "invalid", f"did not replay: {message}"
    return trial


def execute(jobs: Sequence[Job], workers: int = 1, backend: str = "local") -> Iterator[Trial]:
    """Trials of `jobs` as they finish: `workers` planner processes at a time, or Ray tasks
    (`ray.init(num_cpus=workers)` locally, or the cluster RAY_ADDRESS names)."""
    if backend == "ray":
        from ..util.ray_tasks import ray_unordered
        yield from ray_unordered(run_job, jobs, workers)
        return
    from concurrent.futures import ThreadPoolExecutor, as_completed
    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:  # threads: each plan is a process
        futures = [pool.submit(run_job, job) for job in jobs]
        try:
            for future in as_completed(futures):
                yield future.result()
        finally:
            for future in futures:  # an interrupt: do not start the queued ones
                future.cancel()


TRIALS_FILE = "trials.jsonl"   # in OUT: one line per finished trial
# Settings a config.json written before they existed holds implicitly (a resume compares them too).
CONFIG_DEFAULTS: Dict[str, object] = {"planner_seed_offset": 0}


class TrialStore:
    """OUT/config.json (what the trials were run with) and OUT/trials.jsonl (one line per
    finished trial, flushed and synced as it lands: an interrupt loses only trials in flight).
    A benchmark whose trials carry more fields sets `trial_type` to its Trial subclass."""

    trial_type = Trial

    def __init__(self, folder: str, config: Dict[str, object], resume: bool):
        self.folder = folder
        self.path = os.path.join(folder, TRIALS_FILE)
        config_path = os.path.join(folder, "config.json")
        if os.path.exists(self.path) or os.path.exists(config_path):
            if not resume:
                raise TrialsError(f"{folder}: holds results of an earlier run; --resume continues it, "
                                  f"or give another --out")
            with open(config_path, encoding="utf-8") as handle:
                before = {**CONFIG_DEFAULTS, **json.load(handle)}
            changed = sorted(k for k in config if k in before and before[k] != config[k])
            if changed:
                raise TrialsError(f"{folder}: was run with other settings ({', '.join(f'{k}={before[k]}' for k in changed)})"
                                  f"; resume with those, or give another --out")
        os.makedirs(folder, exist_ok=True)
        tmp = config_path + ".tmp"
        with open(tmp, "w", encoding="utf-8") as handle:
            json.dump(config, handle, indent=1)
        os.replace(tmp, config_path)
        self.trials: Dict[Tuple[str, str, int], Trial] = {t.key: t for t in self._read()}

    def _read(self) -> List[Trial]:
        if not os.path.exists(self.path):
            return []
        out = []
        with open(self.path, encoding="utf-8") as handle:
            for line in handle:
                try:
                    out.append(self.trial_type(**json.loads(line)))
                except (ValueError, TypeError):
                    continue  # a line cut short by a kill: that trial runs again
        return out

    def add(self, trial: Trial) -> None:
        self.trials[trial.key] = trial
        with open(self.path, "a", encoding="utf-8") as handle:
            handle.write(json.dumps(asdict(trial)) + "\n")
            handle.flush()
            os.fsync(handle.fileno())

    def pending(self, jobs: Iterable[Job]) -> List[Job]:
        return [job for job in jobs if job.key not in self.trials]


def run_all(store: TrialStore, jobs: Sequence[Job], workers: int, backend: str,
            on_trial: Callable[[Trial], None]) -> List[Trial]:
    """Run the jobs the store has no trial for (`on_trial` told of each as it lands); every
    job's trial, in the jobs' order."""
    for trial in execute(store.pending(jobs), workers, backend):
        store.add(trial)
        on_trial(trial)
    return [store.trials[job.key] for job in jobs if job.key in store.trials]


def open_store(folder: str, config: Dict[str, object], resume: bool, table_only: bool,
               store_type: type = TrialStore) -> TrialStore:
    """The results folder of a benchmark run: `resume` continues the run it holds,
    `table_only` reads it without running (it must hold trials)."""
    if table_only and not os.path.exists(os.path.join(folder, TRIALS_FILE)):
        raise TrialsError(f"--table-only: {folder} holds no trials")
    return store_type(folder, config, resume or table_only)
