"""Text edits of domain files (lang/edit.py): `learn train` names its checkpoint in a fragment
without touching the user's comments or layout."""
from pdsketch_mech.lang.edit import set_mechanism_sampler
from pdsketch_mech.lang.parser import parse_text

FRAGMENT = """; header
(define (domain my-com) ; inline note
  (:requirements :mechanisms)
  ; a note inside the definition, with a ")" and a :sampler "fake" in it
  (:mechanism my-com
    :parameters (?t - item ?g - grasp)
    :precondition (handempty)
    :certified (holding ?t)
    :actions ((grasp ?t table ?g t1)))  ; trailing note
  )
"""


def mechanism_of(text):
    return parse_text(text, file="my-com.pddl").mechanisms[0]


def test_naming_a_checkpoint_keeps_every_comment_and_line_and_changes_only_the_sampler():
    named = set_mechanism_sampler(FRAGMENT, mechanism_of(FRAGMENT), "my-com.samplers.safetensors")
    assert mechanism_of(named).sampler == "my-com.samplers.safetensors"
    assert named.replace('\n    :sampler "my-com.samplers.safetensors"', "", 1) == FRAGMENT  # nothing else moved
    renamed = set_mechanism_sampler(named, mechanism_of(named), "other.safetensors")
    assert renamed == named.replace("my-com.samplers.safetensors", "other.safetensors")
    assert mechanism_of(renamed).sampler == "other.safetensors"
