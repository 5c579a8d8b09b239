"""The order in which a ranked batch of proposals is verified (ranked.py draws and scores it).

Best first, with a random pick instead now and then (`explore`, trust.py), and topped up
when the rest of the batch is hopeless. A batch often holds one proposal the classifier
believes in and fifteen it does not: on Lever's placements the best of 16 scored log -2.1
and the next -13.4 (lever-test-5, planner seed 5). Walking on from a best that failed
simulates a value the classifier gives one chance in 10^5. So when the best left lies more
than GAP below the best the walk has seen, the walk first tops the batch up with a fresh
batch (ranked.py's BATCH proposals; at most TOP_UPS times a walk, and only for a pick the
visit will verify): the next pick is the best of a fresh batch, not of a larger one (the
optimizer's curse, ranked.py, stays at a batch's size), and nothing is dropped. A cut-off
at the same gap, which skipped the rest instead, cost Poking (the tool put down after a
push: any free spot works, and ending the visit sent the search back to a new push).
Measured at cf0f99a (`bench samplers NAME --instances 10 --runs 3`, learned runs; values
simulated, median and geometric mean over the 30 runs): Lever 18 / 23.4 -> 12 / 18.5,
Poking 17 / 21.3 -> 19 / 19.0 (poking-test-6: 196, 206, 318 -> 34, 66, 114),
Slope-and-Blocker 8 / 14.6 -> 8 / 13.6, Hook 30 / 33.0 -> 30 / 33.3; Edge and
Center-of-Mass the same. A gap of 3 nats: Lever 17 / 17.5, Poking 17 / 19.8. On the next
ten instances (`--seed 10`, not traced): Lever 18 / 19.0 -> 12 / 12.6, Poking 23 / 25.1 ->
20 / 22.2.
"""
from __future__ import annotations

from typing import Callable, Iterator, List, Optional, Tuple

import numpy as np

GAP = 5.0         # nats: a learned pick this far below the best of its walk tops the batch up first
TOP_UPS = 3       # fresh batches a walk may add so


def walk(scores: np.ndarray, rng: np.random.Generator, explore: Callable[[], float],
         top_up: Optional[Callable[[], np.ndarray]] = None) -> Iterator[Tuple[int, bool]]:
    """(index, explored) best first, lazily: each next one is drawn at random from the rest
    with chance `explore()`, read at that moment (outcomes of earlier picks may change it).
    With `top_up` (the scores of a fresh batch the caller appends to its proposals, empty
    when there are none), a learned pick whose best left lies more than GAP below the best
    the walk has seen first tops the batch up, up to TOP_UPS times."""
    scores = [float(x) for x in scores]

    def best_first(indices: List[int]) -> List[int]:
        return sorted(indices, key=lambda i: -scores[i])   # stable: ties keep their order

    remaining = best_first(list(range(len(scores))))
    best, top_ups = max(scores, default=-np.inf), 0
    while remaining:
        explored = len(remaining) > 1 and rng.random() < explore()
        while (not explored and top_up is not None and top_ups < TOP_UPS
               and scores[remaining[0]] < best - GAP):
            top_ups += 1
            fresh = [float(x) for x in top_up()]
            if not fresh:
                break
            scores.extend(fresh)
            best = max(best, max(fresh))
            remaining = best_first(remaining + list(range(len(scores) - len(fresh), len(scores))))
        pick = int(rng.integers(len(remaining))) if explored else 0
        yield remaining.pop(pick), explored
