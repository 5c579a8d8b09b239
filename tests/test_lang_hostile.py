"""Hostile .pddl files: deep nesting, absurd numbers, impossible scenes, other encodings,
control characters and huge files are each one located error line (or accepted), never a
traceback."""
import subprocess
import sys
import time

import pytest

from pdsketch_mech.commands import check, plan
from pdsketch_mech.lang.errors import PddlError
from pdsketch_mech.lang.nodes import Loc
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.lang.scene import quat_from_rpy
from pdsketch_mech.lang.source import MAX_NESTING

from conftest import ROOT
from test_lang_errors import PROBLEM  # the same two-block problem

DOMAIN = """(define (domain d)
  (:requirements :strips :typing :negative-preconditions :disjunctive-preconditions :existential-preconditions)
  (:types block - object)
  (:predicates (on ?x - block ?y - block) (clear ?x - block))
  (:action stack
    :parameters (?x - block ?y - block)
    :precondition {pre}
    :effect (and (on ?x ?y) (not (clear ?y)))))
"""
WRAPPERS = {"not": ("(not (not ", "))"), "and": ("(and ", ")"), "or": ("(or ", ")"),
            "exists": ("(exists (?v - block) ", ")"), "imply": ("(imply (clear ?x) ", ")")}


def nested(kind: str, depth: int) -> str:
    """A precondition `depth` formulas deep (a `not` pair counts two)."""
    opening, closing = WRAPPERS[kind]
    times = depth // 2 if kind == "not" else depth
    return opening * times + "(clear ?x)" + closing * times


def run_check(capsys, *paths):
    status = check.main(["-q", *paths])
    return status, capsys.readouterr().err


# ----------------------------------------------------------------------------- nesting
@pytest.mark.parametrize("kind", sorted(set(WRAPPERS) - {"exists"}))
@pytest.mark.parametrize("depth", [400, MAX_NESTING - 4])  # the limit counts define and action too
def test_deep_formulas_check_plan_and_validate(write_files, capsys, kind, depth):
    domain, problem = write_files(**{"d.pddl": DOMAIN.format(pre=nested(kind, depth)), "p.pddl": PROBLEM})
    assert run_check(capsys, domain, problem) == (0, "")
    assert plan.main([domain, problem, "--validate", "--search", "wastar"]) == 0
    assert "validate: plan valid" in capsys.readouterr().err


def test_400_nested_quantifiers_are_refused_by_check_and_plan(write_files, capsys):
    domain, problem = write_files(**{"d.pddl": DOMAIN.format(pre=nested("exists", 400)), "p.pddl": PROBLEM})
    status, err = run_check(capsys, domain, problem)  # 2^400 groundings: refused, not attempted
    assert status == 2 and err.startswith(f"{problem}:1:1: error: the problem grounds to about 1e121 atoms "
                                          "for action (stack ?x ?y); the limit is 5e6 (--max-ground N)")
    assert plan.main([domain, problem]) == 2
    assert capsys.readouterr().err == err


def test_400_nested_quantifiers_within_the_limit_are_a_located_error_when_planning(write_files, capsys):
    domain, problem = write_files(**{"d.pddl": DOMAIN.format(pre=nested("exists", 400)), "p.pddl": PROBLEM})
    assert plan.main([domain, problem, "--max-ground", "1e300"]) == 2  # the grounder's own limit
    err = capsys.readouterr().err
    assert err.startswith(f"{domain}:7:") and err.endswith(": error: formula expands to more than 4096 alternatives\n")


@pytest.mark.parametrize("kind", sorted(WRAPPERS))
@pytest.mark.parametrize("depth", [MAX_NESTING, 100_000])
def test_deeper_nesting_is_one_located_error(write_files, capsys, kind, depth):
    (domain,) = write_files(**{"d.pddl": DOMAIN.format(pre=nested(kind, depth))})
    started = time.perf_counter()
    status, err = run_check(capsys, domain)
    assert status == 2 and time.perf_counter() - started < 5
    assert err.count("\n") == 1 and err.startswith(f"{domain}:7:")
    assert err.endswith(f": error: parentheses nest deeper than {MAX_NESTING} levels\n")


def test_nesting_error_points_at_the_first_parenthesis_too_deep():
    text = "(define (domain d) " + "(" * 600
    with pytest.raises(PddlError) as caught:
        parse_text(text, "f.pddl")
    assert str(caught.value) == f"f.pddl:1:{20 + MAX_NESTING - 1}: error: parentheses nest deeper than 500 levels"


def test_parentheses_in_comments_and_strings_do_not_count():
    text = '; ' + "(" * 1000 + '\n(define (problem p) (:domain d) (:scene (a :asset "' + "(" * 1000 + '")))'
    assert parse_text(text).scene[0].props[0].value == "(" * 1000


# ----------------------------------------------------------------------------- numbers
SCENE = """(define (problem p) (:domain d)
  (:objects table a b c - block)
  (:init)
  (:goal (and))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (a :asset "block/0" :position (0.5 0 0.026) {a})
    (b :asset "block/0" :position (0.5 0.2 0.026) {b})
    (c :asset "block/0" :position (0.5 -0.2 0.026) {c})))
"""


def scene(a: str = ":on table", b: str = ":on table", c: str = ":on table") -> str:
    return SCENE.format(a=a, b=b, c=c)


@pytest.mark.parametrize("value,col", [
    ("1e400", 55), ("-1e400", 55), ("1" + "0" * 5000, 55), ("1e999999999999", 55),
])
def test_non_finite_numbers_are_rejected_where_they_are(write_files, capsys, value, col):
    domain, problem = write_files(**{"d.pddl": DOMAIN.format(pre="(clear ?x)"),
                                     "p.pddl": scene(a=f":rpy ({value} 0 0)")})
    status, err = run_check(capsys, domain, problem)
    assert status == 2 and err.startswith(f"{problem}:7:{col}: error: number ")
    assert err.endswith("is out of range: numbers must be finite (at most ~1.8e308 in magnitude)\n")
    assert len(err) - len(problem) < 150  # a 5,000-digit literal is shortened


@pytest.mark.parametrize("prop,message", [
    (":scale 1e-300", ":scale must be a factor in [0.01, 100] (one number, or three equal numbers)"),
    (":scale 1000", ":scale must be a factor in [0.01, 100] (one number, or three equal numbers)"),
    (":scale (1 1 2)", ":scale (1 1 2) is not uniform; the simulator scales models by one factor: give one number"),
    (":mass 0", ":mass must be a number of kilograms in [0.001, 1000]"),
    (":mass 1e300", ":mass must be a number of kilograms in [0.001, 1000]"),
    (":friction 1e300", ":friction must be a friction coefficient in [0, 10]"),
    (":friction -1", ":friction must be a friction coefficient in [0, 10]"),
], ids=["tiny scale", "huge scale", "non-uniform scale", "zero mass", "huge mass", "huge friction",
        "negative friction"])
def test_meaningless_scene_values_are_located_errors(write_files, capsys, prop, message):
    domain, problem = write_files(**{"d.pddl": DOMAIN.format(pre="(clear ?x)"), "p.pddl": scene(a=prop)})
    status, err = run_check(capsys, domain, problem)
    assert (status, err) == (2, f"{problem}:7:49: error: scene object 'a': {message}\n")


@pytest.mark.parametrize("a,b,c,message", [
    (":on a", ":on table", ":on table", "7:49: error: scene object 'a' is :on itself"),
    (":on b", ":on a", ":on table", "7:49: error: scene object 'a' rests on itself through a cycle: a :on b :on a"),
    (":on table", ":on c", ":on b", "8:51: error: scene object 'b' rests on itself through a cycle: b :on c :on b"),
], ids=["self-support", "two-cycle", "cycle after a chain"])
def test_support_cycles_are_rejected(write_files, capsys, a, b, c, message):
    domain, problem = write_files(**{"d.pddl": DOMAIN.format(pre="(clear ?x)"), "p.pddl": scene(a, b, c)})
    status, err = run_check(capsys, domain, problem)
    assert (status, err) == (2, f"{problem}:{message}\n")


def test_rpy_matches_scipy():
    from scipy.spatial.transform import Rotation

    for rpy in [(0.3, -1.2, 2.5), (3.0, 0.1, -0.7), (0, 0, 1.5707963267948966)]:
        expected = Rotation.from_euler("xyz", rpy).as_quat()
        assert all(abs(a - b) < 1e-12 for a, b in zip(quat_from_rpy(*rpy), expected))


# ----------------------------------------------------------------------------- encodings, control characters
def test_non_utf8_byte_is_located(tmp_path, capsys):
    path = tmp_path / "d.pddl"
    path.write_bytes(DOMAIN.format(pre="(clear ?x)").replace("(:types", "(:ty\xe9pes").encode("latin-1"))
    status, err = run_check(capsys, str(path))
    assert (status, err) == (2, f"{path}:3:7: error: not UTF-8: byte 0xe9 cannot start or continue a "
                                "character; save the file as UTF-8\n")


def test_column_after_multibyte_characters_counts_characters(tmp_path, capsys):
    path = tmp_path / "d.pddl"
    path.write_bytes("; héllo\n;  ünïcode \xff".encode("utf-8").replace(b"\xc3\xbf", b"\xff"))
    status, err = run_check(capsys, str(path))
    assert status == 2 and err.startswith(f"{path}:2:12: error: not UTF-8: byte 0xff")


def test_utf16_file_is_located_at_its_first_byte(tmp_path, capsys):
    path = tmp_path / "d.pddl"
    path.write_bytes(DOMAIN.format(pre="(clear ?x)").encode("utf-16"))
    assert run_check(capsys, str(path)) == (2, f"{path}:1:1: error: not UTF-8: byte 0xff cannot start or "
                                               "continue a character; save the file as UTF-8\n")


def test_byte_order_mark_is_accepted(tmp_path, capsys):
    path = tmp_path / "d.pddl"
    path.write_bytes(b"\xef\xbb\xbf" + DOMAIN.format(pre="(clear ?x)").encode())
    assert run_check(capsys, str(path)) == (0, "")


@pytest.mark.parametrize("inserted,shown", [("\x1b[31m", "\\x1b[31m"), ("\x00", "\\x00"), ("\u202e", "\\u202e"),
                                            ("\x07", "\\x07")])
def test_control_characters_are_shown_escaped(write_files, capsys, inserted, shown):
    (domain,) = write_files(**{"d.pddl": DOMAIN.format(pre="(clear ?x)").replace("(:types", f"(:types{inserted}")})
    status, err = run_check(capsys, domain)
    assert status == 2 and shown in err and inserted not in err and err.count("\n") == 1


def test_escaped_source_line_on_a_terminal_keeps_the_caret_under_the_error():
    located = PddlError("bad", Loc("f", 1, 4))
    assert located.render("a\x1bbX").splitlines() == ["f:1:4: error: bad", "  a\\x1bbX", "        ^"]


def test_an_error_about_no_file_is_a_bare_error_line():
    assert str(PddlError("bad value")) == "error: bad value"


# ----------------------------------------------------------------------------- names declared in runs
def test_duplicate_object_inside_a_multi_line_run_is_located_exactly(write_files, capsys):
    problem_text = PROBLEM.replace("(:objects a b - block)", "(:objects a b\n     c  a - block)")
    domain, problem = write_files(**{"d.pddl": DOMAIN.format(pre="(clear ?x)"), "p.pddl": problem_text})
    assert run_check(capsys, domain, problem) == (2, f"{problem}:4:9: error: object 'a' is declared twice\n")


def test_type_error_after_a_typed_part_of_the_run_is_located_exactly(write_files, capsys):
    problem_text = PROBLEM.replace("(:objects a b - block)", "(:objects a - block b c - blok)")
    domain, problem = write_files(**{"d.pddl": DOMAIN.format(pre="(clear ?x)"), "p.pddl": problem_text})
    assert run_check(capsys, domain, problem) == (2, f"{problem}:3:23: error: unknown type 'blok' "
                                                     "(did you mean 'block'?)\n")


def test_dash_without_names_is_located(write_files, capsys):
    problem_text = PROBLEM.replace("(:objects a b - block)", "(:objects a - block - block)")
    domain, problem = write_files(**{"d.pddl": DOMAIN.format(pre="(clear ?x)"), "p.pddl": problem_text})
    assert run_check(capsys, domain, problem) == (2, f"{problem}:3:23: error: '- block' has no names before it\n")


# ----------------------------------------------------------------------------- size
def big_problem(path, objects: int) -> None:
    with open(path, "w") as handle:
        handle.write("(define (problem big) (:domain d)\n  (:objects\n")
        for start in range(0, objects, 10):
            handle.write("    " + " ".join(f"b{i}" for i in range(start, min(objects, start + 10))) + " - block\n")
        handle.write("  )\n  (:init (clear b0) (clear b1))\n  (:goal (on b0 b1)))\n")


def test_a_duplicate_deep_in_a_big_problem_is_located(tmp_path, capsys):
    path = tmp_path / "big.pddl"
    big_problem(path, 100_000)
    text = path.read_text().replace(" b77777 ", " b5 ")
    path.write_text(text)
    (domain,) = [str(tmp_path / "d.pddl")]
    (tmp_path / "d.pddl").write_text(DOMAIN.format(pre="(clear ?x)"))
    status, err = run_check(capsys, domain, str(path))
    assert (status, err) == (2, f"{path}:7780:54: error: object 'b5' is declared twice\n")


@pytest.mark.slow
def test_a_10_mb_problem_checks_in_5_s_and_300_mb(tmp_path):
    path, domain = tmp_path / "big.pddl", tmp_path / "d.pddl"
    big_problem(path, 1_200_000)
    domain.write_text(DOMAIN.format(pre="(clear ?x)"))
    assert path.stat().st_size > 10e6
    # The child reports its own peak (VmHWM): getrusage's maxrss would include the pytest
    # process it was forked from, which Linux carries across exec.
    script = ("import sys; from pdsketch_mech.commands import check; status = check.main(sys.argv[1:]); "
              "print(status, next(l.split()[1] for l in open('/proc/self/status') if l.startswith('VmHWM')))")
    started = time.perf_counter()
    # 1.2 M blocks stack in 1.4e12 ways: past --max-ground's default, but this test is about reading
    done = subprocess.run([sys.executable, "-c", script, "-q", "--max-ground", "1e13", str(domain), str(path)],
                          capture_output=True, text=True, cwd=ROOT, timeout=120)
    elapsed = time.perf_counter() - started
    status, max_rss_kb = map(int, done.stdout.split())
    assert status == 0, done.stderr
    assert elapsed < 5.0 and max_rss_kb < 300 * 1024, (elapsed, max_rss_kb, done.stderr)
