"""Hostile input: mutants of every shipped .pddl file (token, line and byte edits, deep
nesting, special numbers, other encodings, files grown huge) get exit 0 or exactly one
located error line, never a traceback, a hang or more than the memory limit. The long run:
`python -m pdsketch_mech.bench fuzz --mutants 3000`."""
import os
import random

import pytest

from pdsketch_mech.bench import mutate
from pdsketch_mech.bench.child import run_limited
from pdsketch_mech.bench.fuzz import MEMORY_MB, check_in_child, check_in_process, classify, run_fuzz, seed_files

from conftest import ROOT


def test_the_seed_files_cover_domains_problems_and_test_data():
    files = seed_files()
    for folder in ("domains/", "domains/mechanisms/", "problems/", "tests/data/ipc/"):
        assert any(f.startswith(folder) for f in files), folder


def test_every_mutation_changes_its_input():
    data = b'(define (problem p) (:domain d) (:objects a - item) (:init (on a)) (:goal (on a))\n' \
           b'  (:scene (a :asset "block/0" :position (0.5 0 0.02))))\n'
    for name, mutation in mutate.MUTATIONS.items():
        rng = random.Random(1)
        assert any(mutation(data, rng) != data for _ in range(5)), name


@pytest.mark.parametrize("status,err,kind", [
    (0, "", "ok"),
    (2, "M:3:4: error: unexpected ')'\n", "error"),
    (2, "M: error: cannot read file\n", "unlocated"),
    (2, "M:3:4: error: a\nM:5:1: error: b\n", "crash"),
    (1, "Traceback (most recent call last):\n  ...\nRecursionError\n", "crash"),
    (2, "M:1:2: error: bad \x1b[31m\n", "crash"),
    (2, "M:99:1: error: beyond the end\n", "crash"),
    (None, "", "hang"),
])
def test_classify_applies_the_contract(status, err, kind):
    assert classify(status, err, "M", b"line one\nline two\nline three\n")[0] == kind


def test_classify_reports_over_memory():
    assert classify(None, "", "M", b"", over_memory=True)[0] == "over-memory"


def test_a_child_over_its_memory_limit_is_stopped_and_reported():
    result = run_limited(lambda: len(bytearray(300 * 2 ** 20)), seconds=30, memory_mb=100)
    assert result.out_of_memory and not result.hang


def test_a_child_over_its_time_limit_is_killed():
    import time
    result = run_limited(lambda: time.sleep(30), seconds=0.5, memory_mb=100)
    assert result.hang


@pytest.mark.parametrize("name,seed", [("many-objects", "problems/com.pddl"),
                                       ("many-facts", "problems/hook-use.pddl"),
                                       pytest.param("many-predicates", "domains/basis.pddl",
                                                    marks=pytest.mark.slow)])  # 1.2 M distinct: ~10 s
def test_the_largest_growths_are_checked_or_refused_within_the_limits(tmp_path, name, seed):
    counts = {"many-objects": "OBJECT_COUNTS", "many-facts": "FACT_COUNTS", "many-predicates": "PREDICATE_COUNTS"}
    original = getattr(mutate, counts[name])
    setattr(mutate, counts[name], [original[-1]])  # the largest only
    try:
        with open(os.path.join(ROOT, seed), "rb") as handle:
            data = mutate.GROWTHS[name](handle.read(), random.Random(0))
    finally:
        setattr(mutate, counts[name], original)
    path = tmp_path / os.path.basename(seed)
    path.write_bytes(data)
    files = [str(path)] if seed.startswith("domains/") else [os.path.join(ROOT, "domains/basis.pddl"), str(path)]
    check_in_process([os.path.join(ROOT, "domains/basis.pddl"), os.path.join(ROOT, "problems/com.pddl")])  # as
    # run_fuzz does first: the simulator's libraries load here, not under the child's memory limit
    run = check_in_child(files)
    kind, detail = classify(run.status, run.err, str(path), data, run.over_memory)
    assert kind in ("ok", "error"), (kind, detail, run.err[-300:])
    assert run.peak_mb < MEMORY_MB


def test_mutants_get_one_located_line_or_pass():
    report = run_fuzz(mutants=1500, seed=0, subprocess_every=100, grow=False)
    assert report.failures == [], report.summary()
    assert report.counts["error"] > 0 and report.counts["ok"] > 0
    assert report.subprocess_runs == 15
