"""Hostile input: mutants of every shipped .pddl file (token, line and byte edits, deep
nesting, special numbers, other encodings) get exit 0 or exactly one located error line,
never a traceback or a hang. The long run: `python -m pdsketch_mech.bench fuzz --mutants 3000`."""
import random

import pytest

from pdsketch_mech.bench import mutate
from pdsketch_mech.bench.fuzz import classify, run_fuzz, seed_files


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


def test_mutants_get_one_located_line_or_pass():
    report = run_fuzz(mutants=1500, seed=0, subprocess_every=100)
    assert report.failures == [], report.summary()
    assert report.counts["error"] > 0 and report.counts["ok"] > 0
    assert report.subprocess_runs == 15
