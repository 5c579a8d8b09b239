"""Grounding, the FF heuristic, search, skeletons and optimistic placeholders."""
import os

import pytest

from pdsketch_mech.lang.loader import load_domain, load_problem
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.lang.typecheck import check_domain, check_problem
from pdsketch_mech.symbolic.grounding import ground
from pdsketch_mech.symbolic.heuristic import INFINITY, FFHeuristic
from pdsketch_mech.symbolic.optimistic import optimistic_problem
from pdsketch_mech.symbolic.skeletons import iter_skeletons
from pdsketch_mech.symbolic.solve import solve
from pdsketch_mech.symbolic.validate import validate_plan

from conftest import DATA, ROOT

# A corridor of rooms: a robot moves between adjacent rooms and may carry one key.
CORRIDOR = """(define (domain corridor)
  (:requirements :strips :typing :negative-preconditions :equality :conditional-effects)
  (:types room key)
  (:predicates (at ?r - room) (adj ?a - room ?b - room) (key-at ?k - key ?r - room)
               (carrying ?k - key) (free) (lit ?r - room))
  (:action move :parameters (?a - room ?b - room)
    :precondition (and (at ?a) (adj ?a ?b) (not (= ?a ?b)))
    :effect (and (not (at ?a)) (at ?b)
                 (forall (?k - key) (when (carrying ?k) (key-at ?k ?b)))
                 (forall (?k - key) (when (carrying ?k) (not (key-at ?k ?a))))))
  (:action pick :parameters (?k - key ?r - room)
    :precondition (and (at ?r) (key-at ?k ?r) (free))
    :effect (and (carrying ?k) (not (free))))
  (:action light :parameters (?r - room)
    :precondition (and (at ?r) (not (lit ?r)) (exists (?k - key) (carrying ?k)))
    :effect (lit ?r)))
"""


def corridor_problem(rooms=4, goal="(and (lit r3) (key-at k r3))", extra_init=""):
    names = " ".join(f"r{i}" for i in range(rooms))
    adj = " ".join(f"(adj r{i} r{i + 1}) (adj r{i + 1} r{i})" for i in range(rooms - 1))
    return (f"(define (problem p) (:domain corridor) (:objects {names} - room k - key)"
            f" (:init (at r0) {adj} (key-at k r1) (free) {extra_init}) (:goal {goal}))")


def task_of(domain_text, problem_text, **kwargs):
    domain, problem = parse_text(domain_text), parse_text(problem_text)
    types = check_domain(domain)
    check_problem(problem, domain, types)
    return domain, problem, types, ground(domain, problem, types, **kwargs)


def test_grounding_keeps_only_reachable_operators_and_fluent_facts():
    cut = corridor_problem().replace("(adj r2 r3) (adj r3 r2)", "")
    _, _, _, task = task_of(CORRIDOR, cut, prune_irrelevant=False)
    labels = {op.label for op in task.operators}
    assert "(move r0 r1)" in labels and "(move r0 r2)" not in labels  # adj is static: filtered
    assert "(move r1 r1)" not in labels                                # equality
    assert "(pick k r0)" in labels                                     # the key can be carried back
    assert "(light r3)" not in labels and ("at", "r3") not in task.fact_ids  # r3 is cut off
    assert all(f[0] != "adj" for f in task.facts)                      # statics are not state
    assert ("adj", "r0", "r1") in task.static_facts


def test_conditional_effects_move_the_carried_key():
    _, _, _, task = task_of(CORRIDOR, corridor_problem(), prune_irrelevant=False)
    op = {o.label: o for o in task.operators}
    state = task.successor(task.init, op["(move r0 r1)"])
    assert task.atoms(state) == [("at", "r1"), ("free",), ("key-at", "k", "r1")]  # not carried: stays
    state = task.successor(state, op["(pick k r1)"])
    state = task.successor(state, op["(move r1 r2)"])
    assert ("key-at", "k", "r2") in task.atoms(state) and ("key-at", "k", "r1") not in task.atoms(state)


def test_negative_precondition_and_exists():
    _, _, _, task = task_of(CORRIDOR, corridor_problem(extra_init="(lit r1)"), prune_irrelevant=False)
    light = {o.label: o for o in task.operators}["(light r1)"]
    assert not task.applicable(task.mask([("at", "r1"), ("carrying", "k"), ("lit", "r1")]), light)
    assert task.applicable(task.mask([("at", "r1"), ("carrying", "k")]), light)
    assert not task.applicable(task.mask([("at", "r1"), ("free",)]), light)  # exists: no key carried


def test_ff_values_on_a_hand_checked_task():
    _, _, _, task = task_of(CORRIDOR, corridor_problem(goal="(carrying k)"))
    h, helpful = FFHeuristic(task)(task.init)
    assert h == 2  # move r0 r1, pick k r1
    assert [task.operators[o].label for o in helpful] == ["(move r0 r1)"]
    _, _, _, task = task_of(CORRIDOR, corridor_problem())
    assert FFHeuristic(task)(task.init)[0] == 5  # move x3, pick, light r3


def test_ff_is_zero_at_the_goal_and_infinite_when_unreachable():
    _, _, _, task = task_of(CORRIDOR, corridor_problem(goal="(at r0)"))
    assert FFHeuristic(task)(task.init) == (0.0, [])
    _, _, _, task = task_of(CORRIDOR, corridor_problem(goal="(key-at k r0)", extra_init="").replace(
        "(adj r0 r1) (adj r1 r0)", ""))  # r0 cut off from the key
    assert FFHeuristic(task)(task.init)[0] == INFINITY


@pytest.mark.parametrize("search", ["gbfs", "wastar"])
@pytest.mark.parametrize("name,problem", [("blocks", "p02.pddl"), ("logistics00", "problem01.pddl"),
                                          ("depot", "task02.pddl"), ("satellite", "task02.pddl"),
                                          ("miconic", "p02.pddl"), ("rovers", "task03.pddl")])
def test_search_finds_valid_plans_on_ipc_problems(search, name, problem):
    loaded, prob = load_problem(os.path.join(DATA, "ipc", name, problem))
    result = solve(loaded.domain, prob, loaded.types, search=search, timeout=60)
    assert result.status == "solved"
    check = validate_plan(loaded.domain, prob, result.plan)
    assert check.ok, check.message


def test_disjunctive_goal_is_compiled_and_hidden_from_the_plan():
    domain, problem, types, _ = task_of(CORRIDOR, corridor_problem(goal="(or (at r3) (carrying k))"))
    result = solve(domain, problem, types)
    assert result.status == "solved" and result.plan == [("move", ("r0", "r1")), ("pick", ("k", "r1"))]


def test_unsolvable_task_is_reported_without_search():
    domain, problem, types, _ = task_of(CORRIDOR, corridor_problem(goal="(at r3)").replace(
        "(adj r2 r3) (adj r3 r2)", ""))
    for search in ("gbfs", "wastar"):
        result = solve(domain, problem, types, search=search, timeout=5)
        assert result.status == "unsolvable" and result.plan == []
        assert result.stats["expansions"] == 0


def test_search_exhausts_a_relaxed_solvable_but_unsolvable_task():
    # The relaxation ignores that lighting needs the key *carried*: dropping is impossible,
    # so once the key is picked the robot can never be free again.
    domain, problem, types, _ = task_of(CORRIDOR, corridor_problem(goal="(and (carrying k) (free))"))
    for search in ("gbfs", "wastar"):
        assert solve(domain, problem, types, search=search, timeout=10).status == "unsolvable"


def test_gbfs_is_deterministic():
    loaded, prob = load_problem(os.path.join(DATA, "ipc", "depot", "task03.pddl"))
    first, second = (solve(loaded.domain, prob, loaded.types) for _ in range(2))
    assert first.status == "solved" and first.plan and second.plan == first.plan


def test_skeletons_are_distinct_valid_and_shortest_first():
    domain, problem, types, task = task_of(CORRIDOR, corridor_problem(goal="(carrying k)"))
    plans = [p for _, p in zip(range(6), iter_skeletons(task))]
    labels = [tuple(task.operators[o].label for o in p) for p in plans]
    assert len(set(labels)) == len(labels) == 6
    assert labels[0] == ("(move r0 r1)", "(pick k r1)")
    assert all(len(a) <= len(b) for a, b in zip(labels, labels[1:]))  # uniform costs, consistent here
    for plan in plans:
        steps = [(task.operators[o].name, task.operators[o].args) for o in plan]
        assert validate_plan(domain, problem, steps).ok


def test_optimistic_placeholders_chain_streams_up_to_the_level_bound():
    loaded, problem = load_problem(os.path.join(ROOT, "problems", "hook-use.pddl"))
    extended, placeholders = optimistic_problem(loaded.domain, problem, loaded.types, max_level=2)
    grasps = [p for p in placeholders.values() if p.stream == "sample-grasp"]
    assert sorted(p.inputs for p in grasps) == [("box",), ("hook",), ("table",)]
    motions = [p for p in placeholders.values() if p.stream == "plan-grasp-motion"]
    assert {p.level for p in motions} == {2} and len(motions) == 3
    assert all(placeholders[p.inputs[1]].stream == "sample-grasp" for p in motions)  # domain: valid-grasp
    _, shallow = optimistic_problem(loaded.domain, problem, loaded.types, max_level=1)
    assert all(p.level == 1 for p in shallow.values()) and len(shallow) < len(placeholders)
    grasp = next(p.name for p in grasps if p.inputs == ("box",))
    assert any(a.predicate == "valid-grasp" and [t.name for t in a.args] == ["box", grasp] for a in extended.init)


def test_hook_use_skeleton_is_enumerated_with_basis_operators():
    loaded, problem = load_problem(os.path.join(ROOT, "problems", "hook-use.pddl"),
                                   [load_domain([os.path.join(ROOT, "domains", "basis.pddl")])])
    extended, _ = optimistic_problem(loaded.domain, problem, loaded.types)
    task = ground(loaded.domain, extended, loaded.types, prune_irrelevant=False)
    names = []
    for _, plan in zip(range(100), iter_skeletons(task)):
        names.append(tuple(" ".join([task.operators[o].name] + [a for a in task.operators[o].args
                                                                 if not a.startswith("#")]) for o in plan))
    assert names[0] == ("grasp box table",)
    hook = ("grasp hook table", "move-cont hook box table", "place hook table", "grasp box table")
    assert hook in names


def test_grounding_respects_the_deadline():
    loaded, prob = load_problem(os.path.join(DATA, "ipc", "logistics00", "problem03.pddl"))
    result = solve(loaded.domain, prob, loaded.types, timeout=0.005)
    assert result.status == "timeout" and result.plan == []
    assert result.stats["operators"] == 0  # stopped inside grounding (~0.1 s here), before any search
