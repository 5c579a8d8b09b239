"""The source names no test instance and carries no commit-stamped measurement logs.

Test instances are for reported tables only (docs/evaluation.md): a comment that names one
is a sign that something was tuned on it. Measurements and their history belong in
results/HISTORY.md, where they can be dated and compared, not in docstrings."""
import glob
import os
import re

from conftest import ROOT

# A generated test instance's name: TASK-test-SEED (see envs/generate.py `Instance.name`).
TEST_INSTANCE = re.compile(r"\b[a-z][a-z-]*-" + "test" + r"-\d+\b")
COMMIT_STAMP = re.compile(r"\b(at|since|before|after) [0-9a-f]{7}\b")


def _lines_matching(pattern, folders):
    """'path:line: text' for every line of the folders' Python files that `pattern` finds."""
    found = []
    for folder in folders:
        for path in glob.glob(os.path.join(ROOT, folder, "**", "*.py"), recursive=True):
            with open(path, encoding="utf-8") as handle:
                for number, line in enumerate(handle, 1):
                    if pattern.search(line):
                        found.append(f"{os.path.relpath(path, ROOT)}:{number}: {line.strip()}")
    return found


def test_no_source_file_names_a_test_instance():
    found = _lines_matching(TEST_INSTANCE, ("pdsketch_mech", "tests"))
    assert not found, "test instances named in source:\n" + "\n".join(found)


def test_no_source_comment_carries_a_commit_stamped_measurement():
    found = _lines_matching(COMMIT_STAMP, ("pdsketch_mech",))
    assert not found, "measurements stamped with a commit in source:\n" + "\n".join(found)


def test_the_patterns_catch_what_they_are_for():
    assert TEST_INSTANCE.search("on hook-" + "test-3 the tool") and not TEST_INSTANCE.search("hook-dev-3")
    assert COMMIT_STAMP.search("Measured at cf0f99a (") and not COMMIT_STAMP.search("at 10 cm")
