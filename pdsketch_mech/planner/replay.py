"""Re-execute a saved plan in a fresh world and check that the goal holds at the end."""
from __future__ import annotations

from typing import Any, Dict, Optional, Sequence

from ..lang.loader import LoadedDomain
from ..lang.nodes import Problem
from ..operators.execution import FrameRecorder
from .bilevel import prepare_task
from .execute import ExecutionResult, execute_plan


def replay(domain: LoadedDomain, problem: Problem, plan: Sequence[Dict[str, Any]],
           recorder: Optional[FrameRecorder] = None) -> ExecutionResult:
    """Run each step of `plan` (JSON entries with "name", "args", "params") in a new world,
    exactly as the planner executed it."""
    task, _ = prepare_task(domain, problem, use_mechanisms=False)
    return execute_plan(task, problem, plan, recorder)
