"""The plan validator: an independent oracle that runs plans on the syntax tree."""
import os

import pytest

from pdsketch_mech.lang.loader import load_problem
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.lang.typecheck import check_domain, check_problem
from pdsketch_mech.symbolic.validate import ValidationResult, validate_plan

from conftest import DATA

# ----------------------------------------------------------------------------- blocks (IPC)
BLOCKS_P01 = os.path.join(DATA, "ipc", "blocks", "p01.pddl")

# Init: b4 on b2 on b3 on b5 on b1 (on the table). Goal: b4, b2 on the table; b3 on b1 on b5.
BLOCKS_PLAN = [
    ("unstack", ("b4", "b2")), ("put-down", ("b4",)),
    ("unstack", ("b2", "b3")), ("put-down", ("b2",)),
    ("unstack", ("b3", "b5")), ("put-down", ("b3",)),
    ("unstack", ("b5", "b1")), ("put-down", ("b5",)),
    ("pick-up", ("b1",)), ("stack", ("b1", "b5")),
    ("pick-up", ("b3",)), ("stack", ("b3", "b1")),
]


@pytest.fixture(scope="module")
def blocks():
    loaded, problem = load_problem(BLOCKS_P01)
    return loaded.domain, problem


def test_valid_blocks_plan_is_accepted(blocks):
    result = validate_plan(*blocks, BLOCKS_PLAN)
    assert result.ok, result.message
    assert result.message == "plan valid: 12 steps reach the goal"
    assert result.failed_step is None
    assert result.final_state == frozenset({
        ("handempty",), ("clear", "b4"), ("ontable", "b4"), ("clear", "b2"), ("ontable", "b2"),
        ("clear", "b3"), ("on", "b3", "b1"), ("on", "b1", "b5"), ("ontable", "b5"),
    })


def test_plan_names_are_case_insensitive(blocks):
    plan = [(name.upper(), tuple(a.upper() for a in args)) for name, args in BLOCKS_PLAN]
    assert validate_plan(*blocks, plan).ok


def test_failing_precondition_names_the_step_and_the_atom(blocks):
    plan = BLOCKS_PLAN[:2] + BLOCKS_PLAN[3:]  # skip `unstack b2 b3`: then `put-down b2` fails
    result = validate_plan(*blocks, plan)
    assert not result.ok
    assert result.failed_step == 3
    assert result.message == "step 3 (put-down b2): precondition does not hold: (holding b2) is false"
    # the state reached before the failing step
    assert ("ontable", "b4") in result.final_state and ("on", "b2", "b3") in result.final_state


def test_plan_that_misses_the_goal_is_rejected_without_a_step(blocks):
    result = validate_plan(*blocks, BLOCKS_PLAN[:-1])
    assert not result.ok
    assert result.failed_step is None
    assert result.message == "goal does not hold after 11 steps: (clear b3) is false"
    assert ("holding", "b3") in result.final_state


def test_empty_plan_checks_the_goal(blocks):
    result = validate_plan(*blocks, [])
    assert not result.ok and result.failed_step is None
    assert result.message.startswith("goal does not hold after 0 steps: ")


@pytest.mark.parametrize("step,message", [
    (("fly", ("b4",)), "step 2 (fly b4): unknown action 'fly'"),
    (("put-down", ()), "step 2 (put-down): action 'put-down' takes 1 argument(s), got 0"),
    (("put-down", ("b4", "b2")), "step 2 (put-down b4 b2): action 'put-down' takes 1 argument(s), got 2"),
    (("put-down", ("b9",)), "step 2 (put-down b9): argument 1 'b9' is not a known object"),
])
def test_malformed_steps_are_rejected(blocks, step, message):
    result = validate_plan(*blocks, [BLOCKS_PLAN[0], step])
    assert not result.ok
    assert result.failed_step == 2
    assert result.message == message


# ----------------------------------------------------------------------------- an inline ADL domain
LIGHTS = """(define (domain lights)
  (:requirements :adl :typing)
  (:types room device - object lamp - device)
  (:constants hall porch - room)
  (:predicates (at ?r - room) (in ?d - device ?r - room) (on ?d - device) (locked ?r - room) (done))
  (:action move
    :parameters (?from - room ?to - room)
    :precondition (and (at ?from) (not (= ?from ?to)) (not (locked ?to)))
    :effect (and (not (at ?from)) (at ?to)))
  (:action toggle
    :parameters (?d - device)
    :precondition (exists (?r - room) (and (at ?r) (in ?d ?r)))
    :effect (and (when (on ?d) (not (on ?d))) (when (not (on ?d)) (on ?d))))
  (:action relight
    :parameters (?d - lamp)
    :precondition (on ?d)
    :effect (and (not (on ?d)) (on ?d)))
  (:action all-off
    :parameters ()
    :effect (forall (?d - device) (not (on ?d))))
  (:action finish
    :parameters ()
    :precondition (and (forall (?d - device) (not (on ?d))) (or (at hall) (at porch)))
    :effect (done)))
"""

LIGHTS_PROBLEM = """(define (problem p)
  (:domain lights)
  (:objects r1 r2 r3 - room l1 l2 - lamp fan - device)
  (:init (at r1) (in l1 r2) (in l2 r1) (in fan hall) (on l2) (on fan) (locked r3))
  (:goal {goal}))
"""


def lights(goal: str = "(done)"):
    domain = parse_text(LIGHTS)
    problem = parse_text(LIGHTS_PROBLEM.format(goal=goal))
    check_problem(problem, domain, check_domain(domain))  # the inline texts are well-formed
    return domain, problem


def run(plan, goal: str = "(done)") -> ValidationResult:
    return validate_plan(*lights(goal), [(name, tuple(args.split())) for name, args in plan])


def test_forall_effect_and_forall_precondition():
    result = run([("all-off", ""), ("move", "r1 hall"), ("finish", "")])
    assert result.ok, result.message
    assert result.final_state == frozenset({("at", "hall"), ("in", "l1", "r2"), ("in", "l2", "r1"),
                                            ("in", "fan", "hall"), ("locked", "r3"), ("done",)})


def test_forall_precondition_reports_the_counterexample():
    result = run([("move", "r1 hall"), ("finish", "")])
    assert result.failed_step == 2
    assert result.message == "step 2 (finish): precondition does not hold: (on l2) is true"


def test_disjunctive_precondition():
    result = run([("all-off", ""), ("finish", "")])  # still in r1: neither hall nor porch
    assert result.failed_step == 2
    assert "precondition does not hold" in result.message and "(or (at hall) (at porch))" in result.message


def test_exists_precondition():
    assert run([("toggle", "l2")]).ok is False  # the goal fails, but the step itself is fine
    assert run([("toggle", "l2")]).failed_step is None
    result = run([("toggle", "l1")])  # l1 is in r2, we are in r1
    assert result.failed_step == 1
    assert result.message.startswith("step 1 (toggle l1): precondition does not hold")


def test_conditional_effects_are_judged_in_the_pre_state():
    once = run([("toggle", "l2")])
    assert ("on", "l2") not in once.final_state
    twice = run([("toggle", "l2"), ("toggle", "l2")])
    assert ("on", "l2") in twice.final_state
    assert twice.final_state - {("on", "l2")} == once.final_state


def test_add_wins_over_delete_of_the_same_atom():
    result = run([("relight", "l2")], goal="(on l2)")
    assert result.ok, result.message
    assert ("on", "l2") in result.final_state


def test_negative_precondition():
    result = run([("move", "r1 r3")])
    assert result.failed_step == 1
    assert result.message == "step 1 (move r1 r3): precondition does not hold: (locked r3) is true"


def test_equality_precondition():
    result = run([("move", "r1 r1")])
    assert result.failed_step == 1
    assert result.message == "step 1 (move r1 r1): precondition does not hold: (not (= r1 r1)) is false"


def test_domain_constants_are_objects():
    result = run([("all-off", ""), ("move", "r1 porch"), ("finish", "")])
    assert result.ok, result.message
    assert ("at", "porch") in result.final_state


def test_subtype_argument_is_accepted():
    # toggle takes a device; l2 is a lamp, a subtype of device
    assert run([("toggle", "l2")], goal="(not (on l2))").ok


@pytest.mark.parametrize("name,args,message", [
    ("toggle", "r1", "argument 1 'r1' is of type 'room', but ?d must be of type 'device'"),
    ("relight", "fan", "argument 1 'fan' is of type 'device', but ?d must be of type 'lamp'"),
    ("move", "r1 l1", "argument 2 'l1' is of type 'lamp', but ?to must be of type 'room'"),
])
def test_argument_of_wrong_type_is_rejected(name, args, message):
    result = run([(name, args)])
    assert not result.ok
    assert result.failed_step == 1
    assert result.message == f"step 1 ({name} {args}): {message}"


@pytest.mark.parametrize("goal,ok", [
    ("(exists (?r - room) (locked ?r))", True),
    ("(forall (?d - lamp) (on ?d))", False),
    ("(imply (on l1) (at r2))", True),
    ("(imply (on l2) (at r2))", False),
    ("(and (on fan) (not (= l1 l2)))", True),
])
def test_goal_formulas(goal, ok):
    result = run([], goal=goal)
    assert result.ok is ok, result.message
