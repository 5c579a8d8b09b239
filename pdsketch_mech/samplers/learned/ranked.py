"""A mechanism's learned samplers at planning time: rank what a generic sampler draws.

For a mechanism step whose parameter has a classifier, the step's stream takes a batch of
`learned_batch` proposals from its generic sampler (a checkpoint of values only: a pool of
`learned_pool` verified values, RankedSampler says why), scores the batch in one forward
pass in the step's context (the mechanism's objects where they are now, the values its
earlier steps drew), and goes through it best first (walk.py). A share of the walk
(`learned_explore`) takes one at random from the rest instead, and a rest far below the best
is topped up with a fresh batch first. (Names in backquotes are fields of the sampler's
`SamplerBudget`, ../budget.py.) The ranking reorders, it never removes: a visit verifies the
batch until its budget ends, and the next visit draws new proposals, so the planner stays as
complete as with the generic sampler.
A proposer that runs dry before the batch is full is called again (`learned_refills`): a
batch of the two contacts one call finds leaves the classifier nothing to choose. A visit
still verifies no more proposals than that first call found, as the generic draw would: the
refills widen the choice, they do not make a visit that cannot succeed cost more.

A batch is small on purpose. The best of many proposals by a classifier's score is the one
it overrates most (the optimizer's curse), all the more on a shape it never saw
(results/HISTORY.md has the batch sizes tried).

How often the walk explores is not fixed: each pick's outcome (its proposal verified, its
step simulated as the skeleton expects and the mechanism's next step after it, or not) is
counted per mechanism grounding, and evidence that random picks do better than the learned
ones raises the chance (trust.py): a classifier wrong about a shape it never saw is walked
in the generic order instead.

A classifier is not asked where it would extrapolate: when a fixed object it reads (a slope,
a ledge: the layout) stands where its training never had one (x or y more than
`learned_extrapolation_z` standard deviations, at least MIN_SPREAD each, from the mean of its
training inputs), the step draws from the generic sampler as it is. A fixed object's place varies
only with the task distribution's layout noise, so a classifier cannot have learnt how
values relate to it anywhere else; a movable object was seen wherever the mechanism's steps
and the task's starts put it, and other shapes and sizes where training had its objects are
what the held-out objects are (there the classifiers help). A mechanism learnt on its own
task distribution meets other layouts in a composition (Slope-and-Blocker's slope stands
elsewhere in Hook-then-Place-on-Slope), and there its ranking is worse than none. Movable
objects are not limited: a composition puts them far from self-play's starts where the
ranking still helps (results/HISTORY.md, "moved from code comments").
"""
from __future__ import annotations

import os
import time
from itertools import islice
from typing import TYPE_CHECKING, Any, Callable, Dict, Iterable, Iterator, List, Optional, Tuple

import numpy as np

from ...util.disk_cache import content_key, load_arrays, store_arrays
from ..budget import SamplerBudget
from ..interface import SampleRequest, Sampler
from .checkpoint import context_count, load_numpy
from .context import context_objects
from .encoding import encode_as, encode_proposal, pose_array
from .forward import NumpyClassifiers
from .shapes import cloud_key, size_features, unit_cloud
from .specs import width
from .trust import Trust
from .walk import walk

if TYPE_CHECKING:
    from ...lang.nodes import Mechanism
    from ...world.world import World

# Metres: the least standard deviation of a fixed object's training positions assumed (a
# table never moved has none). Not a budget (SamplerBudget holds those): it spends no work
# and trades none, it says how precisely any layout is reproduced, a fact of the world like
# the samplers' geometry; how far out a classifier is still trusted is
# `learned_extrapolation_z`'s to say.
MIN_SPREAD = 0.01


class LearnedMechanism:
    """One mechanism's classifiers, scoring proposals in a step's context (numpy: forward.py)."""

    def __init__(self, model: NumpyClassifiers, meta: Dict[str, Any], digest: Optional[str] = None):
        self.model, self.meta = model, meta
        self.digest = digest   # the weights file's sha256: names its embeddings in the disk cache
        # Stats: each batch's scoring (encoding the proposals and the forward pass), and apart
        # from it, embedding a shape the plan had not scored before (its point cloud and the
        # PointNet++ encoder, ~3 ms a shape and classifier; read from the disk cache, ~0.2 ms).
        self.score_seconds: List[float] = []
        self.shape_seconds: List[float] = []
        self._shapes: Dict[tuple, np.ndarray] = {}  # (variable, urdf) -> the shape's embedding
        # Bodies nearest the mechanism's objects that self-play recorded with them (context.py).
        self.context = context_count(meta)
        self._context: Dict[Tuple[str, ...], Tuple[str, ...]] = {}   # grounding -> its objects

    def __contains__(self, variable: object) -> bool:
        return variable in self.model

    def ranks_proposals(self, variable: str) -> bool:
        """Whether the classifier was trained on proposals (else on verified values only)."""
        return self.model.classifier(variable).spec.outputs > 1

    def score(self, world: "World", request: SampleRequest, variable: str, proposals: List[object]) -> np.ndarray:
        """The classifier's score for each proposal, higher first (`ParamClassifier.log_score`;
        the median of the others where a proposal has no encoding). The context is the step's:
        the mechanism's objects where they are now and the values its earlier steps drew."""
        started, embedded = time.perf_counter(), len(self.shape_seconds)
        classifier = self.model.classifier(variable)
        numbers = [encode_proposal(world, p) for p in proposals]
        known = [i for i, v in enumerate(numbers) if v is not None]
        out = np.zeros(len(proposals))
        if known:
            objects = self.objects(world, request)
            bodies = [world.bodies[o] for o in objects]
            # First: a new shape's cloud, read or drawn with its half-extents (size_features),
            # falls in the embedding's time, not the batch's.
            shapes = self._shape_vectors(world, request, variable)
            by_variable = {request.step.role(k): v for k, v in request.parents.items()}
            parents = [by_variable.get(variable) for variable, _ in classifier.spec.parents]
            out[known] = classifier.log_score(
                np.nan_to_num(np.stack([numbers[i] for i in known])),
                [np.nan_to_num(encode_as(world, value, kind)) if value is not None else np.zeros(width(kind))
                 for value, (_, kind) in zip(parents, classifier.spec.parents)],
                np.array([float(value is not None) for value in parents]),
                np.array([size_features(b.urdf, b.scale) for b in bodies]),
                np.array([pose_array(world.pose(o)) for o in objects]),
                shapes)
            out[[i for i in range(len(proposals)) if numbers[i] is None]] = np.median(out[known])
        # Shapes embedded for the first time during this call are timed apart (shape_seconds).
        self.score_seconds.append(time.perf_counter() - started - sum(self.shape_seconds[embedded:]))
        return out

    def extrapolates(self, world: "World", request: SampleRequest, variable: str,
                     budget: SamplerBudget = SamplerBudget()) -> Optional[str]:
        """The first fixed object the classifier of `variable` reads that stands where its
        training never had one (x or y more than `budget.learned_extrapolation_z` standard
        deviations, at least MIN_SPREAD, from the training mean), or None."""
        classifier = self.model.classifier(variable)
        for slot, name in enumerate(self.objects(world, request)):
            if not world.bodies[name].fixed:
                continue
            mean, std = classifier.position_statistics(slot)
            z = np.abs((np.asarray(world.pose(name)[0][:2]) - mean) / np.maximum(std, MIN_SPREAD))
            if float(z.max()) > budget.learned_extrapolation_z:
                return name
        return None

    def objects(self, world: "World", request: SampleRequest) -> Tuple[str, ...]:
        """The objects the classifiers see: the mechanism's, then (for a checkpoint trained with
        context) the bodies nearest them when the plan first scored the grounding, as
        self-play chose them at the start of its episode."""
        grounding = tuple(request.step.mechanism_args)
        if grounding not in self._context:
            self._context[grounding] = grounding + tuple(context_objects(world, grounding, self.context))
        return self._context[grounding]

    def _shape_vectors(self, world: "World", request: SampleRequest, variable: str) -> np.ndarray:
        """The mechanism objects' shape embeddings, each shape's computed once (its time
        appended to `shape_seconds`)."""
        rows = []
        for name in self.objects(world, request):
            urdf = world.bodies[name].urdf
            key = (variable, urdf)
            if key not in self._shapes:
                started = time.perf_counter()
                self._shapes[key] = self._embedding(variable, urdf)
                self.shape_seconds.append(time.perf_counter() - started)
            rows.append(self._shapes[key])
        return np.stack(rows)


    def _embedding(self, variable: str, urdf: str) -> np.ndarray:
        """The classifier's embedding of the asset's shape, kept on disk under the weights'
        and the cloud's names (~3 ms a shape and classifier, in every plan otherwise)."""
        classifier = self.model.classifier(variable)
        if self.digest is None:
            return classifier.shape_vector(unit_cloud(urdf))
        name = os.path.join("embeddings", content_key([self.digest, variable, cloud_key(urdf)]) + ".npz")
        entry = load_arrays(name)
        if entry is not None and "embedding" in entry and entry["embedding"].ndim == 1:
            return entry["embedding"]
        embedding = classifier.shape_vector(unit_cloud(urdf))
        store_arrays(name, embedding=embedding)
        return embedding


class RankedSampler(Sampler):
    """A generic sampler whose values are yielded in the order a classifier ranks them.

    Two ways, by what the classifier was trained on. A classifier of proposals (self-play
    logs the proposals that fail verification too) scores `learned_batch` raw proposals by
    the probability that they verify and are used, and they are verified best first: fewer
    verified and fewer simulated. A classifier of values only (checkpoints of schema /1)
    has never seen an unreachable grasp and may rank one first: grasps, contacts and
    placements then verify proposals in the generic order until `learned_pool` values are
    found and yield the pool best first; a push's distance, which nearly always verifies, is
    ranked as a proposal either way. `budget` (a SamplerBudget) holds these sizes; how many
    proposals a visit verifies is the generic sampler's."""

    def __init__(self, generic: Sampler, learned: LearnedMechanism, variable: str, pool: Optional[int] = None,
                 budget: SamplerBudget = SamplerBudget()):
        self.generic, self.learned, self.variable = generic, learned, variable
        self.sampler_budget = budget
        self.budget = generic.budget   # proposals verified per visit: the generic sampler's
        if pool is None:
            classifier = learned.model.classifier(variable)
            pool = 0 if classifier.spec.kind == "push" or learned.ranks_proposals(variable) else budget.learned_pool
        self.pool = pool  # 0: rank proposals
        self.trust: Dict[Tuple[str, ...], Trust] = {}   # per mechanism grounding
        # Told of every scored batch: (the request, the scores), e.g. planner/promise.py.
        self.on_scores: Optional[Callable[[SampleRequest, np.ndarray], None]] = None
        self._pending: Dict[int, Tuple[object, Trust, bool]] = {}  # id(value) -> (value, its trust, explored)
        # Visits drawn in the generic order, per (grounding, the fixed object out of place).
        self.extrapolated: Dict[Tuple[Tuple[str, ...], str], int] = {}

    def trust_for(self, request: SampleRequest) -> Trust:
        """The plan's record of learned against random picks for the step's grounding."""
        return self.trust.setdefault(tuple(request.step.mechanism_args), Trust(self.sampler_budget.learned_explore))

    def outcome(self, value: object, ok: bool) -> None:
        """The step `value` was drawn for simulated as the skeleton expects (`ok`) or not;
        counted once per value, and only for values this sampler yielded from a walk."""
        # The entry holds its value, so no other live object can have the id it is keyed by.
        entry = self._pending.pop(id(value), None)
        if entry is not None:
            entry[1].record(entry[2], ok)

    def _yielded(self, value: object, trust: Trust, explored: bool) -> object:
        # Most values are simulated at once; those whose visit ended first never are, so
        # the oldest are forgotten beyond a bound.
        if len(self._pending) >= self.sampler_budget.learned_pending:
            del self._pending[next(iter(self._pending))]
        self._pending[id(value)] = (value, trust, explored)
        return value

    def draw(self, world: "World", request: SampleRequest, rng: np.random.Generator,
             budget: Optional[int] = None) -> Iterator[object]:
        outside = self.learned.extrapolates(world, request, self.variable, self.sampler_budget)
        if outside is not None:
            key = (tuple(request.step.mechanism_args), outside)
            self.extrapolated[key] = self.extrapolated.get(key, 0) + 1
            yield from self.generic.draw(world, request, rng, budget)
            return
        if not self.pool:
            yield from self._draw_proposals(world, request, rng, budget)
            return
        limit = self.budget if budget is None else budget
        proposals = self.generic.propose(world, request, rng, limit)
        examined = 0
        while examined < limit and time.perf_counter() <= request.deadline:
            pool = []
            for candidate in proposals:
                if examined >= limit or time.perf_counter() > request.deadline:
                    break
                examined += 1
                self.examined += 1
                value = self.generic.verify(world, request, candidate, rng)
                request.verified(candidate, value)
                if value is not None:
                    pool.append(value)
                    if len(pool) >= self.pool:
                        break
            else:
                limit = examined  # the proposals ran out: this pool is the last
            if not pool:
                return
            scores = self._scored(world, request, pool)
            trust = self.trust_for(request)
            for index, explored in walk(scores, rng, trust.explore_chance, budget=self.sampler_budget):
                yield self._yielded(pool[index], trust, explored)

    def probe(self, world: "World", request: SampleRequest, rng: np.random.Generator) -> bool:
        """Score one batch of proposals, verifying none, for `on_scores` (the planner's view of
        the grounding, planner/promise.py). False where the classifier is not asked (a pool of
        verified values, or a fixed object out of its training's place) or nothing is proposed."""
        if self.pool or self.learned.extrapolates(world, request, self.variable, self.sampler_budget) is not None:
            return False
        # Every refill is tried: a thin spoon lying flat may give a call no grasp at all.
        size = self.sampler_budget.learned_batch
        batch = list(islice(self._proposals(world, request, rng, max(self.budget, size), [], until_dry=False), size))
        if batch:
            self._scored(world, request, batch)
        return bool(batch)

    def _scored(self, world: "World", request: SampleRequest, proposals: List[object]) -> np.ndarray:
        scores = self.learned.score(world, request, self.variable, proposals)
        if self.on_scores is not None:
            self.on_scores(request, scores)
        return scores

    def propose(self, world, request, rng, budget):
        return self.generic.propose(world, request, rng, budget)

    def verify(self, world, request, candidate, rng):
        return self.generic.verify(world, request, candidate, rng)

    def _draw_proposals(self, world: "World", request: SampleRequest, rng: np.random.Generator,
                        budget: Optional[int] = None) -> Iterator[object]:
        limit = self.budget if budget is None else budget  # proposals verified, as the generic draw
        # A batch is `learned_batch` proposals even when few are verified (a push verifies one
        # distance per visit, out of a batch proposed and ranked).
        size = self.sampler_budget.learned_batch
        first: List[int] = []   # how many the proposer's first call found, once it is known

        def done() -> bool:
            # A visit verifies no more than the generic draw would (what one call proposes):
            # refills widen the choice, not the work of a visit that cannot succeed (a grasp
            # of a plate still lying flat).
            return examined >= min(limit, first[0] if first else limit) or time.perf_counter() > request.deadline

        proposals = self._proposals(world, request, rng, max(limit, size), first)
        examined = 0
        while not done():
            batch = list(islice(proposals, size))
            if not batch:
                return
            scores = self._scored(world, request, batch)
            trust = self.trust_for(request)

            def top_up() -> np.ndarray:
                # Only for a pick the visit will verify: drawing proposals moves the rng.
                fresh = [] if done() else list(islice(proposals, size))
                batch.extend(fresh)
                return self._scored(world, request, fresh) if fresh else np.zeros(0)

            for index, explored in walk(scores, rng, trust.explore_chance, top_up, self.sampler_budget):
                if done():
                    return
                examined += 1
                self.examined += 1
                value = self.generic.verify(world, request, batch[index], rng)
                request.verified(batch[index], value)
                if value is None:
                    trust.record(explored, False)
                else:
                    yield self._yielded(value, trust, explored)

    def _proposals(self, world: "World", request: SampleRequest, rng: np.random.Generator,
                   count: int, first: List[int], until_dry: bool = True) -> Iterator[object]:
        """The generic proposer's proposals, and when it runs dry, those of up to
        `learned_refills` more calls; a call that finds none ends them (`until_dry`). How many
        the first call found is appended to `first` when that call ends. A proposer examines a bounded number
        of candidates per call: the contact proposer's 60 points on the target give a held
        tool a median of 2 usable contacts, and a batch of 2 leaves the classifier nothing
        to choose (on a Hook test instance 1 in 5 of them pulls the box toward the robot,
        and only those pulls bring it within reach). Proposing is geometry, no IK:
        ~8 ms a call there."""
        for _ in range(1 + self.sampler_budget.learned_refills):
            found = 0
            for proposal in self.generic.propose(world, request, rng, count):
                found += 1
                yield proposal
            if not first:
                first.append(found)
            if (until_dry and not found) or time.perf_counter() > request.deadline:
                return


def checkpoint_path(mechanism: "Mechanism") -> str:
    """The file a mechanism's `:sampler` names, resolved beside the fragment that defines it."""
    return os.path.normpath(os.path.join(os.path.dirname(mechanism.loc.file), mechanism.sampler))


def load_learned(mechanisms: Iterable["Mechanism"]) -> Dict[str, LearnedMechanism]:
    """The learned samplers of the mechanisms that name a checkpoint (CheckpointError if one
    cannot be used: the planner must not fall back silently)."""
    out = {}
    for mechanism in mechanisms:
        if mechanism.sampler:
            model, meta = load_numpy(checkpoint_path(mechanism), mechanism, mechanism.loc.file)
            out[mechanism.name] = LearnedMechanism(model, meta, meta["weights_sha256"])
    return out
