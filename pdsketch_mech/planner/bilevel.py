"""The adaptive bilevel planner: skeletons from the FF-guided symbolic search (with
optimistic stream placeholders), refined by sampling and simulation.

Adaptive, in PDDLStream's sense: work is shared between refining the skeletons found so far
and taking new ones from the symbolic search (schedule.py), so a skeleton that needs many
samples is not starved by the search for new ones, and a deep one (a tool use 20 skeletons
down) is reached within a bounded amount of work.
"""
from __future__ import annotations

import time
import zlib
from collections import Counter
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Dict, Iterator, List, Mapping, Optional, Tuple

import numpy as np

from ..lang.loader import LoadedDomain
from ..lang.nodes import Problem
from ..symbolic.grounding import ground
from ..symbolic.optimistic import optimistic_problem
from ..symbolic.skeletons import iter_skeletons
from ..symbolic.task import StripsTask
from ..world.world import World
from .bindings import StepSampler
from .detours import detour_weight, unexplained_detours
from .execute import contact_mask, execute_plan, observed_state, settle_start
from .macros import add_mechanism_macros
from .pristine import PristineFailures, StepKey, fixed_objects, pristine_keys
from .refine import Refinement, Step, skeleton_steps
from .schedule import SLICE, next_turn
from .serialize import plan_entries

if TYPE_CHECKING:
    from ..samplers.learned.ranked import LearnedMechanism



@dataclass
class PlanResult:
    status: str                                         # "solved" | "unsolved"
    steps: List[Step] = field(default_factory=list)
    values: List[Dict[str, object]] = field(default_factory=list)
    time_s: float = 0.0
    stats: Dict[str, object] = field(default_factory=dict)
    reason: str = ""


# Operators that only move the arm through free space. Every operator plans its own
# approach from wherever the arm is, so on their own these never enable anything; the
# symbolic search skips them unless a mechanism lists them as steps.
FREE_MOTIONS = ("transit", "move")


def prepare_task(domain: LoadedDomain, problem: Problem, use_mechanisms: bool = True):
    """Optimistic problem, grounded task (not relevance-pruned: effect-free pushes matter),
    and mechanisms as macro operators."""
    optimistic, placeholders = optimistic_problem(domain.domain, problem, domain.types)
    task = ground(domain.domain, optimistic, domain.types, prune_irrelevant=False)
    steps = {call.name for m in domain.domain.mechanisms for call in m.actions} if use_mechanisms else set()
    task.operators = [op for op in task.operators if op.name not in FREE_MOTIONS or op.name in steps]
    if use_mechanisms and domain.domain.mechanisms:
        add_mechanism_macros(task, domain.domain, domain.types, optimistic)
    return task, placeholders


def skeleton_order(task: StripsTask, deadline: Optional[float] = None,
                   memo: Optional[PristineFailures] = None) -> Iterator[List[int]]:
    """Skeletons in the order the planner takes them from the symbolic search. With `memo`,
    as refinement finds pristine steps dead (pristine.py): paths that would repeat one wait
    until the others run out, and paths are told apart by which of the objects of dead
    steps they have handled (a box out of reach hooked closer and put back is not the box
    where it lay)."""
    if memo is None:
        return iter_skeletons(task, deadline=deadline)
    masks = memo.attach(task)
    return iter_skeletons(task, deadline=deadline, handles=masks, relevant=lambda: memo.flagged,
                          blocked=memo.blocks_operator)


def bilevel_plan(domain: LoadedDomain, problem: Problem, world: World, timeout: float = 600.0, seed: int = 0,
                 use_mechanisms: bool = True, max_skeletons: int = 200, validate: bool = True,
                 learned: Optional[Mapping[str, "LearnedMechanism"]] = None) -> PlanResult:
    """Plan in `world` (a fresh world of `problem`'s scene; left as it was) within `timeout`
    seconds. With `validate`, a refined skeleton counts only once it has been re-executed
    in another fresh world, as `replay` does, and reached the goal there. `learned`: the
    mechanisms' learned samplers, by mechanism name."""
    start = time.perf_counter()
    deadline = start + timeout
    task, placeholders = prepare_task(domain, problem, use_mechanisms)
    counts: Counter = Counter()
    sampler = StepSampler({s.name: s for s in domain.domain.streams}, placeholders, counts,
                          learned if use_mechanisms else None)
    sampler.deadline = deadline
    warnings = settle_start(world)
    initial = world.snapshot()
    stats: Dict[str, object] = {"skeletons": 0, "refined": 0, "pruned": 0, "samples": counts,
                                "operators": len(task.operators), "executions": 0, "rejected": 0,
                                "symbolic_s": 0.0, "continuous_s": 0.0,
                                # read when the statistics are finished:
                                "proposals": sampler.proposals, "simulated": sampler.simulated,
                                "score_ms": [m.score_seconds for m in (learned or {}).values()],
                                "trust": sampler.trust}
    sim_start = world.sim_steps
    mismatch = _initial_mismatch(task, world)
    if mismatch:
        warnings.append(mismatch)
    if warnings:
        stats["warnings"] = warnings

    def in_fresh_world(steps: List[Step], values: List[Dict[str, object]]) -> Optional[str]:
        result = execute_plan(task, problem, plan_entries(steps, values))
        return None if result.goal_reached else f"in a fresh world, {result.message}"
    memo, fixed = PristineFailures(start=start), fixed_objects(task)
    skeletons = skeleton_order(task, deadline, memo)
    # Skeletons that repeat a dead pristine step, in order, with their steps and step keys.
    deferred: List[Tuple[List[int], List[Step], List[Optional[StepKey]]]] = []
    active: Dict[int, Refinement] = {}
    plans: Dict[int, List[int]] = {}
    created: List[Dict[str, object]] = []   # for the statistics: when each skeleton entered
    stats["skeleton_log"] = created
    stats["deferred"] = 0
    failures: Counter = Counter()
    more = True

    def can_search() -> bool:
        return more and stats["skeletons"] < max_skeletons and time.perf_counter() < deadline

    def next_plan():
        """The next skeleton that repeats no dead pristine step, with its steps and their
        keys; a deferred one once the symbolic search has no more (or the cap is reached);
        None when none is left."""
        nonlocal more
        while can_search():
            plan = next(skeletons, None)
            if plan is None:
                more = False
                break
            steps = skeleton_steps(task, plan)
            keys = pristine_keys(steps, fixed)
            if not memo.blocks(keys):
                return plan, steps, keys
            deferred.append((plan, steps, keys))
            stats["deferred"] += 1
        return deferred.pop(0) if deferred else None

    upcoming = None   # the next skeleton, looked at before it is created: its weight counts

    def peek():
        nonlocal upcoming
        t0 = time.perf_counter()
        if upcoming is None:
            upcoming = next_plan()
        while upcoming is not None and can_search() and memo.blocks(upcoming[2]):  # died since
            deferred.append(upcoming)
            stats["deferred"] += 1
            upcoming = next_plan()
        stats["symbolic_s"] += time.perf_counter() - t0
        return upcoming

    detour_counts: Dict[Tuple[int, ...], Tuple[int, int]] = {}  # plan -> (flagged objects, detours)

    def detours(plan: List[int]) -> int:
        key = tuple(plan)
        known = detour_counts.get(key)
        if known is None or known[0] != memo.flagged:
            known = detour_counts[key] = (memo.flagged, unexplained_detours(task, plan, memo.masks, memo.flagged))
        return known[1]

    def weight(refinement: Refinement) -> float:
        return (sampler.promise.weight(refinement.groundings())
                * detour_weight(detours(plans[refinement.rank])))

    try:
        while time.perf_counter() < deadline:
            taken = peek() if can_search() or deferred or upcoming is not None else None
            turn = next_turn(((r.rank, r.effort, weight(r)) for r in active.values()),
                             stats["skeletons"] + 1 if taken is not None else None,
                             detour_weight(detours(taken[0])) if taken is not None else 1.0)
            if turn is None:
                break
            if turn not in active:
                upcoming = None
                plan, steps, keys = taken
                stats["skeletons"] += 1
                label = " ".join(task.operators[o].label for o in plan)
                created.append({"rank": turn, "created_s": round(time.perf_counter() - start, 3), "skeleton": label})
                if detours(plan):
                    created[-1]["detours"] = detours(plan)
                # Each skeleton draws from its own generator, seeded by the plan's seed and its
                # labels: what one skeleton draws does not depend on which others came first
                # (or were deferred), so a change in the skeleton order does not reshuffle luck.
                skeleton_rng = np.random.default_rng([seed, zlib.crc32(label.encode())])
                active[turn] = Refinement(steps, initial, world, task, sampler, skeleton_rng,
                                          in_fresh_world if validate else None, rank=turn,
                                          pristine=keys, memo=memo)
                plans[turn] = plan
            refinement = active[turn]
            t0, deaths = time.perf_counter(), memo.deaths
            values = refinement.run(deadline, SLICE)
            stats["continuous_s"] += time.perf_counter() - t0
            if values is not None:
                del active[turn]
                for other in active.values():
                    failures += _retire(other, stats)
                stats["sim_steps"] = world.sim_steps - sim_start
                stats["dead_steps"] = memo.labels()
                return _result("solved", refinement, values, start, stats, failures + refinement.failures)
            if refinement.exhausted:
                del active[turn]
                stats["pruned"] += 1
                failures += _retire(refinement, stats)
            if memo.deaths > deaths:  # skeletons created before that repeat the dead step wait
                for rank in [r for r, other in active.items() if memo.blocks(other.pristine)]:
                    retired = active.pop(rank)
                    failures += _retire(retired, stats)
                    deferred.append((plans[rank], list(retired.steps), list(retired.pristine)))
                    stats["deferred"] += 1
    finally:
        world.restore(initial)
    for refinement in active.values():
        failures += _retire(refinement, stats)
    stats["sim_steps"] = world.sim_steps - sim_start
    stats["dead_steps"] = memo.labels()
    elapsed = time.perf_counter() - start
    if time.perf_counter() >= deadline:
        reason = f"timed out after {elapsed:.1f} s"
    elif stats["skeletons"] == 0:
        reason = "no plan exists: no sequence of operators reaches the goal symbolically"
    else:
        reason = f"no plan exists: none of the {stats['skeletons']} skeletons could be refined"
    return PlanResult("unsolved", time_s=elapsed, stats=_finish_stats(stats, failures), reason=reason)


def _retire(refinement: Refinement, stats: Dict[str, object]) -> Counter:
    entry = stats["skeleton_log"][refinement.rank - 1]
    entry["effort"], entry["steps_reached"] = refinement.effort, f"{refinement.deepest}/{len(refinement.steps)}"
    weight = refinement.sampler.promise.weight(refinement.groundings())
    if weight < 1.0:  # learned samplers held it back (promise.py)
        entry["weight"] = round(weight, 3)
    stats["executions"] += refinement.executions
    stats["refined"] += refinement.executions > 0
    stats["rejected"] += refinement.rejected
    return refinement.failures


def _result(status: str, refinement: Refinement, values, start: float, stats, failures) -> PlanResult:
    _retire(refinement, stats)
    return PlanResult(status, refinement.steps, values, time.perf_counter() - start, _finish_stats(stats, failures))


def _finish_stats(stats: Dict[str, object], failures: Counter) -> Dict[str, object]:
    out = dict(stats)
    out["samples"] = dict(sorted(stats["samples"].items()))
    # Per sampler: proposals verified (generic and learned apart) and values in simulated steps.
    out["proposals"] = stats["proposals"]()
    out["simulated"] = dict(sorted(stats["simulated"].items()))
    scores = [t for times in stats["score_ms"] for t in times]
    out["score_ms"] = {"batches": len(scores), "median": round(1000 * float(np.median(scores)), 2) if scores else None}
    out["trust"] = stats["trust"]()
    out["symbolic_s"] = round(stats["symbolic_s"], 3)
    out["continuous_s"] = round(stats["continuous_s"], 3)
    out["failures"] = dict(failures.most_common(8))
    return out


def _initial_mismatch(task: StripsTask, world: World) -> Optional[str]:
    """The problem's :init and the simulated scene should agree on the contact graph."""
    observed = observed_state(task, world)
    diff = (observed ^ task.init) & contact_mask(task)
    if not diff:
        return None
    facts = [task.facts[i] for i in range(len(task.facts)) if diff >> i & 1]
    shown = ", ".join("(" + " ".join(f) + ")" + (" holds in the scene" if observed >> task.fact_ids[f] & 1
                                                  else " is not true in the scene") for f in facts[:4])
    return f"the scene and :init disagree: {shown}"
