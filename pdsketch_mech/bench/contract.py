"""`bench contract`: a mechanism adds, never subtracts.

On problems the basis operators solve, the same problems with any single mechanism fragment
loaded, and with every fragment loaded, must be solved within the limit, in at most
1.5x the basis-only time + 5 s:

    solved  and  time <= CONTRACT_FACTOR * basis_time + CONTRACT_SLACK_S   (contract_report.py)

Every problem of a folder (`problems/contract/` by default) is planned by each config: the
basis operators alone (`--basis-only`), each fragment of the mechanisms folder(s) alone
(`+NAME`), every fragment at once (`all`); each plan in its own process, every solved plan
replayed in a fresh one (trials.py's runner, store and `--resume`). Times are the `plan`
process's own clock, start-up included: what a user waits. Each trial also records the
values it simulated, its executed steps and why its steps failed, which do not depend on
the machine's load: two runs can be compared by them without timing noise.
"""
from __future__ import annotations

import functools
import glob
import json
import os
import re
import shutil
import tempfile
from dataclasses import asdict, dataclass, field
from typing import Any, Callable, Dict, Iterator, List, Optional, Sequence, Tuple

from ..util.files import write_text
from .contract_report import (BASIS, CERTIFIED_FAILURE,
                              count_of, summarize, table, values_table, verdicts)
from .plans import make_run, plan_once, replay_once
from .trials import Trial, TrialStore, checkout_commit

ALL = "all"
EACH = "each"
GROUPS = (BASIS, EACH, ALL)


class ContractError(ValueError):
    """Input the benchmark cannot use (one `error:` line, exit 2)."""


# ----------------------------------------------------------------------------- inputs
_COMMENT = re.compile(r";[^\n]*")
_DEFINES_DOMAIN = re.compile(r"^\s*\(\s*define\s*\(\s*domain\b", re.IGNORECASE)


def defines_domain(path: str) -> bool:
    """Whether a .pddl file is a domain (or fragment) rather than a problem."""
    with open(path, encoding="utf-8", errors="replace") as handle:
        text = _COMMENT.sub("", handle.read(4096))
    return bool(_DEFINES_DOMAIN.match(text))


def fragments_in(folders: Sequence[str]) -> List[Tuple[str, str]]:
    """(name, path) of every domain fragment directly in the folders, by name: the file's name
    less `.pddl` (and `.mech`). Problem files beside them (a demonstration's scene) are
    skipped."""
    found: Dict[str, str] = {}
    for folder in folders:
        if not os.path.isdir(folder):
            raise ContractError(f"--mechanisms-dir {folder}: no such folder")
        paths = [p for p in sorted(glob.glob(os.path.join(folder, "*.pddl"))) if defines_domain(p)]
        if not paths:
            raise ContractError(f"--mechanisms-dir {folder}: no domain fragments (.pddl) there")
        for path in paths:
            name = fragment_name(path)
            if name in found:
                raise ContractError(f"--mechanisms-dir: two fragments named {name}: {found[name]} and {path}")
            found[name] = path
    return sorted(found.items())


def fragment_name(path: str) -> str:
    name = os.path.basename(path)[:-len(".pddl")]
    return name[:-len(".mech")] if name.endswith(".mech") else name


def problems_in(folder: str) -> List[Tuple[str, str]]:
    """(name, path) of every problem file directly in `folder` (not its sub-folders), by name."""
    if not os.path.isdir(folder):
        raise ContractError(f"--problems {folder}: no such folder")
    found = [(os.path.basename(p)[:-len(".pddl")], p) for p in sorted(glob.glob(os.path.join(folder, "*.pddl")))
             if not defines_domain(p)]
    if not found:
        raise ContractError(f"--problems {folder}: no problem files (.pddl) there")
    return found


@dataclass(frozen=True)
class Config:
    """What `plan` is given besides the domain and the problem."""

    name: str                               # basis | +NAME | all
    mechanisms: Tuple[str, ...] = ()        # fragment files
    flags: Tuple[str, ...] = ()

    @property
    def extra(self) -> Tuple[str, ...]:
        return self.flags + (("--mechanisms",) + self.mechanisms if self.mechanisms else ())


def configs(selection: str, fragments: Sequence[Tuple[str, str]]) -> List[Config]:
    """The configs `--configs` names: `basis`, `each` (one per fragment), `all`, or single
    fragments by name (`hook-use`); the basis config always comes first (the contract is
    measured against it)."""
    names = [n.strip() for n in selection.split(",") if n.strip()]
    by_name = dict(fragments)
    unknown = [n for n in names if n not in GROUPS and n.lstrip("+") not in by_name]
    if unknown or not names:
        raise ContractError(f"--configs {selection}: unknown {', '.join(unknown) or 'empty list'}; choose from "
                            f"{','.join(GROUPS)} or a fragment's name ({','.join(by_name)})")
    out = [Config(BASIS, (), ("--basis-only",))]
    for name in names:
        if name == EACH:
            out += [Config("+" + n, (p,)) for n, p in fragments]
        elif name == ALL:
            out.append(Config(ALL, tuple(p for _, p in fragments)))
        elif name != BASIS:
            out.append(Config("+" + name.lstrip("+"), (by_name[name.lstrip("+")],)))
    return list({c.name: c for c in out}.values())   # in order, once each


# ----------------------------------------------------------------------------- trials
@dataclass(frozen=True)
class ContractJob:
    """One problem planned by one config. Carries the problem's text, as trials.Job does."""

    problem: str
    config: str
    problem_text: str
    domain: str
    extra: Tuple[str, ...]
    mechanisms: Tuple[str, ...]   # the fragments the replay loads too
    seed: int = 0
    timeout: float = 120.0

    @property
    def key(self) -> Tuple[str, str, int]:
        return self.problem, self.config, 0


@dataclass
class ContractTrial(Trial):
    """A trial (task: the problem; method: the config) and what it simulated."""

    drawn: Dict[str, int] = field(default_factory=dict)        # stats.samples: values drawn per sampler
    failures: Dict[str, int] = field(default_factory=dict)     # stats.failures: why steps failed (the commonest 8)
    failed_steps: Dict[str, Any] = field(default_factory=dict)  # stats.failed_steps
    certified_failures: int = 0     # failures of a mechanism's :certified facts after its steps
    mechanism_steps: List[str] = field(default_factory=list)    # the mechanisms the plan went through, in order


class ContractStore(TrialStore):
    """trials.TrialStore whose lines are ContractTrials."""

    trial_type = ContractTrial


def run_contract_job(job: ContractJob, keep: Optional[str] = None) -> ContractTrial:
    """Plan `job` in its own process and replay a solved plan in a fresh one; with `keep`,
    the plan's JSON is kept there as PROBLEM--CONFIG.json."""
    with tempfile.TemporaryDirectory(prefix="pdsketch-contract-") as folder:
        problem = os.path.join(folder, job.problem + ".pddl")
        write_text(problem, job.problem_text)
        out = os.path.join(folder, "plan.json")
        outcome = plan_once(job.domain, problem, job.seed, job.timeout, out, extra=job.extra)
        run = make_run(problem, job.domain, job.seed, outcome)
        stats = outcome.document.get("stats", {})
        failures = {k: int(v) for k, v in stats.get("failures", {}).items()}
        plan = outcome.document.get("plan", [])
        trial = ContractTrial(
            job.problem, job.config, 0, job.problem, job.seed, run.status, round(run.time_s, 3), run.skeletons,
            run.refined, run.steps,
            {k: {s: int(n) for s, n in v.items()} for k, v in stats.get("proposals", {}).items()},
            {k: int(v) for k, v in stats.get("simulated", {}).items()}, run.reason,
            (stats.get("score_ms") or {}).get("median"), checkout_commit(), stats.get("planning_s"),
            stats.get("startup_s"), int(stats.get("executions", 0)), int(stats.get("sim_steps", 0)),
            drawn={k: int(v) for k, v in stats.get("samples", {}).items()}, failures=failures,
            failed_steps=stats.get("failed_steps", {}) or {},
            certified_failures=sum(n for k, n in failures.items() if k.endswith(CERTIFIED_FAILURE)),
            mechanism_steps=_collapsed([step.get("mechanism") for step in plan if step.get("mechanism")]))
        if trial.status == "solved":
            ok, message = replay_once(job.domain, problem, out, mechanisms=job.mechanisms)
            if not ok:
                trial.status, trial.reason = "invalid", f"did not replay: {message}"
        if keep and os.path.exists(out):
            shutil.copyfile(out, os.path.join(keep, f"{job.problem}--{job.config.lstrip('+')}.json"))
    return trial


def _collapsed(names: Sequence[str]) -> List[str]:
    out: List[str] = []
    for name in names:
        if not out or out[-1] != name:
            out.append(name)
    return out


def execute(jobs: Sequence[ContractJob], workers: int, keep: Optional[str] = None) -> Iterator[ContractTrial]:
    """Trials of `jobs` as they finish, `workers` planner processes at a time (trials.execute's
    pattern: threads, each waiting on its own process)."""
    from concurrent.futures import ThreadPoolExecutor, as_completed
    run = functools.partial(run_contract_job, keep=keep)
    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        futures = [pool.submit(run, job) for job in jobs]
        try:
            for future in as_completed(futures):
                yield future.result()
        finally:
            for future in futures:
                future.cancel()


def run_all(store: TrialStore, jobs: Sequence[ContractJob], workers: int, on_trial: Callable[[Trial], None],
            keep: Optional[str] = None) -> List[ContractTrial]:
    for trial in execute(store.pending(jobs), workers, keep):
        store.add(trial)
        on_trial(trial)
    return [store.trials[job.key] for job in jobs if job.key in store.trials]   # type: ignore[misc]


def jobs_of(problems: Sequence[Tuple[str, str]], chosen: Sequence[Config], domain: str, seed: int,
            timeout: float) -> List[ContractJob]:
    """Per problem, every config in order (basis first)."""
    jobs = []
    for name, path in problems:
        with open(path, encoding="utf-8") as handle:
            text = handle.read()
        jobs += [ContractJob(name, c.name, text, domain, c.extra, c.mechanisms, seed, timeout) for c in chosen]
    return jobs


# ----------------------------------------------------------------------------- the contract
PROBLEMS_DIR = os.path.join("problems", "contract")
MECHANISMS_DIR = os.path.join("domains", "mechanisms")
DEFAULT_OUT = os.path.join("out", "bench", "contract")


def add_parser(commands) -> None:
    """`bench contract`'s arguments (registered by bench/__main__.py)."""
    from ..commands.common import count, seconds, seed
    run = commands.add_parser(
        "contract", help="a mechanism adds, never subtracts: problems the basis operators solve, planned with each "
                         "mechanism and with all of them loaded (time <= 1.5 x basis + 5 s)")
    run.add_argument("--problems", default=PROBLEMS_DIR, metavar="DIR",
                     help=f"the problem files, DIR/*.pddl (default {PROBLEMS_DIR})")
    run.add_argument("--only", metavar="NAME,...", help="only these problems of DIR (file names without .pddl)")
    run.add_argument("--mechanisms-dir", action="append", metavar="DIR",
                     help=f"the mechanism fragments, DIR/*.pddl (problem files there are skipped); repeat for several "
                          f"folders (default {MECHANISMS_DIR})")
    run.add_argument("--configs", default=",".join(GROUPS), metavar="C,...",
                     help="basis, each (one config per fragment), all (every fragment at once), or fragments by "
                          "name; basis is always run (default basis,each,all)")
    run.add_argument("--timeout", type=seconds, default=120.0, metavar="S", help="seconds per plan (default 120)")
    run.add_argument("--seed", type=seed, default=0, metavar="N", help="the planner's seed for every plan (default 0)")
    run.add_argument("--workers", type=count, default=1, metavar="K",
                     help="plans at a time, each its own process (default 1; times are measured under that load)")
    run.add_argument("--out", default=DEFAULT_OUT, metavar="DIR", help=f"results folder (default {DEFAULT_OUT})")
    run.add_argument("--resume", action="store_true", help="continue the run whose results --out holds")
    run.add_argument("--table-only", action="store_true", help="write the tables from the trials --out holds, "
                                                               "running none")
    run.add_argument("--keep-plans", action="store_true", help="keep every plan's JSON in OUT/plans/")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.set_defaults(func=run_contract_command)


def run_contract_command(args) -> int:
    import sys

    from ..commands.common import EXIT_OK
    from ..learning.paths import BASIS as BASIS_DOMAIN
    from ..util.files import write_json
    from ..util.progress import progress_bar
    from .ipc import BenchError
    from .paper_commands import commits_line
    from .plans import check_domain
    from .tables import render_markdown, render_text
    from .trials import TrialsError, open_store

    folders = args.mechanisms_dir or [MECHANISMS_DIR]
    try:
        problems = problems_in(args.problems)
        fragments = fragments_in(folders)
        chosen = configs(args.configs, fragments)
    except ContractError as error:
        raise BenchError(str(error)) from None
    if args.only:
        wanted = [n.strip() for n in args.only.split(",") if n.strip()]
        names = [n for n, _ in problems]
        missing = [n for n in wanted if n not in names]
        if missing or not wanted:
            raise BenchError(f"--only {args.only}: no problem {', '.join(missing) or '(empty list)'} in "
                             f"{args.problems}")
        problems = [(n, p) for n, p in problems if n in wanted]
    for c in chosen:
        for path in c.mechanisms:
            check_domain(path)
    for _, path in problems:
        check_domain(BASIS_DOMAIN, path)
    config = {"kind": "contract", "seed": args.seed, "timeout_s": args.timeout,
              "problems": os.path.normpath(args.problems), "mechanisms_dirs": [os.path.normpath(f) for f in folders]}
    try:
        store = open_store(args.out, config, args.resume, args.table_only, ContractStore)
    except TrialsError as error:
        raise BenchError(str(error)) from None
    jobs = jobs_of(problems, chosen, BASIS_DOMAIN, args.seed, args.timeout)
    todo = store.pending(jobs)
    if args.table_only:
        print(f"contract: {len(jobs) - len(todo)} of {len(jobs)} trials in {args.out}; none run (--table-only)",
              file=sys.stderr)
        trials = [store.trials[j.key] for j in jobs if j.key in store.trials]
    else:
        keep = os.path.join(args.out, "plans") if args.keep_plans else None
        if keep:
            os.makedirs(keep, exist_ok=True)
        print(f"contract: {count_of(len(problems), 'problem')} x {count_of(len(chosen), 'config')} = {len(jobs)} trials, "
              f"{len(jobs) - len(todo)} done before, {len(todo)} to run ({args.workers} at a time, "
              f"{args.timeout:g} s each at most); results in {args.out}", file=sys.stderr)
        with progress_bar(total=len(todo), unit="trial", desc="contract", disable=args.quiet,
                          dynamic_ncols=True) as bar:
            def landed(trial: Trial) -> None:
                bar.update(1)
                bar.set_postfix_str(f"{trial.task} {trial.method}: {trial.status} {trial.time_s:.1f} s")
            trials = run_all(store, jobs, args.workers, landed, keep)
    names = [n for n, _ in problems]
    config_names = [c.name for c in chosen]
    header, rows, lines = table(trials, names, config_names, args.timeout)
    lines = lines + [commits_line(trials)] if trials else lines
    values_header, values_rows = values_table(trials, names, config_names)
    values_note = ["values simulated over all samplers (steps executed in simulation): they do not depend on "
                   "the machine's load"]
    print(render_text(header, rows, lines), end="")
    print()
    print(render_text(values_header, values_rows, values_note), end="")
    write_text(os.path.join(args.out, "table.md"),
               "# bench contract\n\n" + render_markdown(header, rows, lines) + "\n## Values simulated\n\n"
               + render_markdown(values_header, values_rows, values_note))
    others = [c for c in config_names if c != BASIS]
    write_json(os.path.join(args.out, "summary.json"), {
        "command": " ".join(["python -m pdsketch_mech.bench"] + sys.argv[1:]), "config": config,
        "problems": names, "configs": [{"name": c.name, "mechanisms": list(c.mechanisms), "flags": list(c.flags)}
                                       for c in chosen],
        "summary": summarize(trials, others), "verdicts": [asdict(v) for v in verdicts(trials)],
        "table": {"header": header, "rows": rows}, "values_table": {"header": values_header, "rows": values_rows},
        "lines": lines})
    print(f"wrote {args.out}/trials.jsonl, table.md, summary.json", file=sys.stderr)
    return EXIT_OK
