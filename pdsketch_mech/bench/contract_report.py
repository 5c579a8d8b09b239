"""`bench contract`'s verdicts, tables and summary: whether each configuration kept the
planner's contract on each problem (solved within CONTRACT_FACTOR times the basis
operators' time plus CONTRACT_SLACK_S), read from the trials a run wrote."""
from __future__ import annotations

import math
import statistics
from dataclasses import asdict, dataclass
from typing import Any, Dict, List, Optional, Sequence

from .trials import Trial

CONTRACT_FACTOR = 1.5    # a configuration keeps the contract within this many times the basis time ...
CONTRACT_SLACK_S = 5.0   # ... plus this many seconds (start-up and loading mechanisms cost a little)
BASIS = "basis"          # the configuration every other is measured against
CERTIFIED_FAILURE = "its :certified facts do not hold after its steps"   # planner/refine.py's reason
NOT_COUNTED = "basis unsolved"


def limit_s(basis_s: float) -> float:
    """The most a config may take on a problem the basis operators solve in `basis_s`."""
    return CONTRACT_FACTOR * basis_s + CONTRACT_SLACK_S


@dataclass
class Verdict:
    """One (problem, config) against the problem's basis trial."""

    problem: str
    config: str
    status: str
    time_s: float
    basis_s: Optional[float]     # None: the basis operators did not solve it (not counted)
    limit_s: Optional[float]
    ratio: Optional[float]       # time / basis time, solved trials only
    meets: Optional[bool]        # None: not counted
    values: int                  # values simulated
    basis_values: Optional[int]
    executions: int
    certified_failures: int
    reason: str = ""

    @property
    def counted(self) -> bool:
        return self.meets is not None


def verdict(trial: Trial, basis: Optional[Trial]) -> Verdict:
    """Whether `trial` keeps the contract against the same problem's `basis` trial."""
    solved = trial.status == "solved"
    basis_ok = basis is not None and basis.status == "solved"
    basis_s = basis.time_s if basis_ok else None
    limit = limit_s(basis_s) if basis_s is not None else None
    ratio = trial.time_s / max(basis_s, 1e-3) if (solved and basis_s is not None) else None
    meets = (solved and trial.time_s <= limit) if limit is not None else None
    return Verdict(trial.task, trial.method, trial.status, trial.time_s, basis_s, limit, ratio, meets,
                   trial.samples, basis.samples if basis_ok else None, getattr(trial, "executions", 0),
                   getattr(trial, "certified_failures", 0), trial.reason)


def verdicts(trials: Sequence[Trial]) -> List[Verdict]:
    """Every non-basis trial judged against its problem's basis trial."""
    basis = {t.task: t for t in trials if t.method == BASIS}
    return [verdict(t, basis.get(t.task)) for t in trials if t.method != BASIS]


def format_time(status: str, time_s: float) -> str:
    return f"{time_s:.2f}" if status == "solved" else status


def cell_text(v: Optional[Verdict]) -> str:
    """"2.31" (keeps it), "14.02 !" or "unsolved !" (breaks it), "-" (no trial yet)."""
    if v is None:
        return "-"
    return format_time(v.status, v.time_s) + (" !" if v.meets is False else "")


def table(trials: Sequence[Trial], problems: Sequence[str], config_names: Sequence[str],
          timeout: float) -> Tuple[List[str], List[List[str]], List[str]]:
    """A row per problem: its basis time, the contract's limit, each config's time, and how many
    configs keep the contract; then the summary lines."""
    others = [c for c in config_names if c != BASIS]
    by_key = {(t.task, t.method): t for t in trials}
    judged = {(v.problem, v.config): v for v in verdicts(trials)}
    header = ["problem", "basis s", "limit s"] + others + ["meets"]
    rows = []
    for p in problems:
        b = by_key.get((p, BASIS))
        row = [p, format_time(b.status, b.time_s) if b else "-",
               f"{limit_s(b.time_s):.2f}" if b and b.status == "solved" else "-"]
        row += [cell_text(judged.get((p, c))) for c in others]
        mine = [judged[p, c] for c in others if (p, c) in judged]
        if b is not None and b.status != "solved":
            row.append(NOT_COUNTED)
        else:
            row.append(f"{sum(bool(v.meets) for v in mine)}/{len(mine)}" if mine else "-")
        rows.append(row)
    return header, rows, summary_lines(trials, problems, others, timeout)


def values_table(trials: Sequence[Trial], problems: Sequence[str],
                 config_names: Sequence[str]) -> Tuple[List[str], List[List[str]]]:
    """Values simulated (executed steps) per problem and config: the same comparison without
    timing noise."""
    by_key = {(t.task, t.method): t for t in trials}
    header = ["problem"] + [f"{c} values (steps)" if c == BASIS else c for c in config_names]
    rows = []
    for p in problems:
        row = [p]
        for c in config_names:
            t = by_key.get((p, c))
            row.append("-" if t is None else f"{t.samples} ({getattr(t, 'executions', 0)})"
                       + ("" if t.status == "solved" else f" {t.status}"))
        rows.append(row)
    return header, rows


def summarize(trials: Sequence[Trial], others: Sequence[str]) -> Dict[str, Any]:
    """The figures of the summary line, as the JSON summary holds them."""
    judged = [v for v in verdicts(trials) if v.config in others]
    counted = [v for v in judged if v.counted]
    solved = [v for v in counted if v.ratio is not None]
    worst = max(solved, key=lambda v: (v.ratio, v.time_s), default=None)
    broken = [v for v in counted if not v.meets]
    basis = [t for t in trials if t.method == BASIS]
    per_config = {}
    for c in others:
        mine = [v for v in counted if v.config == c]
        ratios = [v.values / v.basis_values for v in mine if v.status == "solved" and v.basis_values]
        per_config[c] = {"pairs": len(mine), "met": sum(bool(v.meets) for v in mine),
                         "worst_ratio": max((v.ratio for v in mine if v.ratio is not None), default=None),
                         "unsolved": sum(v.status != "solved" for v in mine),
                         "values_ratio_geomean": _geomean(ratios) if ratios else None,
                         # over every problem, counted or not: how often the mechanism's promise failed
                         "certified_failures": sum(v.certified_failures for v in judged if v.config == c)}
    return {
        "factor": CONTRACT_FACTOR, "slack_s": CONTRACT_SLACK_S,
        "pairs": len(counted), "met": len(counted) - len(broken),
        "problems": len({v.problem for v in counted}), "configs": len(others),
        "worst": None if worst is None else {"problem": worst.problem, "config": worst.config,
                                             "ratio": worst.ratio, "time_s": worst.time_s, "basis_s": worst.basis_s},
        "unsolved": sum(v.status != "solved" for v in counted),
        "broken": [asdict(v) for v in broken],
        "basis_unsolved": sorted(t.task for t in basis if t.status != "solved"),
        "per_config": per_config,
    }


def summary_lines(trials: Sequence[Trial], problems: Sequence[str], others: Sequence[str],
                  timeout: float) -> List[str]:
    s = summarize([t for t in trials if t.task in set(problems)], others)
    worst = s["worst"]
    worst_text = (f"worst ratio {worst['ratio']:.2f}x ({worst['problem']}, {worst['config']}: "
                  f"{worst['time_s']:.2f} s against {worst['basis_s']:.2f} s)" if worst else "worst ratio -")
    lines = [f"contract: {s['met']}/{s['pairs']} config x problem pairs keep it ({count_of(s['configs'], 'config')} x "
             f"{count_of(s['problems'], 'problem')}; solved within {timeout:g} s and time <= {CONTRACT_FACTOR:g} x basis + "
             f"{CONTRACT_SLACK_S:g} s); {worst_text}; {s['unsolved']} unsolved",
             f"times in s from the process's start (start-up included); limit: {CONTRACT_FACTOR:g} x basis + "
             f"{CONTRACT_SLACK_S:g} s; '!': breaks the contract (unsolved, not replayed, or over the limit)"]
    if s["basis_unsolved"]:
        lines.append(f"not counted, the basis operators did not solve them: {', '.join(s['basis_unsolved'])}")
    for v in s["broken"]:
        why = (f"{v['time_s']:.2f} s > {v['limit_s']:.2f} s ({v['ratio']:.2f}x)" if v["status"] == "solved"
               else f"{v['status']}: {v['reason'] or '?'}")
        lines.append(f"breaks: {v['problem']} {v['config']}: {why}")
    ratios = [f"{c} {x['values_ratio_geomean']:.2f}x" for c, x in s["per_config"].items()
              if x["values_ratio_geomean"] is not None]
    if ratios:
        lines.append("values simulated against basis (geometric mean over solved problems): " + ", ".join(ratios))
    certified = [f"{c} {x['certified_failures']}" for c, x in s["per_config"].items() if x["certified_failures"]]
    if certified:
        lines.append("mechanisms' :certified facts that failed after their steps (all problems): "
                     + ", ".join(certified))
    return lines


def count_of(count: int, noun: str) -> str:
    return f"{count} {noun}{'' if count == 1 else 's'}"


def _geomean(values: Sequence[float]) -> float:
    return math.exp(statistics.mean(math.log(max(v, 1e-6)) for v in values))


# ----------------------------------------------------------------------------- the command
