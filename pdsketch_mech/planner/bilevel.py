"""The adaptive bilevel planner: skeletons from the FF-guided symbolic search (with
optimistic stream placeholders), refined by sampling and simulation.

Adaptive, in PDDLStream's sense: work is shared between refining the skeletons found so far
and taking new ones from the symbolic search (schedule.py; supply.py hands them out), so a
skeleton that needs many samples is not starved by the search for new ones, and a deep one
(a tool use 20 skeletons down) is reached within a bounded amount of work. Skeletons that
wander (detours.py), mechanism groundings the learned samplers doubt (promise.py; probed
before their skeletons are created, probes.py) and skeletons whose steps keep failing in
other skeletons (bottlenecks.py) get less of it.
"""
from __future__ import annotations

import time
import zlib
from collections import Counter
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Dict, List, Mapping, Optional

import numpy as np

from ..lang.loader import LoadedDomain
from ..lang.nodes import Problem
from ..symbolic.grounding import ground
from ..symbolic.optimistic import optimistic_problem
from ..symbolic.task import StripsTask
from ..world.world import World
from .bindings import StepSampler
from .bottlenecks import SharedOutcomes
from .execute import contact_mask, execute_plan, observed_state, settle_start
from .macros import add_mechanism_macros
from .pristine import PristineFailures
from .probes import GroundingProbes
from .refine import Refinement, Step, skeleton_groundings
from .schedule import SLICE, heaviest, next_turn
from .serialize import plan_entries
from .supply import SkeletonSupply
from .unblocked import UnblockedPrefixes

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
                                "shape_ms": [m.shape_seconds for m in (learned or {}).values()],
                                "trust": sampler.trust, "extrapolation_warnings": sampler.extrapolation_warnings}
    sim_start = world.sim_steps
    mismatch = _initial_mismatch(task, world)
    if mismatch:
        warnings.append(mismatch)
    if warnings:
        stats["warnings"] = warnings

    def in_fresh_world(steps: List[Step], values: List[Dict[str, object]]) -> Optional[str]:
        result = execute_plan(task, problem, plan_entries(steps, values))
        return None if result.goal_reached else f"in a fresh world, {result.message}"
    memo = PristineFailures(start=start)
    supply = SkeletonSupply(task, memo, deadline, max_skeletons)
    unblocked = UnblockedPrefixes()
    outcomes = SharedOutcomes(task.init, contact_mask(task))
    active: Dict[int, Refinement] = {}
    plans: Dict[int, List[int]] = {}
    created: List[Dict[str, object]] = []   # for the statistics: when each skeleton entered
    stats["skeleton_log"] = created
    failures: Counter = Counter()

    def weight(refinement: Refinement) -> float:
        return (sampler.promise.weight(refinement.groundings()) * supply.weight(plans[refinement.rank])
                * unblocked.weight(refinement.steps)
                * outcomes.weight(refinement.outcome_keys, refinement.rank))

    probes = GroundingProbes(task, sampler, world, initial, seed)

    try:
        while time.perf_counter() < deadline:
            window = supply.upcoming()
            if sampler.learned:
                probes.probe(window)
                stats["probes"] = probes.count
            # The first upcoming skeleton with the fewest unexplained detours, and the groundings
            # the learned samplers prefer, comes next (supply.py, promise.py).
            creation_weights = [supply.weight(plan) * sampler.promise.weight(skeleton_groundings(steps))
                                for plan, steps, _ in window]
            chosen = heaviest(creation_weights) if window else 0
            upcoming_weight = (creation_weights[chosen] * unblocked.weight(window[chosen][1])
                               * outcomes.weight(outcomes.keys(window[chosen][1])) if window else 1.0)
            turn = next_turn(((r.rank, r.effort, weight(r)) for r in active.values()),
                             supply.taken + 1 if window else None, upcoming_weight)
            if turn is None:
                break
            if turn not in active:
                plan, steps, keys = supply.take(chosen)
                label = " ".join(task.operators[o].label for o in plan)
                created.append({"rank": turn, "created_s": round(time.perf_counter() - start, 3), "skeleton": label})
                if chosen:
                    created[-1]["passed"] = chosen   # skeletons the search found first, left waiting
                detours = supply.detours(plan)
                if detours:
                    created[-1]["detours"] = detours
                # Each skeleton draws from its own generator, seeded by the plan's seed and its
                # labels: what one skeleton draws does not depend on which others came first
                # (or were deferred), so a change in the skeleton order does not reshuffle luck.
                skeleton_rng = np.random.default_rng([seed, zlib.crc32(label.encode())])
                active[turn] = Refinement(steps, initial, world, task, sampler, skeleton_rng,
                                          in_fresh_world if validate else None, rank=turn,
                                          pristine=keys, memo=memo, outcomes=outcomes)
                plans[turn] = plan
            refinement = active[turn]
            t0, deaths = time.perf_counter(), memo.deaths
            values = refinement.run(deadline, SLICE)
            stats["continuous_s"] += time.perf_counter() - t0
            unblocked.note(refinement.steps, refinement.unblocked)
            if values is not None:
                del active[turn]
                for other in active.values():
                    failures += _retire(other, stats)
                _final_counts(stats, supply, memo, world.sim_steps - sim_start)
                return _result("solved", refinement, values, start, stats, failures + refinement.failures)
            if refinement.exhausted:
                del active[turn]
                stats["pruned"] += 1
                failures += _retire(refinement, stats)
            if memo.deaths > deaths:  # skeletons created before that repeat the dead step wait
                for rank in [r for r, other in active.items() if memo.blocks(other.pristine)]:
                    retired = active.pop(rank)
                    failures += _retire(retired, stats)
                    supply.defer((plans[rank], list(retired.steps), list(retired.pristine)))
    finally:
        world.restore(initial)
    for refinement in active.values():
        failures += _retire(refinement, stats)
    _final_counts(stats, supply, memo, world.sim_steps - sim_start)
    elapsed = time.perf_counter() - start
    if time.perf_counter() >= deadline:
        reason = f"timed out after {elapsed:.1f} s"
    elif stats["skeletons"] == 0:
        reason = "no plan exists: no sequence of operators reaches the goal symbolically"
    else:
        reason = f"no plan exists: none of the {stats['skeletons']} skeletons could be refined"
    return PlanResult("unsolved", time_s=elapsed, stats=_finish_stats(stats, failures), reason=reason)


def _final_counts(stats: Dict[str, object], supply: SkeletonSupply, memo: PristineFailures, sim_steps: int) -> None:
    stats.update(skeletons=supply.taken, deferred=supply.deferrals, sim_steps=sim_steps, dead_steps=memo.labels())
    stats["symbolic_s"] += supply.search_s


def _retire(refinement: Refinement, stats: Dict[str, object]) -> Counter:
    entry = stats["skeleton_log"][refinement.rank - 1]
    entry["effort"], entry["steps_reached"] = refinement.effort, f"{refinement.deepest}/{len(refinement.steps)}"
    if refinement.unblocked:
        entry["unblocked"] = len(refinement.unblocked)
    if refinement.failures:  # where this skeleton's work went: which step failed, and why
        entry["failures"] = dict(refinement.failures.most_common(4))
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
    out["score_ms"] = {"batches": len(scores), "median": round(1000 * float(np.median(scores)), 2) if scores else None,
                       "max": round(1000 * max(scores), 2) if scores else None}
    shapes = [t for times in stats["shape_ms"] for t in times]
    out["shape_ms"] = {"encoded": len(shapes), "total": round(1000 * sum(shapes), 2)}
    out["trust"] = stats["trust"]()
    warnings = list(stats.get("warnings", ())) + out.pop("extrapolation_warnings")()
    if warnings:
        out["warnings"] = warnings
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
