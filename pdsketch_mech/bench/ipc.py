"""IPC benchmark: our classical planner (and optionally pyperplan) on `DIR/*/domain.pddl` problems.

Every trial runs in a fresh spawned process, so a hang or a memory blow-up only loses that
trial and no run shares another's caches. A trial's time is wall-clock `perf_counter` from
before parsing to after the plan is found (parse + ground + search); imports come before
the clock. A trial still running `timeout + GRACE_S` seconds after its worker is ready is
killed; one that finishes after `timeout` seconds also counts as a timeout.
"""
from __future__ import annotations

import glob
import multiprocessing
import os
import statistics
import sys
from dataclasses import dataclass, field
from time import perf_counter
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple


from ..lang.loader import load_problem
from ..symbolic.solve import solve
from ..symbolic.validate import validate_plan
from ..util.progress import progress_bar

OURS = "ours"
PEERS = ("pyperplan",)
PEER_SEARCH = {"gbfs": "gbf", "wastar": "wastar"}  # pyperplan's nearest search, always with h_FF
GRACE_S = 1.0      # extra wait past the timeout before a trial's process is killed
STARTUP_S = 60.0   # how long a worker may take to start and import its planner
BAND = (0.1, 60.0)  # peer times (s) the target speed-up is defined on


class BenchError(Exception):
    """Bad benchmark input (reported in one line, exit code 2)."""


@dataclass
class IpcTrial:
    """One planner on one problem."""

    domain: str
    problem: str
    planner: str
    status: str                       # solved | unsolvable | timeout | error | crashed
    time_s: Optional[float] = None    # None when the process was killed
    length: Optional[int] = None
    valid: Optional[bool] = None      # ours only: the plan passed validate_plan
    expansions: Optional[int] = None  # ours only
    stats: Dict[str, float] = field(default_factory=dict)
    message: str = ""


def discover(directory: str) -> List[Tuple[str, str]]:
    """(domain folder name, problem path) for every `*.pddl` beside a `domain.pddl`, sorted."""
    if not os.path.isdir(directory):
        raise BenchError(f"{directory}: no such directory")
    found = []
    for domain_file in sorted(glob.glob(os.path.join(directory, "*", "domain.pddl"))):
        folder = os.path.dirname(domain_file)
        for path in sorted(glob.glob(os.path.join(folder, "*.pddl"))):
            if path != domain_file:
                found.append((os.path.basename(folder), path))
    if not found:
        raise BenchError(f"{directory}: no problems found (expected DIR/*/domain.pddl with other *.pddl beside it)")
    return found


def _run_ours(path: str, search: str, timeout: float, ready: Callable[[], None]) -> Dict[str, Any]:
    """Load, ground and search (timed), then validate the plan (untimed)."""
    ready()
    start = perf_counter()
    loaded, problem = load_problem(path)
    result = solve(loaded.domain, problem, loaded.types, search=search,
                   timeout=max(0.0, timeout - (perf_counter() - start)))
    elapsed = perf_counter() - start
    out = {"status": result.status, "time_s": elapsed, "expansions": int(result.stats["expansions"]),
           "stats": result.stats}
    if result.status == "solved":
        check = validate_plan(loaded.domain, problem, result.plan)
        out.update(length=len(result.plan), valid=check.ok, message="" if check.ok else check.message)
    return out


def _run_pyperplan(path: str, search: str, timeout: float, ready: Callable[[], None]) -> Dict[str, Any]:
    """pyperplan's `search_plan` with h_FF (it has no timeout of its own: the parent kills it)."""
    import logging

    from pyperplan.planner import HEURISTICS, SEARCHES, search_plan

    logging.disable(logging.CRITICAL)
    domain_file = os.path.join(os.path.dirname(path), "domain.pddl")
    ready()
    start = perf_counter()
    plan = search_plan(domain_file, path, SEARCHES[PEER_SEARCH[search]], HEURISTICS["hff"])
    elapsed = perf_counter() - start
    return {"status": "unsolvable" if plan is None else "solved", "time_s": elapsed,
            "length": None if plan is None else len(plan)}


_RUNNERS = {OURS: _run_ours, "pyperplan": _run_pyperplan}


def _worker(conn: Any, planner: str, path: str, search: str, timeout: float) -> None:
    """Process body: send "ready" once imports are done, then the result fields."""
    try:
        out = _RUNNERS[planner](path, search, timeout, lambda: conn.send("ready"))
    except MemoryError:
        out = {"status": "crashed", "message": "out of memory"}
    except Exception as error:  # any failure is this trial's result, reported in one line
        out = {"status": "error", "message": " ".join(f"{type(error).__name__}: {error}".split())}
    conn.send(out)
    conn.close()


def run_trial(planner: str, domain: str, path: str, search: str, timeout: float) -> IpcTrial:
    """One trial in a fresh spawned process, killed if it overruns."""
    context = multiprocessing.get_context("spawn")
    receiver, sender = context.Pipe(duplex=False)
    process = context.Process(target=_worker, args=(sender, planner, path, search, timeout), daemon=True)
    process.start()
    sender.close()  # so the receiver sees end-of-file if the worker dies
    message: Any = None
    try:
        message = _receive(receiver, STARTUP_S)
        if message == "ready":
            message = _receive(receiver, timeout + GRACE_S)
    finally:
        if message not in (None, "ready"):  # finished: let it exit; otherwise kill it now
            process.join(GRACE_S)
        process.kill()
        process.join()
        receiver.close()
    if message is None:
        fields: Dict[str, Any] = {"status": "timeout", "message": f"killed after {timeout + GRACE_S:g} s"}
    elif message == "eof":
        fields = {"status": "crashed", "message": f"worker died (exit code {process.exitcode})"}
    else:
        fields = message
    if fields["status"] == "solved" and fields["time_s"] > timeout:
        fields.update(status="timeout", length=None, valid=None)
    return IpcTrial(domain, os.path.splitext(os.path.basename(path))[0], planner, **fields)


def _receive(conn: Any, wait: float) -> Any:
    """The next message, None if none came within `wait` seconds, "eof" if the worker died."""
    if not conn.poll(wait):
        return None
    try:
        return conn.recv()
    except EOFError:
        return "eof"


def run_ipc(directory: str, timeout: float = 60.0, peer: Optional[str] = None, search: str = "gbfs",
            progress: bool = True) -> List[IpcTrial]:
    """Every problem under `directory`: ours, then the peer (if any), one after the other."""
    problems = discover(directory)
    planners = [OURS] + ([peer] if peer else [])
    trials = []
    with progress_bar(total=len(problems) * len(planners), unit="trial", disable=not progress) as bar:
        for domain, path in problems:
            for planner in planners:
                bar.set_description(f"{domain}/{os.path.basename(path)} {planner}")
                trials.append(run_trial(planner, domain, path, search, timeout))
                if trials[-1].status in ("error", "crashed"):
                    bar.write(f"{path}: {planner}: {trials[-1].status}: {trials[-1].message}", file=sys.stderr)
                bar.update()
    return trials


def _by_problem(trials: Sequence[IpcTrial]) -> List[Tuple[str, IpcTrial, Optional[IpcTrial]]]:
    """(domain/problem, our trial, the peer's trial or None) in run order."""
    ours = [t for t in trials if t.planner == OURS]
    peers = {(t.domain, t.problem): t for t in trials if t.planner != OURS}
    return [(f"{t.domain}/{t.problem}", t, peers.get((t.domain, t.problem))) for t in ours]


def _solved(trial: Optional[IpcTrial]) -> bool:
    """Solved, and (for ours) with a valid plan."""
    return trial is not None and trial.status == "solved" and trial.valid is not False


def _ratio(ours: IpcTrial, peer: Optional[IpcTrial]) -> Optional[float]:
    """Peer time / our time, when both solved."""
    if not (_solved(ours) and _solved(peer)):
        return None
    return peer.time_s / max(ours.time_s, 1e-9)


def _median(values: Sequence[float]) -> Optional[float]:
    return statistics.median(values) if values else None


def summarize(trials: Sequence[IpcTrial], peer: Optional[str] = None) -> Dict[str, Any]:
    """Solved counts, peer-only solves, median time ratios (all / in BAND), median length ratio."""
    rows = _by_problem(trials)
    summary: Dict[str, Any] = {
        "problems": len(rows), "ours_solved": sum(_solved(o) for _, o, _ in rows),
        "ours_invalid": [name for name, o, _ in rows if o.valid is False]}
    if peer:
        both = [(o, p) for _, o, p in rows if _solved(o) and _solved(p)]
        band = [(o, p) for o, p in both if BAND[0] <= p.time_s <= BAND[1]]
        summary.update(
            peer=peer, peer_solved=sum(_solved(p) for _, _, p in rows),
            peer_only=[name for name, o, p in rows if _solved(p) and not _solved(o)],
            both_solved=len(both), median_time_ratio=_median([_ratio(o, p) for o, p in both]),
            band_s=list(BAND), band_problems=len(band), median_time_ratio_band=_median([_ratio(o, p) for o, p in band]),
            median_length_ratio=_median([o.length / p.length for o, p in both if p.length]))
    return summary


def _fmt(value: Optional[float], spec: str) -> str:
    return "-" if value is None else format(value, spec)


def table(trials: Sequence[IpcTrial], peer: Optional[str] = None) -> Tuple[List[str], List[List[str]]]:
    """Header and cells: problem, our status/time/length/expansions/validity, then the peer's."""
    header = ["problem", OURS, "time s", "length", "expansions", "valid"]
    header += [peer, "time s", "length", "ratio"] if peer else []
    cells = []
    for name, ours, other in _by_problem(trials):
        valid = {True: "yes", False: "NO", None: "-"}[ours.valid]
        row = [name, ours.status, _fmt(ours.time_s, ".3f"), _fmt(ours.length, "d"),
               _fmt(ours.expansions, "d"), valid]
        if peer:
            other = other or IpcTrial(ours.domain, ours.problem, peer, "-")
            row += [other.status, _fmt(other.time_s, ".3f"), _fmt(other.length, "d"),
                    _fmt(_ratio(ours, other), ".2f")]
        cells.append(row)
    return header, cells


def summary_lines(summary: Dict[str, Any]) -> List[str]:
    """The summary as sentences (the same lines go to stdout and to markdown)."""
    n = summary["problems"]
    invalid = summary["ours_invalid"]
    lines = [f"ours solved: {summary['ours_solved']}/{n}"
             + (f" (INVALID plans: {', '.join(invalid)})" if invalid else " (every plan valid)")]
    if "peer" in summary:
        peer, (low, high) = summary["peer"], summary["band_s"]
        lines += [f"{peer} solved: {summary['peer_solved']}/{n}",
                  f"{peer} solved but ours did not: {', '.join(summary['peer_only']) or 'none'}",
                  f"median time ratio ({peer} / ours) over {summary['both_solved']} problems both solved: "
                  f"{_fmt(summary['median_time_ratio'], '.2f')}",
                  f"median time ratio where {peer} took {low:g}-{high:g} s ({summary['band_problems']} problems): "
                  f"{_fmt(summary['median_time_ratio_band'], '.2f')}",
                  f"median plan length ratio (ours / {peer}) over problems both solved: "
                  f"{_fmt(summary['median_length_ratio'], '.3f')}"]
    return lines


def plot(trials: Sequence[IpcTrial], peer: str, path: str) -> None:
    """Log-log scatter of peer time vs our time (problems both solved), one style per domain."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    points = [(o.domain, p.time_s, o.time_s) for _, o, p in _by_problem(trials) if _ratio(o, p) is not None]
    fig, ax = plt.subplots(figsize=(7, 6))
    for i, domain in enumerate(sorted({d for d, _, _ in points})):  # 10 colours, then a new marker
        ax.scatter([x for d, x, _ in points if d == domain], [y for d, _, y in points if d == domain],
                   label=domain, s=30, alpha=0.85, color=f"C{i % 10}", marker="osD^v"[i // 10 % 5])
    values = [v for _, x, y in points for v in (x, y)] or [0.01, 1.0]
    low, high = min(values) / 2, max(values) * 2
    ax.plot([low, high], [low, high], "k-", lw=1, label="y = x (same speed)")
    ax.plot([low, high], [low / 5, high / 5], "k--", lw=1, label="y = x/5 (5x faster)")
    ax.set(xscale="log", yscale="log", xlim=(low, high), ylim=(low / 5, high),
           xlabel=f"{peer} time (s)", ylabel="our time (s)",
           title=f"IPC: our planner vs {peer} ({len(points)} problems both solved)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
