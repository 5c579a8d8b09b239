"""Self-play (paper Alg. 2): one episode of a mechanism on one instance of its task.

An episode draws a train-split instance of the task (a dev-split one for evaluation data;
distractors included), grounds the mechanism on a random choice of the objects present
whose precondition holds symbolically (the learner is not told which object plays which
role), fixes the skeleton to the mechanism's steps and runs the continuous search with the
generic samplers under a budget.

Which groundings the random choice ranges over is the config's `grounding`:
  "goal" (default): those whose :certified facts achieve a goal fact the instance lacks,
      the groundings the planner will ask the mechanism for on the task (the objects of
      roles the goal does not name, a tool or a blocker, are still a random choice among
      all present, distractors included); if none does, every consistent one;
  "any": every grounding whose precondition holds (the paper's RandomGrounding), even one
      whose :certified facts contradict each other (put the target on what it leaves),
      which no search can achieve: on Slope-and-Blocker 2 of 18 groundings serve the goal.
Every value drawn, and every proposal that failed verification, is logged
(selfplay_record.py) and labelled 1 if the successful plan used it, 0 otherwise.

Episode i draws everything from seeds derived from (base seed, i) alone, and its budget is
counted in work units (planner/schedule.py): the same seed gives the same data, whichever
process runs the episode and in whatever order. A seconds limit is a safety net only (an
episode that hits it is marked, since its data then depend on the machine's speed).
"""
from __future__ import annotations

import hashlib
import os
import re
import time
from collections import Counter
from dataclasses import dataclass
from functools import lru_cache
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..envs.generate import sample as sample_instance
from ..envs.task_names import resolve_task, task_names
from ..envs.tasks import TASKS
from ..lang.loader import LoadedDomain, load_domain
from ..lang.nodes import Mechanism, Problem
from ..lang.parser import parse_text
from ..planner.bilevel import prepare_task
from ..planner.bindings import StepSampler
from ..planner.execute import settle_start
from ..planner.refine import Refinement
from ..planner.skeleton import Skeleton, skeleton_steps
from ..symbolic.task import StripsTask
from ..world.build import build_world
from ..samplers.anchored import MechanismAnchors, anchors_beside, anchors_path
from ..samplers.learned.encoding import VALUE_WIDTH, mass_features
from ..samplers.learned.checkpoint import mechanism_hash
from ..samplers.learned.context import context_objects
from .selfplay_record import MAX_PARENTS, SampleLog

SLICE_UNITS = 16  # work units per call of the refinement: only how often the deadline is looked at


@dataclass(frozen=True)
class SelfPlayConfig:
    """Everything an episode depends on (picklable: sent to worker processes)."""

    mechanism: str          # the mechanism's name in the fragment
    fragment: str           # the fragment's path (it extends the basis domain)
    task: str               # the task distribution its instances come from (envs/tasks.py)
    seed: int = 0           # the base seed: episode i uses seeds derived from (seed, i)
    budget: int = 400       # work units per episode (samples drawn and simulated, samplers running dry)
    time_limit: float = 300.0  # seconds per episode, a safety net (hitting it is recorded)
    split: str = "train"    # "dev": data to evaluate classifiers on (`learn evaluate`), never to train
    grounding: str = "goal"  # which groundings an episode draws from: "goal" or "any" (see above)
    context: int = 0        # nearest other bodies recorded with the mechanism's objects (learned/context.py)

    def identity(self) -> Dict[str, object]:
        """What must match for two runs to write into the same folder: the options, and the
        mechanism's definition (the hash a checkpoint records), so that data played before
        an edit of the fragment are not trained on after it; and its demonstration's anchors,
        which the episodes draw from first (samplers/anchored.py), if it has them."""
        identity = {"mechanism": self.mechanism, "task": self.task, "seed": self.seed, "budget": self.budget,
                    "time_limit": self.time_limit, "split": self.split, "grounding": self.grounding,
                    "context": self.context,
                    "mechanism_hash": mechanism_hash(find_mechanism(_domain(self.fragment), self.mechanism))}
        path = anchors_path(self.fragment, self.mechanism)
        if os.path.isfile(path):
            with open(path, "rb") as handle:
                identity["anchors_sha256"] = hashlib.sha256(handle.read()).hexdigest()[:16]
        return identity


def episode_seeds(base: int, episode: int) -> Tuple[int, int]:
    """(instance seed, planner seed) of episode `episode`: a function of (base, episode) only."""
    instance, planner = np.random.SeedSequence([base, episode]).generate_state(2)
    return int(instance), int(planner)


@lru_cache(maxsize=4)
def _anchors(fragment: str, mechanism: str) -> Dict[str, MechanismAnchors]:
    anchors = anchors_beside(fragment, mechanism)   # read once per process, like the domain
    return {mechanism: anchors} if anchors is not None else {}


@lru_cache(maxsize=4)
def _domain(fragment: str) -> LoadedDomain:
    return load_domain([fragment])  # parsed once per process


def find_mechanism(loaded: LoadedDomain, name: str) -> Mechanism:
    for mechanism in loaded.domain.mechanisms:
        if mechanism.name == name:
            return mechanism
    names = ", ".join(m.name for m in loaded.domain.mechanisms) or "none"
    # The files are in load order, what a fragment :extends first: the fragment is the last.
    raise ValueError(f"no mechanism named {name} in {loaded.files[-1]} (it has: {names})")


DEMO_LINE = re.compile(r"^; Mechanism \S+: extracted from the demonstration (\S+)(?: \(([^,]+), instance)?", re.M)


def task_of(fragment: str, name: str) -> Optional[str]:
    """The task a mechanism's instances come from: the task of its name, else the task of
    the demonstration recording its fragment says it was extracted from (by the recording's
    name, or by the task's title the header gives beside it)."""
    known = task_names()
    if name in known:
        return name
    with open(fragment, encoding="utf-8") as handle:
        found = DEMO_LINE.search(handle.read())
    if found is None:
        return None
    if found.group(1) in known:
        return found.group(1)
    # A recording of a perturbed instance is named after it (com-train-5); the header names
    # its task by title too.
    titled = [task.name for task in TASKS.values() if task.title == found.group(2)]
    return titled[0] if titled else None


def groundings(task: StripsTask, mechanism: str) -> List[int]:
    """Macro operators of `mechanism` applicable in the initial state, in a fixed order."""
    out = [i for i, op in enumerate(task.operators)
           if op.name == mechanism and op.steps and op.pre & task.init == op.pre and not op.neg & task.init]
    return sorted(out, key=lambda i: task.operators[i].args)


def _promises(task: StripsTask, op_id: int) -> List[Tuple[int, int]]:
    """The alternatives of the macro's :certified facts that do not contradict themselves."""
    return [(true, false) for true, false in task.operators[op_id].certified if not true & false]


def _consistent(task: StripsTask, op_id: int) -> bool:
    """Some promise of the macro does not hold already."""
    return any(true & ~task.init or false & task.init for true, false in _promises(task, op_id))


def _serves_goal(task: StripsTask, op_id: int) -> bool:
    """Some promise of the macro adds a goal fact missing initially (and none the goal wants false)."""
    missing = task.goal & ~task.init
    return any(true & missing and not true & task.goal_neg for true, _ in _promises(task, op_id))


def episode_groundings(task: StripsTask, mechanism: str, policy: str) -> List[int]:
    """The groundings an episode chooses from under `policy` ("goal" or "any"), in a fixed order."""
    applicable = groundings(task, mechanism)
    if policy == "any":
        return applicable
    if policy != "goal":
        raise ValueError(f"unknown grounding policy {policy!r} (goal, any)")
    serving = [i for i in applicable if _serves_goal(task, i)]
    return serving or [i for i in applicable if _consistent(task, i)] or applicable


def run_episode(config: SelfPlayConfig, episode: int) -> Dict[str, np.ndarray]:
    """One self-play episode -> its arrays (see `episode_arrays`). Builds and closes its own world."""
    instance_seed, planner_seed = episode_seeds(config.seed, episode)
    rng = np.random.default_rng(planner_seed)
    loaded = _domain(config.fragment)
    mechanism = find_mechanism(loaded, config.mechanism)
    instance = sample_instance(resolve_task(config.task), config.split, instance_seed)
    problem = parse_text(instance.problem_text(), file=f"<{instance.name}>")
    assert isinstance(problem, Problem)
    task, placeholders = prepare_task(loaded, problem, use_mechanisms=True)
    # Only the mechanism's own macros: the skeleton is fixed, so basis operators are not needed.
    candidates = episode_groundings(task, mechanism.name, config.grounding)
    started = time.perf_counter()
    with build_world(problem, visual=False) as world:
        settle_start(world)
        start = world.snapshot()
        if not candidates:
            objects: Tuple[str, ...] = ()
            log = None
            values, units, timed_out = None, 0, False
        else:
            macro = task.operators[candidates[int(rng.integers(len(candidates)))]]
            objects = tuple(macro.args) + tuple(context_objects(world, macro.args, config.context))
            plan = [task.operators.index(macro)]
            steps = skeleton_steps(task, plan)
            log = SampleLog(world, objects, [[t.name for t in call.args] for call in mechanism.actions],
                            [q.name for q in mechanism.parameters], placeholders)
            # Generic samplers, after what the demonstration did where the mechanism has anchors:
            # a trick the user showed then succeeds often enough to learn from.
            sampler = StepSampler({s.name: s for s in loaded.domain.streams}, placeholders, Counter(),
                                  anchors=_anchors(config.fragment, mechanism.name))
            sampler.observers.append(log)
            sampler.verify_observers.append(log.verified)
            deadline = started + config.time_limit
            sampler.deadline = deadline
            skeleton = Skeleton(1, plan, steps, [None] * len(steps), [])
            search = Refinement(skeleton, start, world, task, sampler, np.random.default_rng(rng.integers(1 << 63)))
            values = None
            while values is None and not search.exhausted and search.effort < config.budget \
                    and time.perf_counter() < deadline:
                values = search.run(deadline, min(SLICE_UNITS, config.budget - search.effort))
            units, timed_out = search.effort, values is None and time.perf_counter() >= deadline
            log.label(values)
        by_name = {o.name: o for o in instance.objects}
        return episode_arrays(episode, instance_seed, planner_seed, values is not None, objects,
                              [by_name[o].asset for o in objects], [by_name[o].scale for o in objects],
                              log, units, timed_out, time.perf_counter() - started, len(candidates),
                              mass_features(world, objects))


def episode_arrays(episode: int, instance_seed: int, planner_seed: int, success: bool, objects, assets, scales,
                   log: Optional[SampleLog], units: int, timed_out: bool, seconds: float,
                   choices: int, masses: Sequence[float]) -> Dict[str, np.ndarray]:
    """The episode as flat arrays: per-episode fields prefixed `episode_`, one row per sample
    for the rest (parents are sample indices within the episode, -1-padded)."""
    samples = log.samples if log is not None else []
    n, m = len(samples), len(objects)
    value = np.full((n, VALUE_WIDTH), np.nan)
    proposal = np.full((n, VALUE_WIDTH), np.nan)
    parents = np.full((n, MAX_PARENTS), -1, dtype=np.int64)
    poses = np.zeros((n, m, 7))
    for k, s in enumerate(samples):
        value[k, :len(s.value)] = s.value
        proposal[k, :len(s.proposal)] = s.proposal
        parents[k, :len(s.parents[-MAX_PARENTS:])] = s.parents[-MAX_PARENTS:]
        poses[k] = s.poses
    text = lambda xs: np.array(list(xs), dtype=str) if len(xs) else np.zeros(0, dtype="<U1")  # noqa: E731
    return {
        "episode_id": np.array([episode], dtype=np.int64),
        "episode_instance_seed": np.array([instance_seed], dtype=np.int64),
        "episode_planner_seed": np.array([planner_seed], dtype=np.int64),
        "episode_success": np.array([success]),
        "episode_objects": text(objects)[None, :] if m else np.zeros((1, 0), dtype="<U1"),
        "episode_assets": text(assets)[None, :] if m else np.zeros((1, 0), dtype="<U1"),
        "episode_scales": np.array([scales], dtype=float).reshape(1, m),
        "episode_masses": np.array([masses], dtype=float).reshape(1, m),  # log kg (encoding.mass_features)
        "episode_units": np.array([units], dtype=np.int64),
        "episode_timed_out": np.array([timed_out]),
        "episode_groundings": np.array([choices], dtype=np.int64),
        "episode_seconds": np.array([seconds]),
        "episode": np.full(n, episode, dtype=np.int64),
        "sample": np.arange(n, dtype=np.int64),
        "stream": text([s.stream for s in samples]),
        "kind": text([s.kind for s in samples]),
        "step": np.array([s.step for s in samples], dtype=np.int64),
        "operator": text([s.operator for s in samples]),
        "param": text([s.param for s in samples]),
        "param_index": np.array([s.param_index for s in samples], dtype=np.int64),
        "value": value,
        "value_dim": np.array([len(s.value) for s in samples], dtype=np.int64),
        "proposal": proposal,
        "verified": np.array([s.verified for s in samples], dtype=np.int8),
        "poses": poses,
        "parents": parents,
        "label": np.array([s.label for s in samples], dtype=np.int8),
    }


def default_fragment(name: str) -> str:
    from .paths import MECHANISMS_DIR
    return os.path.join(MECHANISMS_DIR, f"{name}.pddl")
