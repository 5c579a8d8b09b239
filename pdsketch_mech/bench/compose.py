"""`bench compose`: the paper's Table 2 -- the two compositional tasks, solved with every
mechanism fragment loaded together (no training of their own), by the three methods of
Table 1: success in N runs and the median time of those that succeed."""
from __future__ import annotations

import statistics
from dataclasses import dataclass
from typing import Dict, List, Sequence, Tuple

from .trials import METHOD_COLOURS, METHOD_TITLES, Trial


@dataclass(frozen=True)
class PaperComposition:
    task: str
    title: str
    paper: Dict[str, float]   # success rate in 10 runs of 10 minutes


TABLE2: Tuple[PaperComposition, ...] = (
    PaperComposition("push-pick-hook", "Push-then-Pick-then-Hook", {"basis": 0.0, "macro": 0.2, "macro+sampler": 1.0}),
    PaperComposition("hook-slope", "Hook-then-Place-on-Slope", {"basis": 0.0, "macro": 0.0, "macro+sampler": 0.9}),
)
BY_TASK = {t.task: t for t in TABLE2}


def column_of(task: str) -> PaperComposition:
    """The paper's column of `task`, or one without the paper's figures for a composition
    beyond the paper."""
    if task in BY_TASK:
        return BY_TASK[task]
    from ..envs.task_names import resolve_task
    return PaperComposition(task, resolve_task(task).title, {})


def table(trials: Sequence[Trial], columns: Sequence[PaperComposition],
          methods: Sequence[str]) -> Tuple[List[str], List[List[str]], List[str]]:
    """A row per method, a column per task: "n/N (xx %), median T s" for ours, the paper's rate beside."""
    header = ["method"] + [c.title for c in columns]
    rows = []
    for m in methods:
        row, paper = [f"{METHOD_TITLES[m]} (ours)"], [f"{METHOD_TITLES[m]} (paper)"]
        for c in columns:
            mine = [t for t in trials if t.task == c.task and t.method == m]
            solved = [t.time_s for t in mine if t.status == "solved"]
            median = f", median {statistics.median(solved):.1f} s" if solved else ""
            row.append(f"{len(solved)}/{len(mine)} ({100 * len(solved) / max(1, len(mine)):.0f} %){median}"
                       if mine else "-")
            paper.append(f"{100 * c.paper[m]:.0f} %" if m in c.paper else "-")
        rows += [row, paper] if any(m in c.paper for c in columns) else [row]
    invalid = [t for t in trials if t.status == "invalid"]
    lines = ["n/N: plans found within the limit that replay in a fresh world; median over those"]
    lines += [f"{t.instance} {t.method}: {t.reason}" for t in invalid]
    return header, rows, lines


def plot(trials: Sequence[Trial], columns: Sequence[PaperComposition], methods: Sequence[str], timeout: float,
         path: str, title: str) -> None:
    """Left: success rates, a group per task, ours solid and the paper's hatched beside them.
    Right: every run's time (log), those that did not finish marked x at the limit: with
    times this heavy-tailed, the spread says more than the median."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    from ..util.files import atomic_file
    fig, (rates, times) = plt.subplots(1, 2, figsize=(max(8.0, 3.6 * len(columns)), 4.0))
    x = np.arange(len(columns))
    width = 0.8 / (2 * len(methods))
    for k, m in enumerate(methods):
        runs = [[t for t in trials if t.task == c.task and t.method == m] for c in columns]
        solved = [sum(t.status == "solved" for t in r) for r in runs]
        offset = (2 * k - len(methods) + 0.5) * width
        bars = rates.bar(x + offset, [s / len(r) if r else 0.0 for s, r in zip(solved, runs)], width,
                         color=METHOD_COLOURS.get(m), label=f"{METHOD_TITLES[m]} (ours)")
        for bar, r, s in zip(bars, runs, solved):
            if r:
                rates.annotate(f"{s}/{len(r)}", (bar.get_x() + width / 2, bar.get_height()), ha="center",
                               va="bottom", fontsize=7)
        rates.bar(x + offset + width, [c.paper.get(m, 0.0) for c in columns], width, color="white",
                  edgecolor=METHOD_COLOURS.get(m), hatch="///", label=f"{METHOD_TITLES[m]} (paper)")
        for i, r in enumerate(runs):
            jitter = np.linspace(-0.08, 0.08, max(1, len(r)))   # runs side by side, not on one another
            for j, t in enumerate(r):
                done = t.status == "solved"
                times.scatter(i + (k - (len(methods) - 1) / 2) * 0.25 + jitter[j], t.time_s if done else timeout,
                              marker="o" if done else "x", color=METHOD_COLOURS.get(m), s=18,
                              label=METHOD_TITLES[m] if i == 0 and j == 0 else None)
    for ax in (rates, times):
        ax.set_xticks(x, [c.title for c in columns], fontsize=8)
    rates.set_ylim(0, 1.15)
    rates.set_ylabel("success rate")
    rates.legend(fontsize=7, ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.1), frameon=False)
    times.set_yscale("log")
    times.axhline(timeout, color="k", lw=0.6, ls="--")
    times.set_ylabel("solve time per run (s, log; x: not solved)")
    times.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=len(methods), frameon=False)
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    with atomic_file(path, binary=True, suffix=".png") as handle:
        fig.savefig(handle, format="png", dpi=90)
    plt.close(fig)
