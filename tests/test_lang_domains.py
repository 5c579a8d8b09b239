"""The project's own language files and the parser's semantics: basis operators, mechanisms,
fragments (`:extends`), scenes, case-insensitivity and locations."""
import math
import os

import pytest

from pdsketch_mech.lang import nodes as n
from pdsketch_mech.lang.errors import PddlError
from pdsketch_mech.lang.loader import load_domain, load_problem
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.lang.scene import build_scene

from conftest import ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")
HOOK = os.path.join(ROOT, "domains", "mechanisms", "hook-use.pddl")


def test_basis_has_the_six_operators_with_continuous_parameters():
    loaded = load_domain([BASIS])
    actions = {a.name: a for a in loaded.domain.actions}
    assert set(actions) == {"transit", "transit-cont", "grasp", "place", "move", "move-cont"}
    value_params = {name: [p.type for p in a.parameters if loaded.types.is_value(p.type)]
                    for name, a in actions.items()}
    assert value_params["grasp"] == ["grasp", "traj"]
    assert value_params["place"] == ["placement", "traj"]
    assert value_params["move-cont"] == ["contact", "traj"]
    assert [p.type for p in actions["move-cont"].parameters][:3] == ["item", "item", "item"]


def test_basis_streams_name_the_generic_samplers():
    domain = load_domain([BASIS]).domain
    from pdsketch_mech.samplers.registry import GENERIC_SAMPLERS
    samplers = {s.sampler for s in domain.streams}
    assert samplers == {"grasp", "placement", "contact", "free-motion", "grasp-motion", "place-motion",
                        "held-motion", "push-motion"}
    assert samplers <= set(GENERIC_SAMPLERS), "every stream's sampler is registered"
    grasp = next(s for s in domain.streams if s.name == "sample-grasp")
    assert [o.type for o in grasp.outputs] == ["grasp"]
    assert grasp.certified == n.Atom("valid-grasp", (n.Var("?x"), n.Var("?g")))


def test_hook_use_mechanism_extends_the_basis():
    loaded = load_domain([HOOK])
    assert loaded.domain.name == "mech-basis" and loaded.names == {"mech-basis", "hook-use"}
    assert [os.path.basename(f) for f in loaded.files] == ["basis.pddl", "hook-use.pddl"]
    (mechanism,) = loaded.domain.mechanisms
    assert [step.name for step in mechanism.actions] == ["grasp", "move-cont", "place", "grasp"]
    assert mechanism.certified == n.Atom("holding", (n.Var("?target"),))
    assert mechanism.actions[1].args[:3] == (n.Var("?tool"), n.Var("?target"), n.Var("?support"))


def test_fragments_merge_when_passed_together(write_files):
    fragment = open(HOOK).read().replace('(:extends "../basis.pddl")', "")
    fragment = fragment.replace('\n    :sampler "hook-use.samplers.safetensors"', "")  # its checkpoint stays behind
    (path,) = write_files(**{"frag.pddl": fragment})
    loaded = load_domain([BASIS, path])
    assert [m.name for m in loaded.domain.mechanisms] == ["hook-use"]
    with pytest.raises(PddlError, match="unknown operator 'grasp'|unknown type 'item'"):
        load_domain([path])


def test_a_file_extended_twice_is_merged_once(write_files):
    base = "(define (domain base) (:predicates (p)) (:action a :effect (p)))"
    left = '(define (domain left) (:extends "base.pddl") (:action b :precondition (p)))'
    right = '(define (domain right) (:extends "base.pddl") (:action c :precondition (p)))'
    _, left_path, right_path = write_files(**{"base.pddl": base, "left.pddl": left, "right.pddl": right})
    loaded = load_domain([left_path, right_path])
    assert [a.name for a in loaded.domain.actions] == ["a", "b", "c"]


def test_extends_cycle_is_an_error(write_files):
    a = '(define (domain a) (:extends "b.pddl"))'
    b = '(define (domain b) (:extends "a.pddl"))'
    path, _ = write_files(**{"a.pddl": a, "b.pddl": b})
    with pytest.raises(PddlError, match="extended in a cycle"):
        load_domain([path])


def test_duplicate_action_across_fragments_points_at_the_second(write_files):
    fragment = '(define (domain f) (:extends "basis.pddl") (:action grasp :parameters ()))'
    text = open(BASIS).read()
    _, path = write_files(**{"basis.pddl": text, "f.pddl": fragment})
    with pytest.raises(PddlError) as error:
        load_domain([path])
    assert str(error.value).startswith(f"{path}:1:44: error: action 'grasp' is already defined (first defined at ")


def test_hook_problem_scene():
    domain, problem = load_problem(os.path.join(ROOT, "problems", "hook-use.pddl"), [load_domain([HOOK])])
    scene = {o.name: o for o in build_scene(problem)}
    assert set(scene) == {"table", "hook", "box"}
    assert scene["table"].fixed and not scene["box"].fixed
    assert scene["box"].mass == 0.2 and scene["box"].support == "table"
    assert scene["hook"].orientation == (0.0, 0.0, 0.0, 1.0) and scene["hook"].asset == "l-stick/0"


def test_scene_orientation_forms_agree():
    text = """(define (problem p) (:domain d) (:objects a b c - item)
      (:scene (a :asset "x" :position (0 0 0) :rpy (0 0 1.5707963267948966))
              (b :asset "x" :position (0 0 0) :rpy-deg (0 0 90))
              (c :asset "x" :position (0 0 0) :quat (0 0 0.7071067811865476 0.7071067811865476) :scale 2)))"""
    a, b, c = build_scene(parse_text(text))
    for other in (b, c):
        assert all(math.isclose(p, q, abs_tol=1e-9) for p, q in zip(a.orientation, other.orientation))
    assert c.scale == (2.0, 2.0, 2.0) and a.scale == (1.0, 1.0, 1.0)


def test_names_are_case_insensitive_and_keywords_can_be_names():
    upper = parse_text("(DEFINE (DOMAIN Domain) (:TYPES Object2 And-Box - OBJECT)"
                       " (:Predicates (ON ?X - And-Box)) (:Action Lift :Parameters (?B - and-box)"
                       " :Precondition (On ?b) :Effect (NOT (on ?B))))")
    lower = parse_text("(define (domain domain) (:types object2 and-box - object)"
                       " (:predicates (on ?x - and-box)) (:action lift :parameters (?b - and-box)"
                       " :precondition (on ?b) :effect (not (on ?b))))")
    assert upper == lower


def test_strings_keep_case_and_comments_are_ignored():
    problem = parse_text("""; header comment
      (define (problem p) ; trailing comment
        (:domain d) (:objects a) (:init) (:goal (and))
        (:scene (a :asset "Block/0;not-a-comment" :position (0 0 0))))""")
    assert problem.scene[0].props[0].value == "Block/0;not-a-comment"


def test_nodes_carry_their_source_location():
    domain = parse_text("(define (domain d)\n  (:predicates (p ?x))\n  (:action a :parameters (?x)\n"
                        "    :precondition (p ?x)))", "f.pddl")
    assert domain.actions[0].loc == n.Loc("f.pddl", 3, 3)
    assert domain.actions[0].precondition.loc == n.Loc("f.pddl", 4, 19)
    assert domain.actions[0].precondition.args[0].loc == n.Loc("f.pddl", 4, 22)


def test_a_domain_file_given_as_a_problem_is_reported(write_files):
    (path,) = write_files(**{"d.pddl": "(define (domain d))"})
    with pytest.raises(PddlError, match="expected a problem definition, found domain 'd'"):
        load_problem(path)


def test_problem_finds_its_domain_beside_it():
    folder = os.path.join(ROOT, "tests", "data", "ipc", "blocks")
    problem = sorted(f for f in os.listdir(folder) if f != "domain.pddl" and f.endswith(".pddl"))[0]
    domain, _ = load_problem(os.path.join(folder, problem))
    assert os.path.basename(domain.files[0]) == "domain.pddl"


def test_a_stream_without_outputs_is_a_test(write_files):
    text = open(BASIS).read().rstrip()[:-1] + """
  (:stream test-cfree
    :inputs (?x - item ?g - grasp ?y - item)
    :domain (valid-grasp ?x ?g)
    :certified (touching ?x ?y)
    :sampler "collision-free"))"""
    (path,) = write_files(**{"basis.pddl": text})
    stream = load_domain([path]).domain.streams[-1]
    assert stream.name == "test-cfree" and stream.outputs == () and stream.sampler == "collision-free"


def test_a_stream_with_outputs_must_certify_them(write_files):
    text = open(BASIS).read().replace(":certified (valid-grasp ?x ?g)\n", "")
    (path,) = write_files(**{"basis.pddl": text})
    with pytest.raises(PddlError, match="stream 'sample-grasp' certifies nothing"):
        load_domain([path])
