"""Where skeletons come from (planner/supply.py): with mechanisms loaded, a search over the
basis operators alone takes turns with the full one, so that a problem that needs no
mechanism meets its plain plan among the first skeletons."""
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
    out = []
    for _, plan in zip(range(n), skeletons):
        out.append(" ".join(task.operators[o].label for o in plan))
    return out


def test_the_plain_plan_of_a_tower_comes_early_with_every_mechanism_loaded():
    domain, problem = load_problem(TOWER, [load_domain([BASIS] + EVERY, samplers_required=False)])
    task, _ = prepare_task(domain, problem)
    plain = "(grasp b table"
    full_search = _labels(task, skeleton_order(task), 40)
    assert not any(label.startswith(plain) and "(com" not in label and "(slope" not in label
                   for label in full_search[:20])          # the full search alone: mechanisms first
    supply = SkeletonSupply(task, Evidence(task), time.perf_counter() + 60, 50)
    window = supply.upcoming()
    basis_only = [s for s in window if not any(step.mechanism for step in s.steps)]
    assert basis_only and basis_only[0].order <= 2
    assert len({tuple(s.plan) for s in window}) == len(window)   # none twice


def test_without_mechanisms_the_supply_is_the_search_alone():
    domain, problem = load_problem(TOWER, [load_domain([BASIS])])
    task, _ = prepare_task(domain, problem)
    supply = SkeletonSupply(task, Evidence(task), time.perf_counter() + 60, 20)
    assert [s.plan for s in supply.upcoming()] == [p for _, p in zip(range(8), skeleton_order(task))]


def test_the_basis_only_search_stops_once_a_step_is_dead_where_the_scene_began():
    """Then the problem needs the scene changed first: the full search goes on alone, and
    what the basis-only search found but was not handed out is forgotten (so the full search
    can hand it out in its own order)."""
    domain, problem = load_problem(TOWER, [load_domain([BASIS] + EVERY, samplers_required=False)])
    task, _ = prepare_task(domain, problem)
    evidence = Evidence(task)
    supply = SkeletonSupply(task, evidence, time.perf_counter() + 60, 50)
    window = supply.upcoming()
    assert any(s.source for s in window)
    for _ in range(evidence.dead_after):
        evidence.ran_dry(("grasp", ("nothing", "table")))
    window = supply.upcoming()
    assert window and not any(s.source for s in window)
    supply.take(window[0])
    assert not any(s.source for s in supply.upcoming())
