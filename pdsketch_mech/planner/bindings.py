"""Streams -> samplers, and the joint values of a step's placeholders.

A step such as `(grasp box table #grasp3 #traj4)` gets its placeholder values from the
streams that created them (`sample-grasp` for #grasp3, `plan-grasp-motion` for #traj4),
sampled in dependency order in the world as it is before the step. Each stream's sampler is
the one its `:sampler` names (samplers/registry.py), told the step's context: the operator,
the mechanism and the step's index in it, the objects' poses and the parent values. A
mechanism with learned samplers (samplers/learned/) ranks the proposals of the streams whose
variables have a classifier; the other streams keep the generic order.
"""
from __future__ import annotations

import time
from collections import Counter, defaultdict
from typing import TYPE_CHECKING, Callable, Dict, FrozenSet, Iterator, List, Mapping, Optional, Tuple

import numpy as np

from ..lang.nodes import Stream
from ..samplers.anchored import AnchoredSampler, MechanismAnchors
from ..samplers.budget import SamplerBudget
from ..samplers.interface import Sampler, SampleRequest, StepContext
from ..samplers.registry import GENERIC_SAMPLERS
from ..symbolic.optimistic import Placeholder, is_placeholder
from ..world.world import World
from .promise import GroundingPromise
from .skeleton import step_label

if TYPE_CHECKING:
    from ..samplers.learned.ranked import LearnedMechanism

# Told of every value a stream's sampler yields, with the request it answered (self-play
# records them); the world is in the state the value was drawn in.
SampleObserver = Callable[[SampleRequest, object], None]
# Told of every proposal a stream's sampler verifies: (request, proposal, value or None).
VerifyObserver = Callable[[SampleRequest, object, Optional[object]], None]


class StepSampler:
    """Joint samples of a step's placeholder arguments, drawn stream by stream."""

    def __init__(self, streams: Mapping[str, Stream], placeholders: Mapping[str, Placeholder], counts: Counter,
                 learned: Optional[Mapping[str, "LearnedMechanism"]] = None,
                 budget: SamplerBudget = SamplerBudget(), anchors: Optional[Mapping[str, MechanismAnchors]] = None):
        self.streams, self.placeholders, self.counts = streams, placeholders, counts
        self.learned = dict(learned or {})   # mechanism name -> its classifiers
        self.anchors = dict(anchors or {})   # mechanism name -> what its demonstration did
        self.budget = budget   # every sampler's search budgets (samplers/budget.py)
        self.simulated: Counter = Counter()  # sampler -> values of it in steps simulated
        # (step label, sampler, its objects where the scene began) -> [proposals verified, of
        # them feasible]: what a failing step lacked (failure_hint.py)
        self.verified: Dict[Tuple[str, str, bool], List[int]] = defaultdict(lambda: [0, 0])
        self.deadline = float("inf")  # (time.perf_counter()) no value is drawn after it
        unknown = sorted({s.sampler or s.name for s in streams.values()} - set(GENERIC_SAMPLERS))
        if unknown:
            known = ", ".join(sorted(GENERIC_SAMPLERS))
            raise ValueError(f"no sampler named {', '.join(unknown)}; known: {known}")
        self.samplers: Dict[str, Sampler] = {s.name: GENERIC_SAMPLERS[s.sampler or s.name](budget)
                                             for s in streams.values()}
        self.observers: List[SampleObserver] = []
        self.verify_observers: List[VerifyObserver] = []
        self._ranked: Dict[Tuple[str, str, str], Sampler] = {}
        self._anchored_samplers: Dict[Tuple[str, str, str], Sampler] = {}
        self.promise = GroundingPromise()   # what the learned samplers think of each grounding

    def own_samplers(self) -> FrozenSet[str]:
        """The mechanisms whose steps propose values of their own (a demonstration's, anchored).
        Learned samplers only reorder the generic proposals: what runs dry for one runs dry
        for them, so they share the generic samplers' beliefs."""
        return frozenset(self.anchors)

    def sampler_for(self, stream: str, step: StepContext, placeholder: str) -> Sampler:
        """The stream's generic sampler; for a mechanism's step, its demonstrated value first
        where the mechanism has an anchor for the variable `placeholder` stands for, and the
        proposals ranked by a classifier where it has one."""
        learned = self.learned.get(step.mechanism) if step.mechanism else None
        variable = step.role(placeholder)
        anchored = self._anchored(stream, step.mechanism, variable)
        if learned is None or variable not in learned:
            return anchored or self.samplers[stream]
        key = (stream, step.mechanism, variable)
        if key not in self._ranked:
            from ..samplers.learned.ranked import RankedSampler
            ranked = RankedSampler(anchored or self.samplers[stream], learned, variable, budget=self.budget)
            ranked.on_scores = lambda request, scores: self.promise.observe(
                request.step.mechanism, request.step.mechanism_args, variable, float(np.max(scores)))
            self._ranked[key] = ranked
        return self._ranked[key]

    def _anchored(self, stream: str, mechanism: Optional[str], variable: Optional[str]) -> Optional[Sampler]:
        """The anchored sampler of a mechanism's variable (None: no anchor for it)."""
        anchors = self.anchors.get(mechanism) if mechanism else None
        anchor = anchors.for_sampler(variable, self.key(stream)) if anchors is not None else None
        if anchor is None:
            return None
        key = (stream, mechanism, variable)
        if key not in self._anchored_samplers:
            self._anchored_samplers[key] = AnchoredSampler(self.samplers[stream], anchor, self.budget)
        return self._anchored_samplers[key]

    def proposals(self) -> Dict[str, Dict[str, int]]:
        """Proposals verified per sampler name: generic, anchored (a demonstration's values
        first, unranked) and learned (ranked) apart."""
        out: Dict[str, Dict[str, int]] = {"generic": Counter(), "anchored": Counter(), "learned": Counter()}
        for stream, sampler in self.samplers.items():
            out["generic"][self.key(stream)] += sampler.examined
        for kind, samplers in (("anchored", self._anchored_samplers), ("learned", self._ranked)):
            for (stream, _, _), sampler in samplers.items():
                out[kind][self.key(stream)] += sampler.examined
        return {k: dict(sorted((n, c) for n, c in v.items() if c)) for k, v in out.items()}

    def key(self, stream: str) -> str:
        """The name statistics use for a stream's sampler."""
        return self.streams[stream].sampler or stream

    def note_simulated(self, values: Mapping[str, object]) -> None:
        """Count the values a simulated step used, per sampler."""
        for name in values:
            holder = self.placeholders.get(name)
            if holder is not None:
                self.simulated[self.key(holder.stream)] += 1

    def note_outcome(self, values: Mapping[str, object], ok: bool) -> None:
        """Tell the learned samplers whether the step their values were drawn for simulated
        as the skeleton expects (samplers/learned/trust.py)."""
        for sampler in self._ranked.values():
            for value in values.values():
                sampler.outcome(value, ok)

    def trust(self) -> Dict[str, Dict[str, object]]:
        """Per mechanism variable with a learned sampler: outcomes of learned and random picks
        (successes, failures), summed over groundings, the highest chance of a random pick
        any grounding reached, and the visits drawn in the generic order because the
        classifier would have extrapolated (samplers/learned/ranked.py)."""
        out: Dict[str, Dict[str, object]] = {}
        for (_, mechanism, variable), sampler in sorted(self._ranked.items()):
            if not sampler.trust and not sampler.extrapolated:
                continue
            row = out.setdefault(f"{mechanism} {variable}", {"learned": [0, 0], "random": [0, 0], "explore": 0.0})
            for record in sampler.trust.values():
                for arm, counts in (("learned", (record.learned_ok, record.learned_failed)),
                                    ("random", (record.random_ok, record.random_failed))):
                    row[arm] = [row[arm][0] + counts[0], row[arm][1] + counts[1]]
                row["explore"] = max(row["explore"], round(record.explore_chance(), 3))
            if sampler.extrapolated:
                row["extrapolated"] = row.get("extrapolated", 0) + sum(sampler.extrapolated.values())
        return out

    def extrapolation_warnings(self) -> List[str]:
        """One line per mechanism whose learned samplers stood aside because a fixed object
        was far from where their training had it (samplers/learned/ranked.py)."""
        visits: Dict[str, int] = Counter()
        objects: Dict[str, set] = {}
        for (_, mechanism, _), sampler in self._ranked.items():
            for (_, name), count in sampler.extrapolated.items():
                visits[mechanism] += count
                objects.setdefault(mechanism, set()).add(name)
        return [f"mechanism '{mechanism}': its learned samplers were not used on {visits[mechanism]} "
                f"visit{'' if visits[mechanism] == 1 else 's'} of its steps, "
                f"because {', '.join(sorted(objects[mechanism]))} stood far from where their training had it "
                "(the generic samplers drew instead; retrain on a task distribution that varies that)"
                for mechanism in sorted(visits)]

    def probe(self, world: World, step: StepContext, rng: np.random.Generator) -> bool:
        """Score one batch of proposals for the step's first parameter, if a classifier of
        proposals ranks it, verifying none: what the learned samplers think of the step's
        mechanism grounding (promise.py) is then known before its skeleton gets any work.
        True if a batch was scored."""
        needed = self._needed(step)
        if not needed or not step.mechanism or step.mechanism not in self.learned:
            return False
        holder = self.placeholders[needed[0]]
        if any(is_placeholder(v) for v in holder.inputs):
            return False
        ranked = self.sampler_for(holder.stream, step, needed[0])
        if not hasattr(ranked, "probe"):
            return False
        return ranked.probe(world, self._request(holder, step, self._poses(world, step), {}), rng)

    def _needed(self, step: StepContext) -> List[str]:
        """The step's placeholders in the order they are sampled (dependencies first)."""
        return sorted({a for a in step.args if is_placeholder(a)}, key=lambda a: (self.placeholders[a].level, a))

    @staticmethod
    def _poses(world: World, step: StepContext) -> Dict[str, object]:
        """Where the step's objects are now."""
        return {a: world.pose(a) for a in step.args if not is_placeholder(a) and a in world.bodies}

    def _request(self, holder: Placeholder, step: StepContext, poses, values: Dict[str, object],
                 parents: Optional[Mapping[str, object]] = None, on_verified=None) -> SampleRequest:
        """The request for `holder`'s stream: its placeholder inputs read from `values` (this
        step's values so far), its parents those and the earlier steps' `parents`."""
        stream = self.streams[holder.stream]
        return SampleRequest(stream.name, tuple(values.get(v, v) for v in holder.inputs),
                             tuple(q.name for q in stream.inputs), step, poses, {**(parents or {}), **values},
                             self.deadline, on_verified)

    def samples(self, world: World, step: StepContext, rng: np.random.Generator,
                parents: Optional[Mapping[str, object]] = None, per_value: int = 1) -> Iterator[Dict[str, object]]:
        """Assignments {placeholder: value} for the placeholders among the step's arguments;
        `parents` are values earlier steps of the step's mechanism drew."""
        yield from self._assign(world, step, dict(parents or {}), self._poses(world, step), self._needed(step), {},
                                rng, per_value, root=True)

    def _assign(self, world, step: StepContext, parents: Dict[str, object], poses, needed: List[str],
                values: Dict[str, object], rng, per_value: int, root: bool):
        """Values for `needed` in order; a value that depends on earlier ones (a trajectory
        for a grasp) is drawn at most `per_value` times per combination of those."""
        if not needed:
            yield dict(values)
            return
        name, rest = needed[0], needed[1:]
        holder = self.placeholders[name]
        stream = self.streams[holder.stream]
        key = self.key(stream.name)
        tally = self.verified[(step_label(step.operator, step.args), key, step.at_start)]

        def verified(candidate, value):
            tally[0] += 1
            tally[1] += value is not None
            for observe in self.verify_observers:
                observe(request, candidate, value)
        request = self._request(holder, step, poses, values, parents, verified)
        drawn = 0
        for value in self.sampler_for(stream.name, step, name).draw(world, request, rng):
            if time.perf_counter() > self.deadline:
                break
            self.counts[key] += 1
            for observe in self.observers:
                observe(request, value)
            values[name] = value
            yield from self._assign(world, step, parents, poses, rest, values, rng, per_value, root=False)
            drawn += 1
            if not root and drawn >= per_value:
                break
        values.pop(name, None)
