"""Re-execute a saved plan in a fresh world and check that the goal holds at the end."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Sequence

import numpy as np

from ..lang.loader import LoadedDomain
from ..lang.nodes import Problem
from ..operators.execution import Recorder
from ..world.build import build_world
from .bindings import run_step
from .bilevel import prepare_task
from .refine import observed_state
from .serialize import from_json


@dataclass
class ReplayResult:
    goal_reached: bool
    message: str
    frames: List[np.ndarray]


def replay(domain: LoadedDomain, problem: Problem, plan: Sequence[Dict[str, Any]], seed: int = 0,
           recorder: Optional[Recorder] = None) -> ReplayResult:
    """Run each step of `plan` (JSON entries with "name", "args", "params") in a new world."""
    rng = np.random.default_rng(seed)
    task, _ = prepare_task(domain, problem, use_mechanisms=False)
    with build_world(problem) as world:
        world.settle()
        if recorder:
            recorder.tick(world, force=True)
        for index, step in enumerate(plan, 1):
            values = {name: from_json(value) for name, value in step.get("params", {}).items()}
            outcome = run_step(world, step["name"], step["args"], values, rng, recorder)
            if not outcome.ok:
                return ReplayResult(False, f"step {index} ({step['name']}) failed: {outcome.reason}",
                                    recorder.frames if recorder else [])
        if recorder:
            recorder.tick(world, force=True)
        reached = task.is_goal(observed_state(task, world))
    message = "the goal holds in the simulation" if reached else "the goal does not hold at the end"
    return ReplayResult(reached, message, recorder.frames if recorder else [])
