"""Executing plan steps: one code path for the planner's search, its final check and `replay`.

Every step starts from a canonical restore of the world (`World.restore`), so a step run
in the planner's long-lived world and the same step run in a fresh world built from the
scene file simulate identically (snapshot.py), and a plan that the planner reports solved
is re-executed in a fresh world exactly as `replay` will execute it.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, List, Mapping, Optional, Sequence

from ..lang.nodes import Problem
from ..operators import basis
from ..operators.execution import FrameRecorder
from ..symbolic.task import StripsTask
from ..world.build import build_world
from ..world.contacts import read_contacts
from ..world.snapshot import Snapshot
from ..world.values import Contact, Grasp, OPERATOR_VALUES, Placement, Trajectory
from ..world.world import World
from .serialize import from_json

CONTACT_PREDICATES = ("holding", "support", "handempty")
SETTLE_WARNING = 5e-3  # metres an object may move while the initial scene settles


def run_step(world: World, action: str, args: Sequence[str], values: Mapping[str, object],
             recorder: Optional[FrameRecorder] = None) -> basis.Outcome:
    """Execute basis operator `action` with its arguments' sampled values."""
    bound = [values.get(a, a) for a in args]
    of = lambda kind: next((v for v in bound if isinstance(v, kind)), None)  # noqa: E731
    trajectory: Optional[Trajectory] = of(Trajectory)
    if action not in OPERATOR_VALUES:
        raise ValueError(f"action '{action}' has no operator implementation; basis operators are "
                         f"{', '.join(OPERATOR_VALUES)}")
    missing = [kind.__name__.lower() for kind in OPERATOR_VALUES[action] if of(kind) is None]
    if missing:
        return basis.Outcome(False, f"no {' or '.join(missing)} value")
    if action == "grasp":
        return basis.grasp(world, args[0], of(Grasp), trajectory, recorder)
    if action == "place":
        return basis.place(world, args[0], of(Placement), trajectory, recorder)
    if action in ("transit-cont", "move-cont"):
        return basis.push(world, of(Contact), trajectory, recorder)
    return basis.transit(world, trajectory, recorder)


def execute_step(world: World, start: Snapshot, action: str, args: Sequence[str], values: Mapping[str, object],
                 recorder: Optional[FrameRecorder] = None) -> basis.Outcome:
    """Restore `start` canonically, then run the step."""
    world.restore(start)
    return run_step(world, action, args, values, recorder)


def contact_mask(task: StripsTask) -> int:
    """The task facts the simulation can observe (the contact-mode graph)."""
    mask = 0
    for fact, i in task.fact_ids.items():
        if fact[0] in CONTACT_PREDICATES:
            mask |= 1 << i
    return mask


def observed_state(task: StripsTask, world: World) -> int:
    """The contact-graph facts true in the world, as task bits."""
    state = 0
    for fact in read_contacts(world).facts():
        i = task.fact_ids.get(tuple(fact))
        if i is not None:
            state |= 1 << i
    return state


def goal_holds(task: StripsTask, state: int) -> bool:
    """The problem's goal in `state`; a disjunctive goal was compiled to artificial
    `reach-goal` operators, one per disjunct, whose preconditions are checked instead."""
    if task.is_goal(state):
        return True
    return any(op.artificial and task.applicable(state, op) for op in task.operators)


def settle_start(world: World) -> List[str]:
    """Let the scene settle as every plan's execution starts; a warning per object that
    moved more than SETTLE_WARNING (floating, or resting on a slope it slides down)."""
    before = {name: world.pose(name)[0] for name in world.movable()}
    world.settle()
    warnings = []
    for name, position in before.items():
        moved = sum((a - b) ** 2 for a, b in zip(world.pose(name)[0], position)) ** 0.5
        if moved > SETTLE_WARNING:
            warnings.append(f"object '{name}' moved {moved * 100:.1f} cm when the scene settled at the start "
                            "(it was not resting at its scene pose)")
    return warnings


@dataclass
class ExecutionResult:
    goal_reached: bool
    message: str
    failed_step: Optional[int] = None   # 1-based index of the first step that failed


def execute_plan(task: StripsTask, problem: Problem, steps: Sequence[Dict[str, Any]],
                 recorder: Optional[FrameRecorder] = None) -> ExecutionResult:
    """Run plan `steps` (JSON entries with "name", "args", "params") in a fresh world built
    from `problem`'s scene, each from a canonical restore, and check the goal at the end."""
    with build_world(problem, visual=recorder is not None) as world:
        settle_start(world)
        if recorder:
            recorder.tick(world, force=True)
        for index, step in enumerate(steps, 1):
            values = {name: from_json(value) for name, value in step.get("params", {}).items()}
            outcome = execute_step(world, world.snapshot(), step["name"], step["args"], values, recorder)
            if not outcome.ok:
                if recorder:   # what happened up to there
                    recorder.finish(world)
                return ExecutionResult(False, f"step {index} ({step['name']}) failed: {outcome.reason}", index)
        if recorder:
            recorder.tick(world, force=True)
        observable = contact_mask(task)
        reached = goal_holds(task, (observed_state(task, world) & observable) | (task.init & ~observable))
        if recorder:
            recorder.finish(world)
    return ExecutionResult(reached, "the goal holds in the simulation" if reached else
                           "the goal does not hold at the end")
