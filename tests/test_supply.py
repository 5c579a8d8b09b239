"""Where skeletons come from (planner/supply.py): the unit order (a mechanism is one action)
takes turns with the priced one (a mechanism costs its basis steps), so that a problem that
needs no mechanism meets its plain plan among the first; skeletons set aside behind a dead
step come back when the step is revisited."""
import glob
import os
import time

from pdsketch_mech.lang.loader import load_domain, load_problem
from pdsketch_mech.planner.bilevel import prepare_task
from pdsketch_mech.planner.evidence import Evidence
from pdsketch_mech.planner.supply import SkeletonSupply, skeleton_order

from conftest import ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")
EVERY = sorted(glob.glob(os.path.join(ROOT, "domains", "mechanisms", "*.pddl")))
TOWER = os.path.join(ROOT, "tests", "data", "tower-of-three.pddl")


def _labels(task, skeletons, n):
    return [" ".join(task.operators[o].label for o in plan) for _, plan in zip(range(n), skeletons)]


def _tower(mechanisms):
    domain, problem = load_problem(TOWER, [load_domain([BASIS] + mechanisms, samplers_required=False)])
    task, _ = prepare_task(domain, problem)
    return task


def test_the_plain_plan_of_a_tower_comes_first_in_the_priced_order_with_every_mechanism_loaded():
    plain = _labels(_tower([]), skeleton_order(_tower([]), priced=True), 1)[0]
    task = _tower(EVERY)
    assert _labels(task, skeleton_order(task, priced=True), 1) == [plain]
    assert plain not in _labels(task, skeleton_order(task), 500)   # the unit order alone: mechanisms first
    supply = SkeletonSupply(task, Evidence(task), time.perf_counter() + 60)
    window = supply.upcoming()
    labels = [s.label(task) for s in window]
    assert "(com" in labels[0] and labels[1] == plain     # the two orders take turns, the unit one first
    assert len({tuple(s.plan) for s in window}) == len(window)   # none twice


def test_in_the_priced_order_a_mechanism_costs_its_steps():
    task = _tower(EVERY)
    macros = [op for op in task.operators if op.steps]
    assert macros and all(op.cost == len(op.steps) > 1 for op in macros)
    costs = [sum(task.operators[o].cost for o in plan)
             for _, plan in zip(range(30), skeleton_order(task, priced=True))]
    assert costs[0] == min(costs) == 4


def test_without_mechanisms_the_supply_is_the_search_alone():
    task = _tower([])
    supply = SkeletonSupply(task, Evidence(task), time.perf_counter() + 60)
    assert [s.plan for s in supply.upcoming()] == [p for _, p in zip(range(8), skeleton_order(task, priced=True))]


def test_skeletons_behind_a_dead_step_are_deferred_and_come_back_when_it_is_revisited():
    task = _tower([])
    evidence = Evidence(task)
    supply = SkeletonSupply(task, evidence, time.perf_counter() + 60)
    first = supply.upcoming()[0]
    key = first.pristine[0]
    for _ in range(evidence.dead_after):
        evidence.ran_dry(key)
    assert key in evidence.dead
    assert first not in supply.upcoming() and first in supply._deferred
    assert not evidence.advance(evidence.revisit_at[key] - 1)   # not yet due
    assert evidence.advance(evidence.revisit_at[key])           # the belief is revisited
    assert key not in evidence.dead and first in supply.upcoming()   # one comes back to try the step
    assert supply.returned == 1
    evidence.found(key)                                             # and finds it feasible after all
    assert evidence.cleared == 1 and supply.upcoming() and supply.returned >= 1


def test_the_mechanisms_search_hands_out_only_skeletons_that_use_a_mechanism():
    """With mechanisms loaded the basis operators' own search has the plain plans
    (side_by_side.py); the other supply passes over them, even where the priced order puts
    the tower's plain plan first."""
    task = _tower(EVERY)
    supply = SkeletonSupply(task, Evidence(task), time.perf_counter() + 60, mechanisms_only=True)
    window = supply.upcoming()
    assert window and all(any(task.operators[o].steps for o in s.plan) for s in window)
    plain = _labels(_tower([]), skeleton_order(_tower([]), priced=True), 1)[0]
    assert plain not in [s.label(task) for s in window]
