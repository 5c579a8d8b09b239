"""`bench mechanisms`: the paper's Table 1 -- each mechanism's task solved by basis operators
only, by the mechanism with generic samplers (Macro) and with its learned samplers
(Macro+Sampler), on the same instances of one split (dev unless asked), every solved plan
replayed.

Times are what the user waits (the planner process's own clock, start-up included). A mean
over trials that did not all finish counts each unfinished one at the limit and is shown as
">mean": a lower bound, as the paper's ">600". Trials that recorded it also get a row of the
planner's own time (`planning_s`): what the paper's times measure, a planning algorithm's
run, without the ~0.65 s a process takes to start, import and build its world.
"""
from __future__ import annotations

import math
import os
import statistics
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

from .trials import ALL_MECHANISMS, Job, METHOD_COLOURS, METHOD_TITLES, Trial


@dataclass(frozen=True)
class PaperTask:
    """A column of Table 1: our task distribution, the mechanism that solves it, and the
    paper's mean times (s; None: ">600", no plan within the limit)."""

    task: str
    title: str
    mechanism: str
    paper: Dict[str, Optional[float]]


TABLE1: Tuple[PaperTask, ...] = (
    PaperTask("edge", "Edge", "edge", {"basis": 89.45, "macro": 8.34, "macro+sampler": 0.57}),
    PaperTask("hook", "Hook", "hook-use", {"basis": None, "macro": 30.82, "macro+sampler": 3.84}),
    PaperTask("lever", "Lever", "lever", {"basis": 523.18, "macro": 1.38, "macro+sampler": 1.55}),
    PaperTask("poking", "Poking", "poking", {"basis": None, "macro": 494.30, "macro+sampler": 97.76}),
    PaperTask("com", "CoM", "com", {"basis": 19.30, "macro": 17.58, "macro+sampler": 0.97}),
    PaperTask("slope-blocker", "Slope&Blocker", "slope-blocker", {"basis": None, "macro": 148.57, "macro+sampler": 4.11}),
)
PAPER_LIMIT = 600.0
BY_TASK = {t.task: t for t in TABLE1}


def column_of(task: str) -> PaperTask:
    """The paper's column of `task`, or a column without the paper's figures for a task beyond
    the paper (its mechanism has the task's name)."""
    if task in BY_TASK:
        return BY_TASK[task]
    from ..envs.task_names import resolve_task
    spec = resolve_task(task)
    return PaperTask(task, spec.title, spec.name, {})


def with_paper(columns: Sequence[PaperTask], method: str) -> bool:
    """Whether the paper has a figure of `method` for every column."""
    return all(method in c.paper for c in columns)


def fragment_of(column: PaperTask, folder: str) -> str:
    return os.path.join(folder, f"{column.mechanism}.pddl")


def instance_jobs(task: str, methods: Sequence[str], trials: int, seed: int, timeout: float, domain: str,
                  mechanisms: Tuple[str, ...] = (), planner_seed_offset: int = 0, split: str = "dev") -> List[Job]:
    """Trial i of every method plans the `split` instance of seed `seed + i` with planner
    seed `seed + i + planner_seed_offset`: the methods see the same instances."""
    from ..envs.generate import sample
    from ..envs.task_names import resolve_task
    jobs = []
    for i in range(trials):
        instance = sample(resolve_task(task), split, seed + i)
        text = instance.problem_text()
        jobs += [Job(task, method, i, instance.name, text, domain, mechanisms, seed + i + planner_seed_offset, timeout)
                 for method in methods]
    return jobs


@dataclass
class Cell:
    """The figures of one (task, method): over all its trials."""

    trials: int
    solved: int
    mean_s: float          # unfinished trials counted at the limit
    stderr_s: float
    median_s: float        # likewise
    lower_bound: bool      # some trial did not finish: the mean is at least this
    median_samples: float  # values simulated
    planning: Optional[Tuple[float, float]] = None  # mean, median of the planner's own time (solved trials recorded it)


def cell(trials: Sequence[Trial], timeout: float) -> Optional[Cell]:
    if not trials:
        return None
    times = [t.time_s if t.status == "solved" else timeout for t in trials]
    solved = sum(t.status == "solved" for t in trials)
    stderr = statistics.stdev(times) / math.sqrt(len(times)) if len(times) > 1 else 0.0
    planning = None
    recorded = [t.planning_s is not None for t in trials if t.status == "solved"]
    if recorded and all(recorded):
        own = [t.planning_s if t.status == "solved" else timeout for t in trials]
        planning = statistics.mean(own), statistics.median(own)
    return Cell(len(trials), solved, statistics.mean(times), stderr, statistics.median(times), solved < len(trials),
                statistics.median(t.samples for t in trials), planning)


def format_cell(c: Optional[Cell], timeout: float) -> str:
    """"0.57 ± 0.05 (med 0.50, 10/10)"; ">600" when nothing finished."""
    if c is None:
        return "-"
    if c.solved == 0:
        return f">{timeout:g} (0/{c.trials})"
    mark = ">" if c.lower_bound else ""
    return f"{mark}{c.mean_s:.2f} ± {c.stderr_s:.2f} (med {c.median_s:.2f}, {c.solved}/{c.trials})"


def format_planning(c: Optional[Cell]) -> str:
    """"0.45 (med 0.40)": the planner's own time, unfinished trials at the limit."""
    if c is None or c.planning is None:
        return "-"
    return f"{'>' if c.lower_bound else ''}{c.planning[0]:.2f} (med {c.planning[1]:.2f})"


def paper_cell(value: Optional[float]) -> str:
    return f">{PAPER_LIMIT:g}" if value is None else f"{value:.2f}"


def cells(trials: Sequence[Trial], columns: Sequence[PaperTask], methods: Sequence[str],
          timeout: float) -> Dict[Tuple[str, str], Optional[Cell]]:
    return {(c.task, m): cell([t for t in trials if t.task == c.task and t.method == m], timeout)
            for c in columns for m in methods}


def table(trials: Sequence[Trial], columns: Sequence[PaperTask], methods: Sequence[str],
          timeout: float) -> Tuple[List[str], List[List[str]], List[str]]:
    """Table 1 in the paper's layout: a row per method (ours, then the paper's), a column per
    task; and lines with the learned samplers' speed-up and the geometric means."""
    figures = cells(trials, columns, methods, timeout)
    header = ["method"] + [c.title for c in columns]
    rows = []
    for m in methods:
        rows.append([f"{METHOD_TITLES[m]} (ours)"] + [format_cell(figures[c.task, m], timeout) for c in columns])
        if any(getattr(figures[c.task, m], "planning", None) is not None for c in columns):
            rows.append([f"{METHOD_TITLES[m]} (ours, planner alone)"] + [format_planning(figures[c.task, m])
                                                                        for c in columns])
        if with_paper(columns, m):
            rows.append([f"{METHOD_TITLES[m]} (paper)"] + [paper_cell(c.paper[m]) for c in columns])
    return header, rows, summary_lines(figures, columns, methods, timeout)


def summary_lines(figures: Dict[Tuple[str, str], Optional[Cell]], columns: Sequence[PaperTask],
                  methods: Sequence[str], timeout: float) -> List[str]:
    lines = [f"time: mean ± standard error over the trials (s), unfinished ones counted at the {timeout:g} s limit "
             "(then the mean is a lower bound, '>'); med: median; n/N: plans found that replay in a fresh world; "
             "planner alone: the same trials' time less the process's start-up (interpreter, imports, parsing, "
             "world, checkpoints)"]
    for m in methods:
        ours = [figures[c.task, m] for c in columns]
        if all(x is not None for x in ours):
            # The all-mechanisms row is compared with the paper's Macro+Sampler row.
            row = "macro+sampler" if m == ALL_MECHANISMS else m
            mean = _geomean([x.mean_s for x in ours])
            solved = f"{sum(x.solved for x in ours)}/{sum(x.trials for x in ours)} solved"
            if not with_paper(columns, row):
                lines.append(f"{METHOD_TITLES[m]}: geometric mean {mean:.2f} s over {len(columns)} tasks; {solved}")
                continue
            paper = _geomean([c.paper[row] if c.paper[row] is not None else PAPER_LIMIT for c in columns])
            lines.append(f"{METHOD_TITLES[m]}: geometric mean {mean:.2f} s over {len(columns)} tasks against the "
                         f"paper's {paper:.2f} s ({paper / mean:.1f}x); {solved}")
            if all(x.planning is not None for x in ours):
                alone = _geomean([x.planning[0] for x in ours])
                lines.append(f"{METHOD_TITLES[m]}, planner alone: geometric mean {alone:.2f} s against the paper's "
                             f"{paper:.2f} s ({paper / alone:.1f}x)")
    if ALL_MECHANISMS in methods and "macro+sampler" in methods:
        one = [figures[c.task, "macro+sampler"] for c in columns]
        every = [figures[c.task, ALL_MECHANISMS] for c in columns]
        if all(one) and all(every):
            ratio = _geomean([x.mean_s for x in every]) / _geomean([x.mean_s for x in one])
            lines.append(f"all mechanisms loaded against the task's own: geometric mean {ratio:.2f}x the time")
    if "macro" in methods and "macro+sampler" in methods:
        for c in columns:
            generic, learned = figures[c.task, "macro"], figures[c.task, "macro+sampler"]
            if generic and learned and learned.median_samples and generic.median_samples:
                ratio = generic.median_samples / learned.median_samples
                fewer = f"{ratio:.1f}x fewer" if ratio >= 1 else f"{1 / ratio:.1f}x more"
                lines.append(f"{c.title}: learned samplers simulate {fewer} values (median {learned.median_samples:g} "
                             f"against {generic.median_samples:g}), mean time {learned.mean_s:.2f} s against "
                             f"{generic.mean_s:.2f} s")
    return lines


def _geomean(values: Sequence[float]) -> float:
    return math.exp(statistics.mean(math.log(max(v, 1e-3)) for v in values))


def plot(trials: Sequence[Trial], columns: Sequence[PaperTask], methods: Sequence[str], timeout: float,
         path: str, title: str) -> None:
    """Grouped bars on a log time axis, a group per task: ours solid, the paper's hatched
    beside them; a bar that did not finish is drawn at the limit with its mark."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from ..util.files import atomic_file
    figures = cells(trials, columns, methods, timeout)
    fig, ax = plt.subplots(figsize=(max(6.0, 1.9 * len(columns)), 4.2))
    x = np.arange(len(columns))
    width = 0.8 / (2 * len(methods))
    for k, m in enumerate(methods):
        ours = [figures[c.task, m] for c in columns]
        heights = [c.mean_s if c else 0 for c in ours]
        errors = [c.stderr_s if c else 0 for c in ours]
        offset = (2 * k - len(methods) + 0.5) * width
        bars = ax.bar(x + offset, heights, width, yerr=errors, color=METHOD_COLOURS.get(m),
                      label=f"{METHOD_TITLES[m]} (ours)")
        for bar, c in zip(bars, ours):
            if c is not None:  # above the error bar
                ax.annotate(f"{c.solved}/{c.trials}", (bar.get_x() + width / 2, c.mean_s + c.stderr_s), ha="center",
                            va="bottom", fontsize=7)
        if not with_paper(columns, m):
            continue
        paper = [c.paper[m] if c.paper[m] is not None else PAPER_LIMIT for c in columns]
        ax.bar(x + offset + width, paper, width, color="white", edgecolor=METHOD_COLOURS.get(m), hatch="///",
               label=f"{METHOD_TITLES[m]} (paper)")
    ax.set_yscale("log")
    ax.axhline(timeout, color="k", lw=0.6, ls="--")
    ax.set_xticks(x, [c.title for c in columns])
    ax.set_ylabel("mean solve time (s, log)")
    ax.set_title(title, fontsize=9)
    # Below the axes: above them it hides the tallest bars (the paper's >600 s ones).
    ax.legend(fontsize=7, ncol=2 * len(methods), loc="upper center", bbox_to_anchor=(0.5, -0.1), frameon=False)
    fig.tight_layout()
    with atomic_file(path, binary=True, suffix=".png") as handle:
        fig.savefig(handle, format="png", dpi=90)
    plt.close(fig)
