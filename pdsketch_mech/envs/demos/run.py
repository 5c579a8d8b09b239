"""Running a scripted demonstration on an instance, recording it, checking its goal."""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, Dict, List, Optional, Set, Tuple

from ...lang.nodes import Formula, Problem
from ...lang.parser import parse_text
from ...symbolic.normalize import holds
from ...world.build import build_world
from ...world.contacts import read_contacts
from ...world.recording import Recorder
from ...world.world import World
from ..generate import Instance, sample
from ..tasks import get_task
from . import com, edge, hook, lever, poking, slope
from .motion import DemoError, Driver

Script = Callable[[World, Instance, Driver], None]

DEMOS: Dict[str, Script] = {
    "edge": edge.demo,
    "hook": hook.demo,
    "lever": lever.demo,
    "poking": poking.demo,
    "com": com.demo,
    "slope-blocker": slope.demo,
}
SETTLE_BEFORE = 120   # physics steps the scene rests before the recording starts


def goal_holds(goal: Formula, facts: Set[Tuple[str, ...]], problem: Problem) -> bool:
    """`goal` in the state given by `facts`; a quantified variable ranges over the objects
    declared with its type (or over all of them for `object`)."""
    by_type: Dict[str, List[str]] = {"object": [o.name for o in problem.objects]}
    for declared in problem.objects:
        by_type.setdefault(declared.type, []).append(declared.name)
    return holds(goal, facts, by_type)


@dataclass
class DemoResult:
    instance: Optional[Instance]      # None for a user's demonstration (its problem file is the scene)
    problem: Problem
    goal_reached: bool
    facts: Set[Tuple[str, ...]]
    recorder: Optional[Recorder]
    sim_steps: int
    wall_s: float
    error: str = ""
    extra: Dict[str, object] = field(default_factory=dict)

    def facts_text(self) -> str:
        return " ".join("(" + " ".join(f) + ")" for f in sorted(self.facts))


def demo_instance(name: str, split: str = "train", seed: Optional[int] = None) -> Instance:
    """The canonical instance of task `name`, or (with a seed) one with perturbed poses."""
    return sample(get_task(name), split, seed, vary_assets=False)


def perform(problem: Problem, act: Callable[[World], None], record: bool = True,
            instance: Optional[Instance] = None, errors: Tuple[type, ...] = (DemoError,)) -> DemoResult:
    """Build `problem`'s world, let it rest, run `act` on it (recording every 4 steps),
    settle, and read the goal off the contact graph. Exceptions of the `errors` types are
    reported in `error`, never raised."""
    start = time.perf_counter()
    with build_world(problem) as world:
        world.step(SETTLE_BEFORE)
        recorder = Recorder(world).start() if record else None
        steps0 = world.sim_steps
        error = ""
        try:
            act(world)
            world.settle()
        except errors as exc:
            error = str(exc)
        if recorder:
            recorder.stop()
        facts = {tuple(f) for f in read_contacts(world).facts()}
        reached = not error and goal_holds(problem.goal, facts, problem)
        result = DemoResult(instance, problem, reached, facts, recorder, world.sim_steps - steps0,
                            time.perf_counter() - start, error)
        if recorder:
            result.extra["arrays"] = recorder.arrays()
            result.extra["header"] = recorder.header(rested_steps_before=SETTLE_BEFORE)
    return result


def run_demo(name: str, instance: Optional[Instance] = None, record: bool = True,
             on_world: Optional[Callable[[World], None]] = None) -> DemoResult:
    """A built-in scripted demonstration on `instance` (default: the canonical one), see
    `perform`; `on_world` runs first."""
    if name not in DEMOS:
        raise KeyError(f"unknown demo {name!r}; demos: {', '.join(DEMOS)}")
    instance = instance or demo_instance(name)
    problem = parse_text(instance.problem_text(), file=f"{instance.name}.pddl")

    def act(world: World) -> None:
        if on_world:
            on_world(world)
        DEMOS[name](world, instance, Driver(world))
    return perform(problem, act, record, instance)


def record_demo(name: str, split: str = "train", seed: Optional[int] = None) -> DemoResult:
    return run_demo(name, demo_instance(name, split, seed))
