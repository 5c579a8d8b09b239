"""Every mistake a user can make in a .pddl file is one `FILE:LINE:COL: error: ...` line, exit 2."""
import os
import subprocess
import sys

import pytest

from pdsketch_mech.commands import check

from conftest import ROOT

DOMAIN = """(define (domain d)
  (:requirements :strips :typing)
  (:types block - object)
  (:predicates (on ?x - block ?y - block) (clear ?x - block))
  (:action stack
    :parameters (?x - block ?y - block)
    :precondition (and (clear ?x) (clear ?y))
    :effect (and (on ?x ?y) (not (clear ?y)))))
"""

PROBLEM = """(define (problem p)
  (:domain d)
  (:objects a b - block)
  (:init (clear a) (clear b))
  (:goal (on a b)))
"""


def run_check(capsys, *paths):
    status = check.main(["-q", *paths])
    return status, capsys.readouterr().err.strip()


def broken_domain(old: str, new: str) -> str:
    assert old in DOMAIN
    return DOMAIN.replace(old, new)


CASES = [
    # (what is wrong, the domain text, the message; line and column come from `at`)
    ("syntax: unclosed parenthesis", DOMAIN.rstrip()[:-1],
     "8:47: error: unexpected end of file; the '(' at line 1, column 1 is never closed"),
    ("syntax: misspelt section keyword", broken_domain("(:predicates", "(:predicate"),
     "4:4: error: unexpected ':predicate' (did you mean ':predicates'?); expected one of ':action', "
     "':constants', ':extends', ':mechanism', ':predicates', ':requirements', ':stream', ':types', "
     "':value-types', ':vocabulary'"),
    ("syntax: misspelt action property", broken_domain(":effect", ":efect"),
     "8:5: error: unexpected ':efect' (did you mean ':effect'?); expected one of ')', ':effect', "
     "':parameters', ':precondition'"),
    ("unsupported requirement", broken_domain(":typing", ":typing :fluents"),
     "2:34: error: unsupported requirement ':fluents'"),
    ("unknown predicate", broken_domain("(clear ?x) (clear ?y))", "(clear ?x) (clean ?y))"),
     "7:35: error: unknown predicate 'clean' (did you mean 'clear'?); known: on, clear"),
    ("unknown type", broken_domain("(?x - block ?y - block)\n", "(?x - blok ?y - block)\n"),
     "6:18: error: unknown type 'blok' (did you mean 'block'?)"),
    ("wrong arity", broken_domain("(on ?x ?y)", "(on ?x)"),
     "8:18: error: predicate 'on' takes 2 arguments, got 1"),
    ("unbound variable", broken_domain("(not (clear ?y))", "(not (clear ?z))"),
     "8:41: error: unbound variable ?z"),
    ("duplicate predicate", broken_domain("(clear ?x - block))", "(clear ?x - block) (on ?a ?b))"),
     "4:62: error: predicate 'on' is already defined (first defined at {d}:4:16)"),
    ("'or' in an effect", broken_domain("(and (on ?x ?y) (not (clear ?y)))", "(or (on ?x ?y))"),
     "8:13: error: 'or' is not allowed in an effect; effects are atoms, (not atom), and, forall and when"),
    ("unknown parent type", broken_domain("block - object", "block - thing"),
     "3:11: error: unknown parent type 'thing' of type 'block'"),
    ("duplicate parameter", broken_domain("(?x - block ?y - block)\n", "(?x - block ?x - block)\n"),
     "6:29: error: parameter ?x appears twice in action 'stack'"),
]


@pytest.mark.parametrize("text,message", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_domain_error_is_one_exact_line(write_files, capsys, text, message):
    (path,) = write_files(**{"d.pddl": text})
    status, err = run_check(capsys, path)
    assert status == 2
    assert err == f"{path}:{message.format(d=path)}"


def test_unknown_predicate_in_a_goal_lists_the_known_ones_without_a_close_match(write_files, capsys):
    unknown = PROBLEM.replace("(:goal (on a b))", "(:goal (over a b))")
    domain, problem = write_files(**{"d.pddl": DOMAIN, "p.pddl": unknown})
    status, err = run_check(capsys, domain, problem)
    assert (status, err) == (2, f"{problem}:5:10: error: unknown predicate 'over'; known: on, clear")


def test_a_long_list_of_known_predicates_is_shortened(write_files, capsys):
    names = [f"p{i}" for i in range(15)]
    many = DOMAIN.replace("(clear ?x - block))", "(clear ?x - block) " + " ".join(f"({n})" for n in names) + ")")
    unknown = PROBLEM.replace("(:goal (on a b))", "(:goal (over a b))")
    domain, problem = write_files(**{"d.pddl": many, "p.pddl": unknown})
    status, err = run_check(capsys, domain, problem)
    assert status == 2
    assert err.endswith("unknown predicate 'over'; known: on, clear, p0, p1, p2, p3, p4, p5, p6, p7, p8, p9, "
                        "... (5 more)")


def test_argument_of_wrong_type(write_files, capsys):
    text = broken_domain("(:types block - object)", "(:types block table - object)")
    text = text.replace("(clear ?x - block))", "(clear ?x - block) (free ?t - table))")
    text = text.replace("(clear ?x) (clear ?y))", "(clear ?x) (free ?y))")
    (path,) = write_files(**{"d.pddl": text})
    status, err = run_check(capsys, path)
    assert (status, err) == (2, f"{path}:7:41: error: argument 1 of predicate 'free' must be of type "
                                "'table', but ?y is of type 'block'")


MECHANISM = """(define (domain m)
  (:extends "d.pddl")
  (:mechanism stack-twice
    :parameters (?a - block ?b - block)
    :certified (on ?a ?b)
    :actions ((stak ?a ?b))))
"""


def test_mechanism_step_naming_a_missing_operator(write_files, capsys):
    _, path = write_files(**{"d.pddl": DOMAIN, "m.pddl": MECHANISM})
    status, err = run_check(capsys, path)
    assert (status, err) == (2, f"{path}:6:15: error: mechanism step names unknown operator 'stak' "
                                "(did you mean 'stack'?)")


def test_mechanism_step_with_wrong_arity(write_files, capsys):
    _, path = write_files(**{"d.pddl": DOMAIN, "m.pddl": MECHANISM.replace("(stak ?a ?b)", "(stack ?a)")})
    status, err = run_check(capsys, path)
    assert (status, err) == (2, f"{path}:6:15: error: operator 'stack' takes 2 arguments, got 1")


def test_extends_a_missing_file(write_files, capsys):
    (path,) = write_files(**{"m.pddl": MECHANISM})
    status, err = run_check(capsys, path)
    missing = os.path.join(os.path.dirname(path), "d.pddl")
    assert (status, err) == (2, f"{path}:1:1: error: extended domain file 'd.pddl' not found "
                                f"(looked for {missing})")


def test_stream_output_must_be_a_value_type(write_files, capsys):
    text = DOMAIN.rstrip()[:-1] + """
  (:stream sample-block :inputs (?x - block) :outputs (?y - block) :certified (on ?x ?y)))"""
    (path,) = write_files(**{"d.pddl": text})
    status, err = run_check(capsys, path)
    assert (status, err) == (2, f"{path}:9:56: error: output ?y of stream 'sample-block' has type 'block', "
                                "which is not a value type (declare it in :value-types)")


@pytest.mark.parametrize("old,new,message", [
    ("(clear a) (clear b)", "(clear a) (clear c)", "4:27: error: unknown object 'c'"),
    ("(on a b)", "(on a)", "5:10: error: predicate 'on' takes 2 arguments, got 1"),
    ("(:objects a b - block)", "(:objects a b a - block)", "3:17: error: object 'a' is declared twice"),
    ("(:domain d)", "(:domain e)",
     "1:1: error: no domain named 'e' (domains: d; none of the domain files beside the problem declares it: {d})"),
], ids=["unknown object", "wrong arity in goal", "duplicate object", "unknown domain"])
def test_problem_errors(write_files, capsys, old, new, message):
    domain, problem = write_files(**{"d.pddl": DOMAIN, "p.pddl": PROBLEM.replace(old, new)})
    status, err = run_check(capsys, domain, problem)
    assert (status, err) == (2, f"{problem}:{message.format(d=domain)}")


def test_a_problem_beside_a_fragment_of_its_domain_says_which_files_to_give(write_files, capsys):
    """The problem names the domain the fragment extends; the fragment declares its own name,
    so it is not found beside the problem by name: the error says what to give instead."""
    base, fragment, problem = write_files(**{
        "base__d.pddl": DOMAIN, "frag.pddl": '(define (domain frag) (:extends "base/d.pddl"))', "p.pddl": PROBLEM})
    status, err = run_check(capsys, problem)
    assert (status, err) == (2, f"{problem}:1:1: error: no domain named 'd' (domains: none given); beside the problem, "
                                f"{fragment} is a fragment of domain 'frag' that extends it: give that fragment, "
                                f"or {base}, which declares 'd'")
    assert check.main([fragment, problem]) == 0


def test_a_failing_domain_is_the_only_error_for_its_problem(write_files, capsys):
    """The problem's domain is the fragment that failed: its 'no domain named' would only mislead."""
    fragment, problem = write_files(**{
        "frag.pddl": '(define (domain frag) (:extends "d.pddl") (:predicates (clear ?x - blok)))',
        "p.pddl": PROBLEM})
    status, err = run_check(capsys, fragment, problem)
    assert status == 2 and err.splitlines() == [f"{fragment}:1:1: error: extended domain file 'd.pddl' not found "
                                                f"(looked for {os.path.dirname(fragment)}/d.pddl)"]


SCENE = """
  (:scene
    (a :asset "block/0" :position (0.5 0 0.02))
    (b :asset "block/1" :position (0.6 0 0.02) :rpy-deg (0 0 90))))"""


@pytest.mark.parametrize("old,new,message", [
    ('(b :asset', '(c :asset', "8:5: error: scene object 'c' is not declared in :objects"),
    (':rpy-deg (0 0 90)', ':colour (1 0 0 1)',
     "8:48: error: scene object 'b': unknown property ':colour' (did you mean ':color'?); expected one of "
     ":asset, :position, :quat, :rpy, :rpy-deg, :fixed, :mass, :friction, :scale, :on, :color"),
    (':position (0.5 0 0.02)', ':position (0.5)',
     "7:25: error: scene object 'a': :position must be a vector (x y z) in metres, or (x y) with :on"),
    (':position (0.5 0 0.02)', ':position (0.5 0)',
     "7:25: error: scene object 'a': :position (x y) gives no z, so it needs :on SUPPORT to rest on; or give "
     "(x y z)"),
    (':rpy-deg (0 0 90)', ':rpy-deg (0 0 90) :quat (0 0 0 1)',
     "8:66: error: scene object 'b': give one orientation, not both :rpy-deg and :quat"),
    ('(a :asset "block/0" ', '(a ', "7:5: error: scene object 'a' has no :asset (an asset name string, e.g. \"block/0\")"),
], ids=["undeclared object", "unknown property", "short position", "position without z or support",
        "two orientations", "missing asset"])
def test_scene_errors(write_files, capsys, old, new, message):
    text = PROBLEM.rstrip()[:-1] + SCENE
    assert old in text
    domain, problem = write_files(**{"d.pddl": DOMAIN, "p.pddl": text.replace(old, new)})
    status, err = run_check(capsys, domain, problem)
    assert (status, err) == (2, f"{problem}:{message}")


def test_unreadable_file(capsys, tmp_path):
    missing = str(tmp_path / "nope.pddl")
    status, err = run_check(capsys, missing)
    assert (status, err) == (2, f"{missing}: error: cannot read file: No such file or directory")


def test_command_line_prints_no_traceback(write_files):
    (path,) = write_files(**{"d.pddl": broken_domain("(on ?x ?y)", "(on ?x)")})
    result = subprocess.run([sys.executable, "-m", "pdsketch_mech.check", path],
                            capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == 2
    assert result.stdout == ""
    assert result.stderr.splitlines() == [f"{path}:8:18: error: predicate 'on' takes 2 arguments, got 1"]


def test_clean_files_exit_zero(write_files, capsys):
    domain, problem = write_files(**{"d.pddl": DOMAIN, "p.pddl": PROBLEM})
    assert check.main([domain, problem]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out == [f"{domain}: ok: domain 'd': 1 type, 2 predicates, 1 action, 0 streams, 0 mechanisms",
                   f"{problem}: ok: problem 'p' for domain 'd': 2 objects, 2 initial facts"]


def test_an_unknown_or_conflicting_vocabulary_is_one_located_line(write_files, capsys):
    unknown = '(define (domain cranes)\n  (:extends "basis")\n  (:requirements :streams)\n)\n'
    plain = ('(define (domain cranes)\n  (:vocabulary cranes)\n  (:requirements :streams)\n  (:value-types g)\n'
             '  (:predicates (ok ?x - g))\n  (:stream s :outputs (?x - g) :certified (ok ?x) :sampler "grasp")\n)\n')
    fragment, alone = write_files(**{"f.pddl": unknown.replace("(:requirements :streams)", "(:vocabulary cranes)"),
                                     "a.pddl": plain})
    status, err = run_check(capsys, fragment)
    assert (status, err) == (2, f"{fragment}:3:16: error: vocabulary 'cranes' differs from 'basis', the vocabulary "
                                 "of domain 'mech-basis' that this domain extends")
    status, err = run_check(capsys, alone)
    assert (status, err) == (2, f"{alone}:2:16: error: unknown vocabulary 'cranes'; known: basis")
