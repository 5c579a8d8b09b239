"""Skeletons that wander: detours that no failure explains.

A *detour* is a run of steps that returns the symbolic state to one the skeleton was in
before: a push (transit-cont has no symbolic effect), a grasp and a place back on the same
support, a tool use that ends where it began. Symbolically a detour does nothing; it can
only matter in the scene, by moving an object. The planner knows which objects need moving:
those of the pristine steps found dead (pristine.py), such as a box the arm cannot reach
where it lies. A detour that handles one of them is *explained* (hooking that box closer and
putting it down is how the Hook task is solved without a mechanism); one that handles only
other objects (pushing the tool, lifting a distractor and putting it back) is not.

The FF-guided search yields many unexplained detours: every skeleton comes again with pushes
of every object in front, and with each object lifted and put back, and their first slices
took the work a mechanism's own skeleton needed. A skeleton's share of work is multiplied by
DETOUR_WEIGHT per unexplained detour (schedule.py): such skeletons still come (the planner
stays complete: an obstacle may need moving that no dead step names), but later and with
less work. results/HISTORY.md has the runs that chose it and what it costs where an
unexplained push was what worked.
"""
from __future__ import annotations

from typing import Dict, Sequence

from ..symbolic.task import StripsTask

DETOUR_WEIGHT = 0.25   # share of work kept per unexplained detour


def unexplained_detours(task: StripsTask, plan: Sequence[int], masks: Sequence[int], flagged: int) -> int:
    """How many times the skeleton `plan` (operator ids) returns to a symbolic state it was in
    before through steps that handle none of the `flagged` objects (bits of `masks[op]`,
    the objects each operator handles)."""
    state = task.init
    last_seen: Dict[int, int] = {state: 0}   # state -> after how many steps it was last seen
    detours = 0
    for j, op in enumerate(plan, 1):
        state = task.successor(state, task.operators[op])
        i = last_seen.get(state)
        if i is not None:
            handled = 0
            for earlier in plan[i:j]:
                handled |= masks[earlier]
            detours += not handled & flagged
        last_seen[state] = j
    return detours


def detour_weight(detours: int) -> float:
    """The share of work a skeleton keeps for its unexplained detours, in (0, 1]."""
    return DETOUR_WEIGHT ** detours
