"""`bench compose`: the paper's Table 2 -- the two compositional tasks, solved with every
mechanism fragment loaded together (no training of their own), by the three methods of
Table 1: success in N runs and the median time of those that succeed."""
from __future__ import annotations

import statistics
from dataclasses import dataclass
from typing import Dict, List, Sequence, Tuple

from .trials import METHOD_TITLES, Trial


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
            paper.append(f"{100 * c.paper[m]:.0f} %")
        rows += [row, paper]
    invalid = [t for t in trials if t.status == "invalid"]
    lines = ["n/N: plans found within the limit that replay in a fresh world; median over those"]
    lines += [f"{t.instance} {t.method}: {t.reason}" for t in invalid]
    return header, rows, lines
