"""How far a plan trusts a learned order, judged by the plan's own outcomes.

A classifier trained on the train split's objects can be confidently wrong about a shape it
never saw: on Slope-and-Blocker's held-out blockers (a spoon, a thicker stick) the placements
it ranks first slid off where the generic sampler's first random one held (46 values
simulated against 8), and on Poking's held-out spoon it needed 510 values where the generic
order needed 160. The walk through a ranked batch already takes a random proposal instead
of the best left with a small chance (SamplerBudget.learned_explore, ../budget.py: the
`floor`); `Trust` keeps score of both kinds of pick in one plan, per mechanism grounding,
and raises that chance as the evidence grows that random picks do better than the learned
ones, up to a walk in the generic (random) order.

A pick succeeds when its proposal verifies, the step it is used in simulates with the
contacts the skeleton expects, and the mechanism's next step then simulates too within that
visit (planner/refine.py): a grasp of a blocker that lets no placement hold is a failure of
the grasp, though the grasp itself worked. It fails when any of these does not. While the learned picks do
at least as well as the random ones the chance stays at its floor, so on the objects a
classifier knows nothing changes; a learned sampler that does no better than the generic
one in a step's own outcome (a grasp that works either way, whose worth shows only steps
later) keeps its order too. Only evidence that the learned picks do *worse* moves it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Tuple


@dataclass
class Trust:
    """Outcomes of learned picks (the best left of a ranked batch) and of random ones."""

    floor: float                 # the chance of a random pick with no evidence against the order
    learned_ok: int = 0
    learned_failed: int = 0
    random_ok: int = 0
    random_failed: int = 0

    def record(self, explored: bool, ok: bool) -> None:
        """Count the outcome of one pick (`explored`: a random one)."""
        if explored:
            self.random_ok += ok
            self.random_failed += not ok
        else:
            self.learned_ok += ok
            self.learned_failed += not ok

    def random_better(self) -> float:
        """P(a random pick's success rate exceeds a learned pick's), by the normal
        approximation of the difference of their Beta posteriors. Both share a prior of
        weight 2 centred on the pooled rate: where every pick fails (a grounding that cannot
        work), the few random picks are not thought better for being few."""
        ok, failed = self.learned_ok + self.random_ok, self.learned_failed + self.random_failed
        pooled = (ok + 1.0) / (ok + failed + 2.0)
        prior = (2.0 * pooled, 2.0 * (1.0 - pooled))
        m1, v1 = _beta(self.random_ok, self.random_failed, prior)
        m2, v2 = _beta(self.learned_ok, self.learned_failed, prior)
        return 0.5 * (1.0 + math.erf((m1 - m2) / math.sqrt(2.0 * (v1 + v2))))

    def explore_chance(self) -> float:
        """The floor while the learned picks do at least as well; towards 1 (the generic
        order) as P(random picks do better) goes from 1/2 to 1."""
        doubt = max(0.0, 2.0 * self.random_better() - 1.0)
        return self.floor + (1.0 - self.floor) * doubt

    def to_json(self) -> dict:
        return {"learned": [self.learned_ok, self.learned_failed], "random": [self.random_ok, self.random_failed],
                "explore": round(self.explore_chance(), 3)}


def _beta(ok: int, failed: int, prior: Tuple[float, float]) -> Tuple[float, float]:
    """Mean and variance of Beta(prior[0] + ok, prior[1] + failed)."""
    a, b = prior[0] + ok, prior[1] + failed
    return a / (a + b), a * b / ((a + b) ** 2 * (a + b + 1.0))
