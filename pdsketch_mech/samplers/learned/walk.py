"""The order in which a ranked batch of proposals is verified (ranked.py draws and scores it).

Best first, with a random pick instead now and then (`explore`, trust.py), and topped up
when the rest of the batch is hopeless. A batch often holds one proposal the classifier
believes in and fifteen it does not (a best at log -2 and the next at log -13): walking on
from a best that failed simulates a value the classifier gives one chance in 10^5. So when
the best left lies more than `learned_top_up_gap` nats below the best the walk has seen, the
walk first tops the batch up with a fresh batch (ranked.py's `learned_batch` proposals; at
most `learned_top_ups` times a walk, and only for a pick the visit will verify; both fields
of SamplerBudget, ../budget.py): the next pick is the best of a fresh batch, not of a larger
one (the optimizer's curse, ranked.py, stays at a batch's size), and nothing is dropped. A
cut-off at the same gap, which skipped the rest instead, cost Poking (the tool put down
after a push: any free spot works, and ending the visit sent the search back to a new push).
Figures: results/HISTORY.md.
"""
from __future__ import annotations

from typing import Callable, Iterator, List, Optional, Tuple

import numpy as np

from ..budget import SamplerBudget


def walk(scores: np.ndarray, rng: np.random.Generator, explore: Callable[[], float],
         top_up: Optional[Callable[[], np.ndarray]] = None,
         budget: SamplerBudget = SamplerBudget()) -> Iterator[Tuple[int, bool]]:
    """(index, explored) best first, lazily: each next one is drawn at random from the rest
    with chance `explore()`, read at that moment (outcomes of earlier picks may change it).
    With `top_up` (the scores of a fresh batch the caller appends to its proposals, empty
    when there are none), a learned pick whose best left lies more than
    `budget.learned_top_up_gap` below the best the walk has seen first tops the batch up, up
    to `budget.learned_top_ups` times."""
    scores = [float(x) for x in scores]

    def best_first(indices: List[int]) -> List[int]:
        return sorted(indices, key=lambda i: -scores[i])   # stable: ties keep their order

    remaining = best_first(list(range(len(scores))))
    best, top_ups = max(scores, default=-np.inf), 0
    while remaining:
        explored = len(remaining) > 1 and rng.random() < explore()
        while (not explored and top_up is not None and top_ups < budget.learned_top_ups
               and scores[remaining[0]] < best - budget.learned_top_up_gap):
            top_ups += 1
            fresh = [float(x) for x in top_up()]
            if not fresh:
                break
            scores.extend(fresh)
            best = max(best, max(fresh))
            remaining = best_first(remaining + list(range(len(scores) - len(fresh), len(scores))))
        pick = int(rng.integers(len(remaining))) if explored else 0
        yield remaining.pop(pick), explored
