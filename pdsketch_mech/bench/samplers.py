"""`bench samplers NAME`: a mechanism's learned samplers against its generic ones (the
paper's Macro+Sampler vs Macro) on instances of one of its task's splits (dev unless asked).

Each instance is planned twice with the mechanism's fragment, each in its own process and
with the instance's seed as the planner's:
`--no-learned-samplers` (Macro) and with the checkpoint the fragment names (Macro+Sampler).
Every solved plan is replayed in a fresh process. Figures per method: solved, median time,
median proposals verified (samples drawn from the samplers) and median values evaluated in
simulation, and both per sampler. Instances whose objects include a category the task's
train split never shows are reported apart (held-out categories).
"""
from __future__ import annotations

import os
import statistics
import sys
import tempfile
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence, Tuple

from .trials import Job, run_job

METHODS = ("macro", "macro+sampler")   # the paper's Macro and Macro+Sampler (trials.METHOD_FLAGS)


RUN_SEED_STRIDE = 1000   # run j of instance k plans with seed S + k + RUN_SEED_STRIDE * j


@dataclass
class SamplerTrial:
    instance: str
    held_out: bool                        # an object of a category the train split never shows
    method: str
    status: str
    time_s: float
    proposals: Dict[str, int] = field(default_factory=dict)   # per sampler, generic + learned
    simulated: Dict[str, int] = field(default_factory=dict)   # per sampler
    score_ms: Optional[float] = None
    reason: str = ""
    seed: int = 0                         # the planner's --seed

    @property
    def run(self) -> Tuple[str, int]:
        """The instance and planner seed: the same for both methods' trials of one run."""
        return self.instance, self.seed

    @property
    def proposed(self) -> int:
        return sum(self.proposals.values())

    @property
    def evaluated(self) -> int:
        return sum(self.simulated.values())


def run_samplers(task_name: str, fragment: str, instances: int, split: str, seed: int, timeout: float,
                 keep: Optional[str] = None, progress: bool = True, workers: int = 1, runs: int = 1) -> List[SamplerTrial]:
    """Every instance planned by both methods `runs` times (planner seeds S + k, then
    S + k + RUN_SEED_STRIDE * j), `workers` plans at a time (each its own process); trials
    in (instance, run, method) order whatever order they finish in."""
    from concurrent.futures import ThreadPoolExecutor

    from ..envs.generate import sample
    from ..envs.task_names import resolve_task
    with tempfile.TemporaryDirectory() as tmp:
        jobs = []
        for k in range(instances):
            instance = sample(resolve_task(task_name), split, seed + k)
            held = instance.held_out
            # The planner's seed is the instance's, as in `bench mechanisms`: with one seed for
            # all, the generic sampler's first draws were the same on every instance, and on
            # near-identical instances (five spoon/2 blockers on Slope-and-Blocker) one lucky
            # draw counted five times.
            # One plan says little: the same checkpoint solved Hook 8/10 and 6/10 on two runs.
            for j in range(runs):
                name = instance.name + (f"-run{j}" if j else "")   # keep: INSTANCE[-runJ]-METHOD.json
                jobs += [(held, Job(task_name, method, k, name, instance.problem_text(), fragment, (),
                                    seed + k + RUN_SEED_STRIDE * j, timeout), instance.name) for method in METHODS]

        def run(item: Tuple[bool, Job, str]) -> SamplerTrial:
            held, job, instance = item
            done = run_job(job, keep or tmp)
            trial = SamplerTrial(instance, held, job.method, done.status, done.time_s, _summed(done.proposals),
                          done.simulated, done.score_ms, done.reason, job.seed)
            if progress:
                print(f"  {job.instance}{' (held-out category)' if trial.held_out else ''} {trial.method}: "
                      f"{trial.status} in {trial.time_s:.1f} s, {trial.proposed} proposals, "
                      f"{trial.evaluated} simulated", file=sys.stderr, flush=True)
            return trial

        with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:  # threads: each plan is a process
            return list(pool.map(run, jobs))


def _summed(proposals: Dict[str, Dict[str, int]]) -> Dict[str, int]:
    """Proposals per sampler, generic and learned together."""
    out: Dict[str, int] = {}
    for part in proposals.values():
        for sampler, n in part.items():
            out[sampler] = out.get(sampler, 0) + n
    return out


def _median(values: Sequence[float]) -> str:
    return f"{statistics.median(values):.1f}" if values else "-"


def fewest_values(fragment: str, name: str) -> int:
    """The fewest values a plan through mechanism `name`'s steps simulates: one per
    continuous parameter (each is sampled once and its step simulated once)."""
    from ..lang.loader import load_domain
    from ..learning.selfplay import find_mechanism
    loaded = load_domain([fragment])
    return sum(loaded.types.is_value(p.type) for p in find_mechanism(loaded, name).parameters)


def table(trials: Sequence[SamplerTrial], fewest: Optional[int] = None) -> Tuple[List[str], List[List[str]], List[str]]:
    """One row per (instances, method); medians over every instance (unsolved ones count
    what they drew until the limit), times over solved ones. With `fewest` (fewest_values),
    a line says how many times fewer values than the generic median any sampler could take."""
    header = ["instances", "method", "solved", "median s", "median proposals", "median simulated",
              "per sampler: proposals / simulated (medians)"]
    rows, lines = [], []
    both = {t.run for t in trials if t.status == "solved" and all(u.status == "solved" for u in trials if u.run == t.run)}
    groups = [("all", list(trials)), ("seen categories", [t for t in trials if not t.held_out]),
              ("held-out categories", [t for t in trials if t.held_out]),
              ("solved by both", [t for t in trials if t.run in both])]
    for label, group in groups:
        if not group or (label != "all" and len(group) == len(trials)):
            continue
        for method in METHODS:
            mine = [t for t in group if t.method == method]
            solved = [t for t in mine if t.status == "solved"]
            samplers = sorted({n for t in mine for n in list(t.proposals) + list(t.simulated)})
            per = ", ".join(f"{n} {_median([t.proposals.get(n, 0) for t in mine])}/"
                            f"{_median([t.simulated.get(n, 0) for t in mine])}" for n in samplers)
            rows.append([label, method, f"{len(solved)}/{len(mine)}", _median([t.time_s for t in solved]),
                         _median([t.proposed for t in mine]), _median([t.evaluated for t in mine]), per])
    solved_by_both = [t for t in trials if t.run in both]
    for label, group in (("all instances", list(trials)), ("instances solved by both", solved_by_both)):
        generic = [t for t in group if t.method == "macro"]
        learned = [t for t in group if t.method == "macro+sampler"]
        if generic and learned:
            g, lt = statistics.median(t.evaluated for t in generic), statistics.median(t.evaluated for t in learned)
            gp, lp = statistics.median(t.proposed for t in generic), statistics.median(t.proposed for t in learned)
            lines.append(f"{label}, learned against generic samplers (medians): {_fewer(g, lt)} values simulated "
                         f"({lt:g} against {g:g}), {_fewer(gp, lp)} proposals verified ({lp:g} against {gp:g})")
            if fewest and label == "all instances":
                # The headroom: where the generic samplers already take nearly the fewest
                # values, no ranking can take many times fewer (Center-of-Mass: 4 of 4).
                lines.append(f"the fewest values a plan through the mechanism's steps simulates: {fewest} (one per "
                             f"continuous parameter), {g / fewest:.2f}x fewer than the generic median ({g:g}): "
                             "no sampler's plans through those steps can do better")
    scores = [t.score_ms for t in trials if t.method == "macro+sampler" and t.score_ms is not None]
    if scores:
        lines.append(f"scoring a batch of proposals: median {statistics.median(scores):.1f} ms "
                     "(embedding a shape the plan had not scored before is timed apart)")
    for t in trials:
        if t.status != "solved":
            lines.append(f"{t.instance} (seed {t.seed}) {t.method}: {t.status} ({t.reason})")
    return header, rows, lines


def _fewer(generic: float, learned: float) -> str:
    """'3.00x fewer', 'as many' or '1.25x more': learned against generic."""
    if generic == learned:
        return "as many"
    if learned < generic:
        return f"{generic / max(learned, 1e-9):.2f}x fewer"
    return f"{learned / max(generic, 1e-9):.2f}x more"

def plot(trials: Sequence[SamplerTrial], path: str, title: str) -> None:
    """The per-sampler breakdown (the paper's Fig. 8): median proposals and values simulated
    per sampler, generic (Macro) beside learned (Macro+Sampler)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from ..util.files import atomic_file
    names = sorted({n for t in trials for n in list(t.proposals) + list(t.simulated)})
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.6))
    x = np.arange(len(names))
    for ax, what in zip(axes, ("proposals", "simulated")):
        for k, method in enumerate(METHODS):
            mine = [t for t in trials if t.method == method]
            heights = [statistics.median(getattr(t, what).get(n, 0) for t in mine) if mine else 0 for n in names]
            ax.bar(x + (k - 0.5) * 0.4, heights, 0.4, label=method)
        ax.set_xticks(x, names, rotation=30, ha="right", fontsize=8)
        ax.set_title(f"median {'proposals verified' if what == 'proposals' else 'values simulated'} per sampler")
        ax.legend(fontsize=8)
    fig.suptitle(title)
    fig.tight_layout()
    with atomic_file(path, binary=True, suffix=".png") as handle:
        fig.savefig(handle, format="png", dpi=90)
    plt.close(fig)


def report_of(fragment: str, name: str) -> str:
    """The learning report (NAME.samplers.md) of the checkpoint mechanism `name` names in `fragment`."""
    from ..lang.parser import parse_file
    from ..samplers.learned.ranked import checkpoint_path
    from .ipc import BenchError
    mechanisms = [m for m in getattr(parse_file(fragment), "mechanisms", ()) if m.name == name]
    if not mechanisms or not mechanisms[0].sampler:
        raise BenchError(f"--report: {fragment} names no learned sampler for {name} (learn train {name} writes one)")
    report = checkpoint_path(mechanisms[0])[:-len(".safetensors")] + ".md"
    if not os.path.isfile(report):
        raise BenchError(f"--report: {report}: no such file (learn train {name} writes it)")
    return report


REPORT_HEADING = "## Generic vs learned samplers (the paper's Fig. 8)"


def add_to_report(trials: Sequence[SamplerTrial], report: str, name: str, command: str, commit: str = "",
                  fewest: Optional[int] = None, split: str = "dev") -> str:
    """Put the comparison into a mechanism's learning report (NAME.samplers.md): the table,
    and the per-sampler breakdown drawn beside it (NAME.samplers-fig8.png), with the command
    and the commit (`checkout_commit`; "" when unknown) that made them. A section written
    before is replaced, the rest of the report kept. Returns the PNG's path."""
    from ..util.files import write_text
    from .tables import render_markdown
    png = report[:-len(".md")] + "-fig8.png"
    instances, runs = len({t.instance for t in trials}), len({t.run for t in trials})
    plot(trials, png, f"mechanism {name}: samples per sampler, generic vs learned "
                      f"({instances} {split} instances, {runs} runs)")
    header, cells, lines = table(trials, fewest)
    with open(report, encoding="utf-8") as handle:
        text = handle.read()
    kept = text.split(REPORT_HEADING)[0].rstrip("\n")
    made = f"`{command}` at commit {commit}" if commit else f"`{command}`"
    section = (f"{REPORT_HEADING}\n\nMade by {made}: each run (an instance and a planner seed) planned with "
               "the mechanism's generic "
               "samplers (Macro) and with the learned ones (Macro+Sampler); every solved plan replayed in a fresh "
               "process.\n\n" + render_markdown(header, cells, lines)
               + f"\n![per-sampler breakdown]({os.path.basename(png)})\n")
    write_text(report, kept + "\n\n" + section)
    return png
