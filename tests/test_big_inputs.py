"""Big inputs (issue 58): check and plan stay linear in the file's size, and a problem too big
to ground is refused with one located line before grounding starts (`--max-ground`). Speed
targets are the benchmark's (`bench big-inputs`); these tests compare sizes with each other."""
import os
import re
import time

import pytest

from pdsketch_mech.commands import check, plan
from pdsketch_mech.bench.big_inputs import ferry_problem, with_objects
from pdsketch_mech.lang.loader import load_domain, load_problem
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.symbolic.ground_size import ground_sizes, short_number

from conftest import ROOT

BASIS = os.path.join(ROOT, "domains", "basis.pddl")
FERRY = os.path.join(ROOT, "tests", "data", "ipc", "ferry", "domain.pddl")
REFUSAL = re.compile(r"^(?P<file>.+):(?P<line>\d+):1: error: the problem grounds to about (?P<size>\S+) "
                     r"(?P<unit>atoms|stream instances|macro groundings) for (?P<what>.+); "
                     r"the limit is (?P<limit>\S+) \(--max-ground N\)\n$")


def com_with(tmp_path, count: int, typed: bool = True) -> str:
    with open(os.path.join(ROOT, "problems", "com.pddl"), encoding="utf-8") as handle:
        text = with_objects(handle.read(), count, typed)
    path = tmp_path / f"com-{count}-{typed}.pddl"
    path.write_text(text)
    return str(path)


def run(capsys, main, *args):
    status = main(list(args))
    return status, capsys.readouterr().err


# ----------------------------------------------------------------------------- the guard
def test_a_problem_too_big_to_ground_is_one_located_line_from_check_and_plan(tmp_path, capsys):
    problem = com_with(tmp_path, 2000)
    for main in (check.main, plan.main):
        status, err = run(capsys, main, *(["-q"] if main is check.main else []), BASIS, problem)
        match = REFUSAL.match(err)
        assert status == 2 and match, err
        assert (match["file"], match["line"]) == (problem, "3")  # the problem's (define
        assert match["what"] == "action (move-cont ?x ?y ?s ?c ?t)" and match["limit"] == "5e6"
        assert float(match["size"]) > 1e10


def test_max_ground_sets_the_limit(tmp_path, capsys):
    com = os.path.join(ROOT, "problems", "com.pddl")
    status, err = run(capsys, check.main, "-q", "--max-ground", "100", BASIS, com)
    assert status == 2 and REFUSAL.match(err)["limit"] == "100", err
    assert run(capsys, check.main, "-q", "--max-ground", "1e4", BASIS, com) == (0, "")
    bigger = com_with(tmp_path, 12)  # 15 items: 3,375 contacts, 2e4 atoms for move-cont
    status, err = run(capsys, check.main, "-q", BASIS, bigger)
    assert status == 0, err
    status, err = run(capsys, check.main, "-q", "--max-ground", "1e4", BASIS, bigger)
    assert status == 2 and REFUSAL.match(err)["limit"] == "1e4", err


@pytest.mark.parametrize("value", ["0", "-5", "abc", "nan", "inf"])
def test_a_bad_max_ground_is_one_error_line(capsys, value):
    with pytest.raises(SystemExit) as stopped:
        check.main(["--max-ground", value, BASIS])
    assert stopped.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("error: argument --max-ground: ") and err.count("\n") == 1


def test_a_classical_problem_too_big_to_ground_is_refused_by_plan(tmp_path, capsys):
    gripper = os.path.join(ROOT, "tests", "data", "ipc", "gripper", "domain.pddl")
    balls = " ".join(f"b{i}" for i in range(3000))
    facts = " ".join(f"(ball b{i}) (at b{i} rooma)" for i in range(3000))
    problem = tmp_path / "p.pddl"
    problem.write_text(f"(define (problem g) (:domain gripper-strips) (:objects rooma roomb left right {balls})\n"
                       f"(:init (room rooma) (room roomb) (gripper left) (gripper right) (at-robby rooma) "
                       f"(free left) (free right) {facts}) (:goal (at b0 roomb)))\n")
    status, err = run(capsys, plan.main, "--max-ground", "1e4", gripper, str(problem))
    match = REFUSAL.match(err)
    assert status == 2 and match and match["what"] == "action (pick ?obj ?room ?gripper)", err
    assert match["size"] == "1.1e5"  # 3000 balls x 2 rooms x 2 grippers, 9 literals each


def test_stream_instances_grow_as_the_cube_of_the_items(tmp_path):
    domain = load_domain([BASIS])
    sizes = {}
    for extra in (7, 17):
        _, problem = load_problem(com_with(tmp_path, extra), [domain])
        found = {s.what: s.count for s in ground_sizes(domain.domain, problem, domain.types)}
        sizes[extra] = found["stream (sample-contact ?x ?y ?s)"]
    assert sizes == {7: 10.0 ** 3, 17: 20.0 ** 3}  # one per triple of items


def test_short_number_reads_as_in_the_messages():
    assert [short_number(x) for x in (120, 5e6, 1.44e10, 1e16)] == ["120", "5e6", "1.4e10", "1e16"]


# ----------------------------------------------------------------------------- linear time
def best_seconds(action, repeats: int = 2) -> float:
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        action()
        times.append(time.perf_counter() - started)
    return min(times)


def test_checking_a_scene_problem_is_linear_in_its_extra_objects(tmp_path, capsys):
    small, large = com_with(tmp_path, 10_000, typed=False), com_with(tmp_path, 20_000, typed=False)
    check.main(["-q", BASIS, small])  # loads the simulator once, outside the timing
    capsys.readouterr()
    seconds = {p: best_seconds(lambda p=p: check.main(["-q", BASIS, p])) for p in (small, large)}
    assert capsys.readouterr().err == ""
    assert seconds[large] / seconds[small] < 3.0, seconds  # quadratic would be 4


def test_reading_an_init_is_linear_in_its_facts(tmp_path):
    texts = {n: ferry_problem(n) for n in (100, 200)}  # about 10,000 and 40,000 facts
    seconds = {n: best_seconds(lambda t=t: parse_text(t, "p.pddl")) for n, t in texts.items()}
    assert seconds[200] / seconds[100] < 4 * 1.5, seconds  # 4 times the facts


def test_a_duplicate_predicate_is_reported_in_time_linear_in_the_declarations(tmp_path, capsys):
    with open(BASIS, encoding="utf-8") as handle:
        text = handle.read()
    at = text.index("(:predicates") + len("(:predicates")
    seconds = {}
    for count in (50_000, 100_000):
        path = tmp_path / f"basis-{count}.pddl"
        path.write_text(text[:at] + "\n" + "(p) " * count + "\n" + text[at:])
        seconds[count] = best_seconds(lambda p=str(path): check.main(["-q", p]))
        assert capsys.readouterr().err.endswith(
            f"{path}:{text[:at].count(chr(10)) + 2}:5: error: predicate 'p' is already defined "
            f"(first defined at {path}:{text[:at].count(chr(10)) + 2}:1)\n")
    assert seconds[100_000] / seconds[50_000] < 3.0, seconds


# ----------------------------------------------------------------------------- runs keep locations
def test_facts_read_as_a_run_keep_their_lines_and_columns(tmp_path, capsys):
    problem = tmp_path / "p.pddl"
    problem.write_text("(define (problem p) (:domain ferry) (:objects a b - object)\n"
                       "  (:init (location a) (location b)\n"
                       "     (not-eq a b) (not-eq a\n"
                       "        zz))\n"
                       "  (:goal (at-ferry a)))\n")
    status, err = run(capsys, check.main, "-q", FERRY, str(problem))
    assert (status, err) == (2, f"{problem}:4:9: error: unknown object 'zz'\n")


def test_declarations_read_as_a_run_keep_their_lines_and_columns(tmp_path, capsys):
    domain = tmp_path / "d.pddl"
    domain.write_text("(define (domain d) (:requirements :strips :typing) (:types block)\n"
                      "  (:predicates (on ?x ?y - block) (clear ?x - block)\n"
                      "     (held ?x - bloc)))\n")
    status, err = run(capsys, check.main, "-q", str(domain))
    assert status == 2 and err.startswith(f"{domain}:3:12: error: unknown type 'bloc'"), err
