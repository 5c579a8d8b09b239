"""Executing plan steps: one code path for the planner's search, its final check and `replay`.

Every step starts from a canonical restore of the world (`World.restore`), so a step run
in the planner's long-lived world and the same step run in a fresh world built from the
scene file simulate identically (snapshot.py), and a plan that the planner reports solved
is re-executed in a fresh world exactly as `replay` will execute it.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple

from ..lang.nodes import Problem
from ..operators import basis
from ..operators.execution import FrameRecorder
from ..operators.vocabulary import BASIS, Vocabulary
from ..symbolic.task import StripsTask
from ..world.build import build_world
from ..world.snapshot import Snapshot
from ..world.world import World
from .serialize import from_json

SETTLE_WARNING = 5e-3  # metres an object may move while the initial scene settles


def run_step(world: World, action: str, args: Sequence[str], values: Mapping[str, object],
             recorder: Optional[FrameRecorder] = None, vocabulary: Vocabulary = BASIS) -> basis.Outcome:
    """Execute operator `action` with its arguments' sampled values, as the vocabulary says."""
    return vocabulary.execute(world, action, args, values, recorder)


def execute_step(world: World, start: Snapshot, action: str, args: Sequence[str], values: Mapping[str, object],
                 recorder: Optional[FrameRecorder] = None, vocabulary: Vocabulary = BASIS) -> basis.Outcome:
    """Restore `start` canonically, then run the step."""
    world.restore(start)
    return run_step(world, action, args, values, recorder, vocabulary)


def contact_mask(task: StripsTask, vocabulary: Vocabulary = BASIS) -> int:
    """The task facts the simulation can observe (the contact-mode graph)."""
    return vocabulary.contact_mask(task)


def observed_state(task: StripsTask, world: World, vocabulary: Vocabulary = BASIS) -> int:
    """The observable facts true in the world, as task bits."""
    return vocabulary.observed(task, world)


def goal_holds(task: StripsTask, state: int) -> bool:
    """The problem's goal in `state`; a disjunctive goal was compiled to artificial
    `reach-goal` operators, one per disjunct, whose preconditions are checked instead."""
    if task.is_goal(state):
        return True
    return any(op.artificial and task.applicable(state, op) for op in task.operators)


def settle_moves(world: World) -> List[Tuple[str, float]]:
    """Let the scene settle as every plan's execution starts; each object that moved more
    than SETTLE_WARNING (floating, tipping over, sliding down a slope), with how far (m)."""
    before = {name: world.pose(name)[0] for name in world.movable()}
    world.settle()
    moved = [(name, sum((a - b) ** 2 for a, b in zip(world.pose(name)[0], position)) ** 0.5)
             for name, position in before.items()]
    return [(name, distance) for name, distance in moved if distance > SETTLE_WARNING]


def settle_start(world: World) -> List[str]:
    """`settle_moves`, as the planner's warnings."""
    return [f"object '{name}' moved {distance * 100:.1f} cm when the scene settled at the start "
            "(it was not resting at its scene pose)" for name, distance in settle_moves(world)]


@dataclass
class ExecutionResult:
    goal_reached: bool
    message: str
    failed_step: Optional[int] = None   # 1-based index of the first step that failed


def execute_plan(task: StripsTask, problem: Problem, steps: Sequence[Dict[str, Any]],
                 recorder: Optional[FrameRecorder] = None, vocabulary: Vocabulary = BASIS) -> ExecutionResult:
    """Run plan `steps` (JSON entries with "name", "args", "params") in a fresh world built
    from `problem`'s scene, each from a canonical restore, and check the goal at the end."""
    with build_world(problem, visual=recorder is not None) as world:
        settle_start(world)
        if recorder:
            recorder.tick(world, force=True)
        for index, step in enumerate(steps, 1):
            values = {name: from_json(value) for name, value in step.get("params", {}).items()}
            outcome = execute_step(world, world.snapshot(), step["name"], step["args"], values, recorder, vocabulary)
            if not outcome.ok:
                if recorder:   # what happened up to there
                    recorder.finish(world)
                return ExecutionResult(False, f"step {index} ({step['name']}) failed: {outcome.reason}", index)
        if recorder:
            recorder.tick(world, force=True)
        observable = contact_mask(task, vocabulary)
        reached = goal_holds(task, (observed_state(task, world, vocabulary) & observable) | (task.init & ~observable))
        if recorder:
            recorder.finish(world)
    return ExecutionResult(reached, "the goal holds in the simulation" if reached else
                           "the goal does not hold at the end")
