"""The planner's contract with mechanisms loaded: the basis operators' own search and the
mechanisms' search, run side by side on one world.

The plain search is exactly the search `--basis-only` runs (its own skeletons, evidence,
sampler and clock), so what it has done after W units is what the basis operators alone do
in W units. The other search hands out only skeletons that use a mechanism. They take turns
by `schedule.plain_owed`: the mechanisms' search has the first `head_start` units, then the
plain one is owed `plain_share` of the work beyond them; one with nothing to work on passes
its turn. So a problem the basis operators solve in W units is solved within
`head_start + W / plain_share` units (plus one slice) whatever is loaded. docs/planner.md,
"Two searches side by side", says what this costs and why the share is what it is.
"""
from __future__ import annotations

import time
from typing import Dict, List

from .budget import SearchBudget
from .run_stats import unsolved_reason
from .schedule import plain_owed


class SideBySide:
    """Two `BilevelSearch`es (planner/bilevel.py) on one world: `plain` over the basis
    operators alone, `mechanisms` over the skeletons that use a mechanism."""

    def __init__(self, plain, mechanisms, budget: SearchBudget):
        self.plain, self.mechanisms, self.budget = plain, mechanisms, budget

    def run(self):
        """Give the search whose turn it is a slice of work until one refines a plan, both have
        nothing left, or the time is up; the result carries both searches' statistics."""
        world, deadline = self.plain.world, self.plain.deadline
        sim_start = world.sim_steps
        # Work done when each search may be asked again: a search with nothing to work on is
        # done for good, unless it only passed over plain plans (the other search's) on its
        # way, in which case it asks on once the work has grown by `revisit`, or at once if
        # nothing else can.
        ready = {id(self.plain): 0.0, id(self.mechanisms): 0.0}
        winner, flagged = None, 0
        try:
            while winner is None and time.perf_counter() < deadline:
                work = self.plain.work + self.mechanisms.work
                waiting = [s for s in self._turns() if ready[id(s)] <= work]
                if not waiting:
                    later = [s for s in self._turns() if ready[id(s)] < float("inf")]
                    if not later:
                        break
                    waiting = [min(later, key=lambda s: ready[id(s)])]
                for search in waiting:
                    outcome = search.step()
                    # What the basis operators' search found dead explains the mechanisms'
                    # detours too; nothing flows back, so it stays the search --basis-only runs.
                    if self.plain.evidence.flagged != flagged:
                        flagged = self.plain.evidence.flagged
                        self.mechanisms.evidence.flag(self.plain.evidence.flagged_objects())
                    if outcome is None:
                        again = self.budget.revisit * work + self.budget.slice
                        ready[id(search)] = again if search.supply.passed_plain else float("inf")
                        continue
                    winner = search if outcome else None
                    break
        finally:
            world.restore(self.plain.initial)
        sim_steps = world.sim_steps - sim_start
        first = winner or self.mechanisms
        second = self.plain if first is self.mechanisms else self.mechanisms
        result, other = first.result(sim_steps), second.result(sim_steps)
        for search, stats in ((first, result.stats), (second, other.stats)):
            for entry in stats.get("skeleton_log", []):
                entry["search"] = "basis" if search is self.plain else "mechanisms"
        result.stats = merged_stats(result.stats, other.stats)
        result.stats.update(plain_work=self.plain.work, work=self.plain.work + self.mechanisms.work,
                            sim_steps=sim_steps)
        if winner is None:
            timed_out = any(r.reason.startswith("timed out") for r in (result, other))
            result.reason = unsolved_reason(timed_out, result.time_s, result.stats.get("skeletons", 0))
        return result

    def _turns(self) -> List[object]:
        """The searches in the order they are asked: the one owed the turn first."""
        owed = plain_owed(self.plain.work + self.mechanisms.work, self.plain.work,
                          self.budget.head_start, self.budget.plain_share)
        return [self.plain, self.mechanisms] if owed else [self.mechanisms, self.plain]


def merged_stats(first: Dict[str, object], second: Dict[str, object]) -> Dict[str, object]:
    """Two searches' statistics as one: counts added, logs joined (the first's entries
    first), lists of messages without repeats; where only one has a field, its value."""
    out: Dict[str, object] = dict(first)
    for key, value in second.items():
        out[key] = _merged(first[key], value) if key in first else value
    return out


def _merged(a: object, b: object) -> object:
    if isinstance(a, bool) or isinstance(b, bool):
        return a
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return a + b
    if isinstance(a, dict) and isinstance(b, dict):
        return merged_stats(a, b)
    if isinstance(a, list) and isinstance(b, list):
        if all(isinstance(x, str) for x in a + b):
            return list(dict.fromkeys(a + b))
        return a + b
    return a

