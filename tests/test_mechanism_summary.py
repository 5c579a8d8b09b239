"""A freshly extracted mechanism's plain-words summary says what the planner will ground its
roles with: its precondition and what its steps' basis operators need."""
import os

from pdsketch_mech.lang.loader import load_domain
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.learning.summary import mechanism_summary

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BASIS_ACTIONS = load_domain([os.path.join(ROOT, "domains", "basis.pddl")]).domain.actions

TRAY_PULL = """(define (domain d) (:requirements :mechanisms)
  (:mechanism tray-pull
    :parameters (?pushed ?support ?target - item ?c - contact ?t1 - traj ?g - grasp ?t2 - traj)
    :precondition (and (handempty) (support ?pushed ?support) (support ?target ?pushed))
    :certified (holding ?target)
    :actions ((transit-cont ?pushed ?support ?c ?t1) (grasp ?target ?pushed ?g ?t2))))"""


def _summary(text):
    mechanism = parse_text(text, "<test>").mechanisms[0]
    return mechanism_summary(mechanism, {"?pushed": "plate", "?support": "table", "?target": "apple"},
                             BASIS_ACTIONS)


def test_roles_a_step_pushes_or_grasps_are_said_to_be_movable():
    lines = _summary(TRAY_PULL)
    assert "any movable object may be ?pushed, ?target; any object, fixed or not, may be ?support" in lines


def test_two_surfaces_one_of_which_rests_on_the_other_are_never_said_to_be_one_object():
    assert not any(line.startswith("may be one object or two") for line in _summary(TRAY_PULL))
    two_shelves = TRAY_PULL.replace("(support ?target ?pushed))", "(support ?target ?pushed) (support ?c2 ?shelf))") \
        .replace("?target - item", "?target ?c2 ?shelf - item")
    assert "may be one object or two: ?pushed and ?shelf, ?shelf and ?support" in _summary(two_shelves)


def test_without_the_basis_operators_only_the_precondition_speaks():
    mechanism = parse_text(TRAY_PULL, "<test>").mechanisms[0]
    assert "any object, fixed or not, may be ?pushed, ?support, ?target" in mechanism_summary(mechanism, {
        "?pushed": "plate", "?support": "table", "?target": "apple"})
