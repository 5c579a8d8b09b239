"""The adaptive bilevel planner (the paper's Alg. 1 with PDDLStream's adaptive schedule):
skeletons from the FF-guided symbolic search (with optimistic stream placeholders), refined
by sampling and simulation.

One loop: the skeletons in view (the active ones and the next few from the search) are
scored by one score (schedule.py), the lowest gets the next slice of work (created first if
it is new), and what its refinement learns goes into one evidence store (evidence.py) that
every later score reads. docs/planner.md maps it to Alg. 1 and to PDDLStream.
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
from .evidence import Evidence
from .execute import contact_mask, execute_plan, observed_state, settle_start
from .failure_hint import failed_steps
from .macros import add_mechanism_macros
from .probes import GroundingProbes
from .refine import Refinement
from .schedule import SLICE, lowest, score
from .serialize import plan_entries
from .skeleton import Skeleton, Step, step_label
from .supply import SkeletonSupply

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
                                "symbolic_s": 0.0, "continuous_s": 0.0}
    sim_start = world.sim_steps
    mismatch = _initial_mismatch(task, world)
    if mismatch:
        warnings.append(mismatch)
    if warnings:
        stats["warnings"] = warnings

    def in_fresh_world(steps: List[Step], values: List[Dict[str, object]]) -> Optional[str]:
        result = execute_plan(task, problem, plan_entries(steps, values))
        return None if result.goal_reached else f"in a fresh world, {result.message}"
    evidence = Evidence(task, sampler.promise, start)
    supply = SkeletonSupply(task, evidence, deadline, max_skeletons)
    probes = GroundingProbes(task, sampler, world, initial, seed)
    active: Dict[int, Refinement] = {}
    stats["skeleton_log"] = []
    failures: Counter = Counter()
    step_failures: Counter = Counter()   # (step, why) over every skeleton, for the failure hint
    try:
        while time.perf_counter() < deadline:
            window = supply.upcoming()
            sampler.promise.register(g for skeleton in window for g in skeleton.groundings())
            if sampler.learned:
                probes.probe(window)
                stats["probes"] = probes.count
            # An upcoming skeleton competes as the next rank; among them, the search's order decides ties.
            rank = supply.taken + 1
            chosen = lowest([(score(r.rank, r.effort, evidence.estimate(r.skeleton, r.number)), (r.rank,), r)
                             for r in active.values()]
                            + [(score(rank, 0, evidence.estimate(s)), (rank, s.order, s.number), s) for s in window])
            if chosen is None:
                break
            if isinstance(chosen, Skeleton):
                supply.take(chosen)
                _log_created(stats, chosen, rank, window, task, evidence, start)
                # Each skeleton draws from its own generator, seeded by the plan's seed and its
                # labels: what one skeleton draws does not depend on which others came first.
                rng = np.random.default_rng([seed, zlib.crc32(chosen.label(task).encode())])
                chosen = active[chosen.number] = Refinement(chosen, initial, world, task, sampler, rng,
                                                            in_fresh_world if validate else None, evidence, rank,
                                                            step_failures=step_failures)
            refinement, deaths = chosen, evidence.deaths
            t0 = time.perf_counter()
            values = refinement.run(deadline, SLICE)
            stats["continuous_s"] += time.perf_counter() - t0
            if values is not None:
                del active[refinement.number]
                for other in active.values():
                    failures += _retire(other, stats, evidence)
                _final_counts(stats, supply, evidence, world.sim_steps - sim_start)
                return _result("solved", refinement, values, start, stats, failures + refinement.failures, evidence,
                               step_failures)
            if refinement.exhausted:
                del active[refinement.number]
                stats["pruned"] += 1
                failures += _retire(refinement, stats, evidence)
            if evidence.deaths > deaths:  # skeletons that repeat the dead step wait for the others
                for number in [n for n, other in active.items() if evidence.blocks(other.pristine)]:
                    retired = active.pop(number)
                    failures += _retire(retired, stats, evidence)
                    supply.defer(retired.skeleton)
    finally:
        world.restore(initial)
    for refinement in active.values():
        failures += _retire(refinement, stats, evidence)
    _final_counts(stats, supply, evidence, world.sim_steps - sim_start)
    elapsed = time.perf_counter() - start
    if time.perf_counter() >= deadline:
        reason = f"timed out after {elapsed:.1f} s"
    elif stats["skeletons"] == 0:
        reason = "no plan exists: no sequence of operators reaches the goal symbolically"
    else:
        reason = f"no plan exists: none of the {stats['skeletons']} skeletons could be refined"
    return PlanResult("unsolved", time_s=elapsed, reason=reason,
                      stats=_finish_stats(stats, failures, sampler, step_failures, evidence))


def _log_created(stats: Dict[str, object], skeleton: Skeleton, rank: int, window: List[Skeleton],
                 task: StripsTask, evidence: Evidence, start: float) -> None:
    """The statistics' entry of a skeleton as it is created: when, what, and what the
    evidence said of it then."""
    entry: Dict[str, object] = {"rank": rank, "number": skeleton.number, "created_s": round(time.perf_counter() - start, 3),
                                "skeleton": skeleton.label(task)}
    if skeleton.source:
        entry["basis_only"] = True   # from the search over basis operators alone
    passed = [s for s in window if s.number < skeleton.number]
    if passed:
        entry["passed"] = len(passed)   # skeletons the search found first, left waiting
    detours = evidence.detours(skeleton.plan)
    if detours:
        entry["detours"] = detours
    stats["skeleton_log"].append(entry)


def _final_counts(stats: Dict[str, object], supply: SkeletonSupply, evidence: Evidence, sim_steps: int) -> None:
    stats.update(skeletons=supply.taken, deferred=supply.deferrals, sim_steps=sim_steps, dead_steps=evidence.labels())
    stats["symbolic_s"] += supply.search_s


def _retire(refinement: Refinement, stats: Dict[str, object], evidence: Evidence) -> Counter:
    """Close the skeleton's statistics entry (its latest: a deferred skeleton may come twice)."""
    entry = next(e for e in reversed(stats["skeleton_log"]) if e["number"] == refinement.number)
    entry["effort"], entry["steps_reached"] = refinement.effort, f"{refinement.deepest}/{len(refinement.steps)}"
    if refinement.unblocked:
        entry["unblocked"] = len(refinement.unblocked)
    if refinement.failures:  # where this skeleton's work went: which step failed, and why
        entry["failures"] = dict(refinement.failures.most_common(4))
    terms = {k: round(v, 2) for k, v in evidence.log_terms(refinement.skeleton, refinement.number).items() if v}
    if terms:  # what the evidence said of it last, as natural logs
        entry["estimate"] = terms
    stats["executions"] += refinement.executions
    stats["refined"] += refinement.executions > 0
    stats["rejected"] += refinement.rejected
    return refinement.failures


def _result(status: str, refinement: Refinement, values, start: float, stats, failures,
            evidence: Evidence, step_failures: Counter) -> PlanResult:
    _retire(refinement, stats, evidence)
    return PlanResult(status, refinement.steps, values, time.perf_counter() - start,
                      _finish_stats(stats, failures, refinement.sampler, step_failures, evidence))


def _finish_stats(stats: Dict[str, object], failures: Counter, sampler: StepSampler,
                  step_failures: Counter, evidence: Evidence) -> Dict[str, object]:
    """The statistics as the JSON document has them, with what the samplers recorded."""
    out = dict(stats)
    out["samples"] = dict(sorted(stats["samples"].items()))
    # Per sampler: proposals verified (generic and learned apart) and values in simulated steps.
    out["proposals"] = sampler.proposals()
    out["simulated"] = dict(sorted(sampler.simulated.items()))
    learned = sampler.learned.values()
    scores = [t for m in learned for t in m.score_seconds]
    out["score_ms"] = {"batches": len(scores), "median": round(1000 * float(np.median(scores)), 2) if scores else None,
                       "max": round(1000 * max(scores), 2) if scores else None}
    shapes = [t for m in learned for t in m.shape_seconds]
    out["shape_ms"] = {"encoded": len(shapes), "total": round(1000 * sum(shapes), 2)}
    out["trust"] = sampler.trust()
    warnings = list(stats.get("warnings", ())) + sampler.extrapolation_warnings()
    if warnings:
        out["warnings"] = warnings
    out["symbolic_s"] = round(stats["symbolic_s"], 3)
    out["continuous_s"] = round(stats["continuous_s"], 3)
    out["failures"] = dict(failures.most_common(8))
    out["failed_steps"] = failed_steps(step_failures, sampler.verified, [step_label(*key) for key in evidence.dead])
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
