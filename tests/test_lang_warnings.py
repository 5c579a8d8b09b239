"""Accepted oddities are one `FILE:LINE:COL: warning: ...` line on stderr, exit 0: a predicate
declaring a parameter name twice, as real IPC files do (logistics: `(in ?obj ?obj)`)."""
from pdsketch_mech.commands import check, plan

DOMAIN = """(define (domain tiny-logistics)
  (:requirements :strips)
  (:predicates (package ?p) (truck ?t) (at ?obj ?loc) (in ?obj ?obj))
  (:action load
    :parameters (?p ?t ?l)
    :precondition (and (package ?p) (truck ?t) (at ?p ?l) (at ?t ?l))
    :effect (and (in ?p ?t) (not (at ?p ?l)))))
"""

PROBLEM = """(define (problem load-one) (:domain tiny-logistics)
  (:objects pkg truck depot)
  (:init (package pkg) (truck truck) (at pkg depot) (at truck depot))
  (:goal (in pkg truck)))
"""

WARNING = "3:64: warning: parameter ?obj appears twice in predicate 'in'; accepted, as only a predicate's " \
          "parameter types matter"


def test_check_warns_about_a_repeated_predicate_parameter(write_files, capsys):
    domain, problem = write_files(**{"d.pddl": DOMAIN, "p.pddl": PROBLEM})
    assert check.main(["-q", domain, problem]) == 0
    assert capsys.readouterr().err.splitlines() == [f"{domain}:{WARNING}"]


def test_plan_warns_and_plans(write_files, capsys):
    domain, problem = write_files(**{"d.pddl": DOMAIN, "p.pddl": PROBLEM})
    assert plan.main([domain, problem]) == 0
    captured = capsys.readouterr()
    assert captured.out.splitlines() == ["(load pkg truck depot)"]
    err = captured.err.splitlines()
    assert err[0] == f"{domain}:{WARNING}" and err[1].startswith("solved: 1 steps")


def test_a_repeated_action_parameter_is_still_an_error(write_files, capsys):
    text = DOMAIN.replace(":parameters (?p ?t ?l)", ":parameters (?p ?t ?p)")
    (domain,) = write_files(**{"d.pddl": text})
    assert check.main(["-q", domain]) == 2
    assert capsys.readouterr().err.splitlines() == [f"{domain}:5:24: error: parameter ?p appears twice in "
                                                    "action 'load'"]
