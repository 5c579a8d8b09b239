"""A plan's statistics, as `--json` has them under `stats` (docs/planner.md, "Reading a
plan's statistics"): gathered as the search goes, written out once it ends."""
from __future__ import annotations

import time
from collections import Counter
from typing import TYPE_CHECKING, Dict, List, Optional

import numpy as np

from ..operators.vocabulary import BASIS, Vocabulary
from ..symbolic.task import StripsTask
from ..world.world import World
from .evidence import Evidence
from .execute import contact_mask, observed_state
from .failure_hint import failed_steps
from .skeleton import Skeleton, step_label

if TYPE_CHECKING:
    from .bindings import StepSampler
    from .refine import Refinement
    from .supply import SkeletonSupply


class RunStats:
    """What one plan's search did, for the statistics document."""

    def __init__(self, task: StripsTask, samples: Counter, start: float):
        self.task, self.samples, self.start = task, samples, start
        self.created = self.refined = self.pruned = self.executions = self.rejected = self.probes = 0
        self.continuous_s = 0.0
        self.warnings: List[str] = []
        self.log: List[Dict[str, object]] = []   # per skeleton created, in that order
        self.failures: Counter = Counter()
        self.step_failures: Counter = Counter()  # (step, why) over every skeleton, for the failure hint
        self.mechanism_skeletons: Counter = Counter()   # mechanism -> skeletons created that use it
        self.extra: Dict[str, object] = {}

    def warn(self, warnings: List[str]) -> None:
        self.warnings.extend(warnings)

    def created_skeleton(self, skeleton: Skeleton, rank: int, window: List[Skeleton], evidence: Evidence) -> None:
        """The statistics' entry of a skeleton as it is created: when, what, and what the
        evidence said of it then."""
        self.created += 1
        entry: Dict[str, object] = {"rank": rank, "number": skeleton.number,
                                    "created_s": round(time.perf_counter() - self.start, 3),
                                    "skeleton": skeleton.label(self.task)}
        passed = [s for s in window if s.number < skeleton.number]
        if passed:
            entry["passed"] = len(passed)   # skeletons the search found first, left waiting
        detours = evidence.detours(skeleton.plan)
        if detours:
            entry["detours"] = detours
        for mechanism in {g[0] for g, _ in skeleton.groundings()}:
            self.mechanism_skeletons[mechanism] += 1
        self.log.append(entry)

    def retire(self, refinement: "Refinement", evidence: Evidence) -> None:
        """Close the skeleton's statistics entry (its latest: a deferred skeleton may come twice)."""
        entry = next(e for e in reversed(self.log) if e["number"] == refinement.number)
        entry["effort"], entry["steps_reached"] = refinement.effort, f"{refinement.deepest}/{len(refinement.steps)}"
        if refinement.unblocked:
            entry["unblocked"] = len(refinement.unblocked)
        if refinement.failures:  # where this skeleton's work went: which step failed, and why
            entry["failures"] = dict(refinement.failures.most_common(4))
        terms = {k: round(v, 2) for k, v in evidence.log_terms(refinement.skeleton, refinement.number).items() if v}
        if terms:  # what the evidence said of it last, as natural logs
            entry["estimate"] = terms
        self.executions += refinement.executions
        self.refined += refinement.executions > 0
        self.rejected += refinement.rejected
        self.failures += refinement.failures

    def final(self, supply: "SkeletonSupply", evidence: Evidence, sim_steps: int) -> None:
        """The counts known once the search ends."""
        self.extra = {"deferred": supply.deferrals, "returned": supply.returned, "revived": evidence.revivals,
                      "sim_steps": sim_steps, "dead_steps": evidence.labels(), "symbolic_s": supply.search_s,
                      "work": evidence.work}

    def document(self, sampler: "StepSampler", evidence: Evidence) -> Dict[str, object]:
        """The statistics as the JSON document has them, with what the samplers recorded."""
        out: Dict[str, object] = {"skeletons": self.created, "refined": self.refined, "pruned": self.pruned,
                                  "operators": len(self.task.operators), "executions": self.executions,
                                  "rejected": self.rejected, **self.extra}
        out["samples"] = dict(sorted(self.samples.items()))
        if self.probes:
            out["probes"] = self.probes
        out["skeleton_log"] = self.log
        # Per sampler: proposals verified (generic and learned apart) and values in simulated steps.
        out["proposals"] = sampler.proposals()
        out["simulated"] = dict(sorted(sampler.simulated.items()))
        out.update(_learned_timing(sampler))
        out["trust"] = sampler.trust()
        warnings = self.warnings + sampler.extrapolation_warnings()
        if warnings:
            out["warnings"] = warnings
        out["symbolic_s"] = round(float(out.get("symbolic_s", 0.0)), 3)
        out["continuous_s"] = round(self.continuous_s, 3)
        out["failures"] = dict(self.failures.most_common(8))
        out["failed_steps"] = failed_steps(self.step_failures, sampler.verified,
                                           list(dict.fromkeys(step_label(name, objects)
                                                              for name, objects, _ in evidence.first_dead)))
        out["mechanisms"] = mechanism_summary(self.step_failures, self.mechanism_skeletons, self.created)
        return out


def mechanism_summary(step_failures: Counter, skeletons: Counter, created: int) -> Dict[str, Dict[str, int]]:
    """Per mechanism: the skeletons that used it (of `created`) and how often its certified
    facts failed, for the failure hint."""
    broken: Counter = Counter()
    for (label, why), count in step_failures.items():
        if "certified" in why:
            broken[label.split()[0]] += count
    return {name: {"skeletons": skeletons[name], "of": created, "certified_failed": broken[name]}
            for name in sorted(set(skeletons) | set(broken))}


def _learned_timing(sampler: "StepSampler") -> Dict[str, object]:
    """How long the learned samplers took to score batches and encode shapes."""
    learned = sampler.learned.values()
    scores = [t for m in learned for t in m.score_seconds]
    shapes = [t for m in learned for t in m.shape_seconds]
    return {"score_ms": {"batches": len(scores), "median": round(1000 * float(np.median(scores)), 2) if scores else None,
                         "max": round(1000 * max(scores), 2) if scores else None},
            "shape_ms": {"encoded": len(shapes), "total": round(1000 * sum(shapes), 2)}}


def initial_mismatch(task: StripsTask, world: World, vocabulary: Vocabulary = BASIS) -> Optional[str]:
    """The problem's :init and the simulated scene should agree on the contact graph."""
    observed = observed_state(task, world, vocabulary)
    diff = (observed ^ task.init) & contact_mask(task, vocabulary)
    if not diff:
        return None
    facts = [task.facts[i] for i in range(len(task.facts)) if diff >> i & 1]
    shown = ", ".join("(" + " ".join(f) + ")" + (" holds in the scene" if observed >> task.fact_ids[f] & 1
                                                  else " is not true in the scene") for f in facts[:4])
    fixed = [f for f in facts[:4] if len(f) == 3 and all(("fixed", x) in task.static_facts for x in f[1:])]
    why = (f" (what one fixed object stands on is never read, {' '.join('(' + ' '.join(f) + ')' for f in fixed)} "
           "included: leave such facts out of :init)") if fixed else ""
    return f"the scene and :init disagree: {shown}{why}"


def unsolved_reason(timed_out: bool, elapsed: float, created: int) -> str:
    """Why a search ended without a plan, as `plan` prints it."""
    if timed_out:
        return f"timed out after {elapsed:.1f} s"
    if created == 0:
        return "no plan exists: no sequence of operators reaches the goal symbolically"
    return f"no plan exists: none of the {created} skeletons could be refined"
