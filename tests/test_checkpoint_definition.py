"""A checkpoint serves the definition it was trained for and any that only narrows it:
object parameters renamed, preconditions added. Anything else is refused."""
import hashlib

from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.samplers.learned.definition import definition_text, mechanism_hash, serves

TRAINED = """(define (domain push) (:requirements :mechanisms)
  (:mechanism push-off
    :parameters (?tool ?target ?support ?object - item ?g - grasp ?c - contact ?t - traj)
    :precondition (and (handempty) (support ?target ?support) (not (= ?tool ?target)))
    :certified (support ?target ?object)
    :actions ((grasp ?tool ?support ?g ?t) (move-cont ?tool ?target ?support ?c ?t))))"""
VALUES = {"?g", "?c", "?t"}


def _mechanism(text: str):
    return parse_text(text, "<test>").mechanisms[0]


def _trained():
    mechanism = _mechanism(TRAINED)
    return definition_text(mechanism), mechanism_hash(mechanism)


def _variant(old: str, new: str):
    assert old in TRAINED
    return _mechanism(TRAINED.replace(old, new))


def test_the_definition_it_was_trained_for_is_served_with_or_without_its_own_text():
    text, digest = _trained()
    assert serves(text, digest, _mechanism(TRAINED), VALUES)
    assert serves(None, digest, _mechanism(TRAINED), VALUES)   # older checkpoints record the hash only


def test_an_object_parameter_renamed_and_preconditions_added_are_served():
    text, digest = _trained()
    landing = _mechanism(TRAINED.replace("?object", "?landing").replace(
        "(not (= ?tool ?target)))", "(not (= ?tool ?target)) (fixed ?landing) (not (= ?landing ?support)))"))
    assert serves(text, digest, landing, VALUES)


def test_anything_that_changes_what_the_classifiers_saw_is_refused():
    text, digest = _trained()
    refused = {
        "a precondition dropped": _variant(" (not (= ?tool ?target))", ""),
        "other certified facts": _variant("(support ?target ?object)", "(holding ?target)"),
        "another step": _variant("(move-cont ?tool ?target ?support ?c ?t)", "(transit-cont ?target ?support ?c ?t)"),
        "a value renamed": _mechanism(TRAINED.replace("?c", "?c1")),
        "parameters reordered": _variant("?tool ?target ?support ?object - item", "?target ?tool ?support ?object - item"),
    }
    for what, mechanism in refused.items():
        assert not serves(text, digest, mechanism, VALUES), what


def test_a_recorded_definition_that_does_not_match_its_hash_is_not_trusted():
    text, _ = _trained()
    landing = _mechanism(TRAINED.replace("?object", "?landing"))
    assert not serves(text, "0" * 64, landing, VALUES)
    assert not serves(text.replace("(handempty) ", ""), mechanism_hash(_mechanism(TRAINED)), landing, VALUES)


def test_a_recorded_definition_that_is_not_text_is_not_trusted_and_raises_nothing():
    landing = _mechanism(TRAINED.replace("?object", "?landing"))
    for broken in (12, ["(:mechanism"], {"a": 1}, "(:mechanism push-off", "((((((" * 2000):
        digest = hashlib.sha256(broken.encode()).hexdigest() if isinstance(broken, str) else "0" * 64
        assert not serves(broken, digest, landing, VALUES)
