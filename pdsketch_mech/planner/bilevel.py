"""The adaptive bilevel planner (the paper's Alg. 1 with PDDLStream's adaptive schedule):
skeletons from the FF-guided symbolic search (with optimistic stream placeholders), refined
by sampling and simulation.

One loop: the skeletons in view (the active ones and the next few from the search) are
scored by one score (schedule.py), the lowest gets the next slice of work (created first if
it is new), and what its refinement learns goes into one evidence store (evidence.py) that
every later score reads. Nothing is lost for good: a skeleton whose first step is believed
dead is set aside with the others that repeat that step, and all come back when the belief
is revisited. docs/planner.md maps it to Alg. 1 and to PDDLStream and argues completeness.
"""
from __future__ import annotations

import time
import zlib
from collections import Counter
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Dict, List, Mapping, Optional, Tuple

import numpy as np

from ..lang.loader import LoadedDomain
from ..lang.nodes import Problem
from ..operators.vocabulary import BASIS, Vocabulary, vocabulary_of
from ..samplers.anchored import MechanismAnchors
from ..symbolic.grounding import ground
from ..symbolic.optimistic import optimistic_problem
from ..world.world import World
from .bindings import StepSampler
from .budget import DEFAULT_BUDGET, SearchBudget
from .evidence import Evidence
from .execute import execute_plan, settle_start
from .macros import add_mechanism_macros
from .probes import GroundingProbes
from .refine import Refinement
from .run_stats import RunStats, initial_mismatch, unsolved_reason
from .schedule import lowest, score
from .serialize import plan_entries
from .side_by_side import SideBySide
from .skeleton import Skeleton, Step
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


def prepare_task(domain: LoadedDomain, problem: Problem, use_mechanisms: bool = True,
                 vocabulary: Vocabulary = BASIS):
    """Optimistic problem, grounded task (not relevance-pruned: effect-free pushes matter),
    and mechanisms as macro operators. Free motions are left out unless a mechanism lists
    them as steps: every operator plans its own approach, so on their own they enable
    nothing."""
    optimistic, placeholders = optimistic_problem(domain.domain, problem, domain.types)
    task = ground(domain.domain, optimistic, domain.types, prune_irrelevant=False)
    steps = {call.name for m in domain.domain.mechanisms for call in m.actions} if use_mechanisms else set()
    task.operators = [op for op in task.operators if op.name not in vocabulary.free_motions or op.name in steps]
    if use_mechanisms and domain.domain.mechanisms:
        add_mechanism_macros(task, domain.domain, domain.types, optimistic, vocabulary)
    return task, placeholders


def bilevel_plan(domain: LoadedDomain, problem: Problem, world: World, timeout: float = 600.0, seed: int = 0,
                 use_mechanisms: bool = True, validate: bool = True,
                 learned: Optional[Mapping[str, "LearnedMechanism"]] = None,
                 budget: SearchBudget = DEFAULT_BUDGET, vocabulary: Optional[Vocabulary] = None,
                 anchors: Optional[Mapping[str, MechanismAnchors]] = None) -> PlanResult:
    """Plan in `world` (a fresh world of `problem`'s scene; left as it was) within `timeout`
    seconds. With `validate`, a refined skeleton counts only once it has been re-executed
    in another fresh world, as `replay` does, and reached the goal there. `learned`: the
    mechanisms' learned samplers, by mechanism name; `anchors`: what their demonstrations
    did (samplers/anchored.py). `vocabulary`: the one the domain names unless given."""
    vocabulary = vocabulary or vocabulary_of(domain.domain)
    if not (use_mechanisms and domain.domain.mechanisms):
        return BilevelSearch(domain, problem, world, timeout, seed, False, validate, None, budget, vocabulary).run()
    # The contract: the basis operators' own search, and beside it the mechanisms' (side_by_side.py).
    plain = BilevelSearch(domain, problem, world, timeout, seed, False, validate, None, budget, vocabulary)
    mechanisms = BilevelSearch(domain, problem, world, timeout, seed, True, validate, learned, budget, vocabulary,
                               anchors, mechanisms_only=True, start=(plain.start, plain.initial, plain.warnings))
    return SideBySide(plain, mechanisms, budget).run()


class BilevelSearch:
    """One plan's search: the loop of the module docstring and the state it shares."""

    def __init__(self, domain: LoadedDomain, problem: Problem, world: World, timeout: float, seed: int,
                 use_mechanisms: bool, validate: bool, learned: Optional[Mapping[str, "LearnedMechanism"]],
                 budget: SearchBudget, vocabulary: Vocabulary, anchors: Optional[Mapping[str, MechanismAnchors]] = None,
                 mechanisms_only: bool = False, start: Optional[Tuple[float, object, List[str]]] = None):
        """`mechanisms_only`: skeletons that use a mechanism, none of basis steps alone (the
        search beside the basis operators' own: side_by_side.py). `start`: (clock start, the
        world's settled snapshot, its warnings) when another search has settled the world."""
        self.start = time.perf_counter() if start is None else start[0]
        self.deadline = self.start + timeout
        self.problem, self.world, self.seed, self.validate = problem, world, seed, validate
        self.budget, self.vocabulary = budget, vocabulary
        self.task, placeholders = prepare_task(domain, problem, use_mechanisms, vocabulary)
        counts: Counter = Counter()
        self.sampler = StepSampler({s.name: s for s in domain.domain.streams}, placeholders, counts,
                                   learned if use_mechanisms else None, budget=budget.samplers,
                                   anchors=anchors if use_mechanisms else None)
        self.sampler.deadline = self.deadline
        self.stats = RunStats(self.task, counts, self.start)
        if start is None:
            warnings = settle_start(world)
            self.initial = world.snapshot()
        else:
            self.initial, warnings = start[1], list(start[2])
            world.restore(self.initial)
        self.warnings = list(warnings)
        mismatch = initial_mismatch(self.task, world, vocabulary)
        self.stats.warn(warnings + ([mismatch] if mismatch else []))
        self.evidence = Evidence(self.task, self.sampler.promise, self.start, budget, self.sampler.own_samplers())
        self.supply = SkeletonSupply(self.task, self.evidence, self.deadline, budget, vocabulary,
                                     mechanisms_only=mechanisms_only)
        self.probes = GroundingProbes(self.task, self.sampler, world, self.initial, seed)
        self.active: Dict[int, Refinement] = {}
        self.work = 0   # units done by every refinement together: the evidence's clock
        self.solution: Optional[Tuple[Refinement, List[Dict[str, object]]]] = None

    def run(self) -> PlanResult:
        """Work on the lowest-scored skeleton until one is refined or the time is up."""
        sim_start = self.world.sim_steps
        try:
            while time.perf_counter() < self.deadline:
                outcome = self.step()
                if outcome is not False:
                    break
        finally:
            self.world.restore(self.initial)
        return self.result(self.world.sim_steps - sim_start)

    def step(self) -> Optional[bool]:
        """One slice of work on the skeleton the score puts first: True once a skeleton is
        refined, None when there is nothing to work on, False otherwise."""
        chosen = self._choose()
        if chosen is None:
            return None
        values = self._work_on(chosen)
        if values is None:
            return False
        self.solution = (chosen, values)
        return True

    def result(self, sim_steps: int) -> PlanResult:
        """The search's outcome: the plan `step` refined, or why there is none."""
        if self.solution is not None:
            return self._solved(*self.solution, sim_steps)
        for refinement in self.active.values():
            self.stats.retire(refinement, self.evidence)
        self.stats.final(self.supply, self.evidence, sim_steps)
        elapsed = time.perf_counter() - self.start
        reason = unsolved_reason(time.perf_counter() >= self.deadline, elapsed, self.stats.created)
        return PlanResult("unsolved", time_s=elapsed, reason=reason,
                          stats=self.stats.document(self.sampler, self.evidence))

    def _choose(self) -> Optional[Refinement]:
        """The refinement the score puts first, created if it is an upcoming skeleton."""
        window = self.supply.upcoming()
        # Nothing is being refined and every skeleton left repeats a step believed dead: the
        # work, the revisits' clock, would stand still, so the revisit due first comes now.
        while not self.active and all(self.evidence.blocks(s.pristine) for s in window) \
                and self.evidence.revive_earliest():
            window = self.supply.upcoming()
        self.sampler.promise.register(g for skeleton in window for g in skeleton.groundings())
        if self.sampler.learned:
            self.probes.probe(window)
            self.stats.probes = self.probes.count
        # An upcoming skeleton competes as the next rank; among them, the search's order decides ties.
        rank, units, evidence = self.supply.taken + 1, self.budget.slice, self.evidence
        chosen = lowest([(score(r.rank, r.effort, evidence.estimate(r.skeleton, r.number), units), (r.rank,), r)
                         for r in self.active.values()]
                        + [(score(rank, 0, evidence.estimate(s), units), (rank, s.order, s.number), s) for s in window])
        if not isinstance(chosen, Skeleton):
            return chosen
        self.supply.take(chosen)
        self.stats.created_skeleton(chosen, rank, window, evidence)
        # Each skeleton draws from its own generator, seeded by the plan's seed and its
        # labels: what one skeleton draws does not depend on which others came first.
        rng = np.random.default_rng([self.seed, zlib.crc32(chosen.label(self.task).encode())])
        refinement = Refinement(chosen, self.initial, self.world, self.task, self.sampler, rng,
                                self._in_fresh_world if self.validate else None, evidence, rank,
                                step_failures=self.stats.step_failures, budget=self.budget, vocabulary=self.vocabulary)
        self.active[chosen.number] = refinement
        return refinement

    def _work_on(self, refinement: Refinement) -> Optional[List[Dict[str, object]]]:
        """One slice of work; then set aside what the evidence now says waits."""
        deaths, effort = self.evidence.deaths, refinement.effort
        t0 = time.perf_counter()
        values = refinement.run(self.deadline, self.budget.slice)
        self.stats.continuous_s += time.perf_counter() - t0
        self.work += refinement.effort - effort
        self.evidence.advance(self.work)
        if values is not None:
            return values
        if refinement.exhausted:   # its first step is believed dead, or an empty plan the scene refutes
            self._set_aside(refinement, defer=bool(refinement.steps))
        if self.evidence.deaths > deaths:   # skeletons that repeat the dead step wait for the others
            for other in [r for r in self.active.values() if self.evidence.blocks(r.pristine)]:
                self._set_aside(other, defer=True)
        return None

    def _set_aside(self, refinement: Refinement, defer: bool) -> None:
        """Retire a refinement; `defer`: its skeleton comes back when its dead step is revisited."""
        del self.active[refinement.number]
        self.stats.retire(refinement, self.evidence)
        self.stats.pruned += 1
        if defer:
            self.supply.defer(refinement.skeleton)

    def _in_fresh_world(self, steps: List[Step], values: List[Dict[str, object]]) -> Optional[str]:
        result = execute_plan(self.task, self.problem, plan_entries(steps, values), vocabulary=self.vocabulary)
        return None if result.goal_reached else f"in a fresh world, {result.message}"

    def _solved(self, refinement: Refinement, values, sim_steps: int) -> PlanResult:
        del self.active[refinement.number]
        for other in self.active.values():
            self.stats.retire(other, self.evidence)
        self.stats.retire(refinement, self.evidence)
        self.stats.final(self.supply, self.evidence, sim_steps)
        return PlanResult("solved", refinement.steps, values, time.perf_counter() - self.start,
                          self.stats.document(self.sampler, self.evidence))
