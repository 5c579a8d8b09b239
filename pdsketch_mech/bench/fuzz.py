"""`python -m pdsketch_mech.bench fuzz [--mutants N] [--seed S]`: hostile input for `check`.

Every shipped `.pddl` file (under `domains/`, `problems/` and `tests/data/`) is mutated
(`bench/mutate.py`, including files grown to 120,000 objects, 300,000 facts or 1.2 M
predicate declarations) and checked, with the unchanged files it needs (a problem's domain).
The contract of the command-line tools, asserted for each mutant: exit 0, or exit 2 with
exactly one line `MUTANT:LINE:COL: error: ...` (a line and column inside the file); no
traceback, no raw control characters, no hang (`HANG_S`), and no more than `MEMORY_MB` of
memory. Most mutants are checked in a forked child of this process (`check.main`, fast;
`bench/child.py` limits and measures it); every `subprocess_every`-th one also as
`python -m pdsketch_mech.check`, measured the same way.
"""
from __future__ import annotations

import contextlib
import io
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections import Counter
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence, Tuple

from ..commands import check
from ..lang.loader import declared_domain_name
from ..util.data import REPO_ROOT
from .child import child_error, run_limited, wait_measured
from .mutate import mutate

SEED_FOLDERS = ("domains", "problems", os.path.join("tests", "data"))
HANG_S = 20.0  # seconds one check may take before it counts as a hang
MEMORY_MB = 1024.0  # memory one check may add to its process before it counts as over-memory
_PROBLEM_DOMAIN = re.compile(rb"\(\s*:domain\s+([^\s()]+)\s*\)", re.IGNORECASE)
_WARNING = re.compile(r"^.*: warning: ")
_UNPRINTABLE = re.compile(r"[\x00-\x09\x0b-\x1f\x7f-\x9f]")


@dataclass
class MutantOutcome:
    file: str            # the seed file, relative to the repository
    mutations: List[str]
    kind: str            # "ok" | "error" (located) | "unlocated" | "crash" | "hang" | "over-memory"
    detail: str = ""


@dataclass
class FuzzReport:
    counts: Counter = field(default_factory=Counter)
    failures: List[MutantOutcome] = field(default_factory=list)   # every crash, hang and unlocated error
    subprocess_runs: int = 0
    seconds: float = 0.0
    peak_mb: float = 0.0     # the most memory one check added
    slowest_s: float = 0.0   # the longest one check took

    def summary(self) -> str:
        total = sum(self.counts.values())
        return (f"{total} mutants ({self.subprocess_runs} also in a subprocess) in {self.seconds:.1f} s: "
                f"{self.counts['ok']} accepted, {self.counts['error']} located errors, "
                f"{self.counts['unlocated']} errors without line and column, {self.counts['crash']} crashes, "
                f"{self.counts['hang']} hangs, {self.counts['over-memory']} over {MEMORY_MB:g} MB; slowest check "
                f"{self.slowest_s:.1f} s, largest {self.peak_mb:.0f} MB")


def seed_files(root: str = REPO_ROOT) -> List[str]:
    """The shipped `.pddl` files, relative to `root`, sorted."""
    found = []
    for folder in SEED_FOLDERS:
        for base, _, files in os.walk(os.path.join(root, folder)):
            found += [os.path.relpath(os.path.join(base, f), root) for f in files if f.endswith(".pddl")]
    return sorted(found)


def companions(files: Sequence[str], root: str) -> Dict[str, List[str]]:
    """For each problem file, the domain file(s) it is checked with: the one of its domain's
    name in its own folder, else anywhere among `files`."""
    domains: Dict[str, List[str]] = {}
    for rel in files:
        name = declared_domain_name(os.path.join(root, rel))
        if name is not None:
            domains.setdefault(name, []).append(rel)
    out: Dict[str, List[str]] = {}
    for rel in files:
        if declared_domain_name(os.path.join(root, rel)) is not None:
            continue
        with open(os.path.join(root, rel), "rb") as handle:
            match = _PROBLEM_DOMAIN.search(handle.read())
        candidates = domains.get(match.group(1).decode().lower(), []) if match else []
        near = [d for d in candidates if os.path.dirname(d) == os.path.dirname(rel)]
        out[rel] = (near or candidates)[:1]
    return out


@dataclass
class Run:
    """One check of a mutant: exit status (None: stopped), stderr, peak memory and time."""

    status: Optional[int]
    err: str
    peak_mb: float = 0.0
    seconds: float = 0.0
    over_memory: bool = False


def classify(status: Optional[int], err: str, mutant: str, data: bytes, over_memory: bool = False
             ) -> Tuple[str, str]:
    """The kind of outcome of one check run, and a detail for failures."""
    if over_memory:
        return "over-memory", f"more than {MEMORY_MB:g} MB"
    if status is None:
        return "hang", f"no answer within {HANG_S:g} s"
    if "Traceback" in err:
        return "crash", err.strip().splitlines()[-1][:300]
    if _UNPRINTABLE.search(err):
        return "crash", f"raw control character in the output: {err[:300]!r}"
    errors = [line for line in err.splitlines() if not _WARNING.match(line)]
    if status == 0 and not errors:
        return "ok", ""
    if status != 2 or len(errors) != 1:
        return "crash", f"exit {status}, {len(errors)} error lines: {err[:300]!r}"
    located = re.match(rf"^{re.escape(mutant)}:(\d+):(\d+): error: \S", errors[0])
    if located is None:
        return "unlocated", errors[0][:300]
    line, col = int(located.group(1)), int(located.group(2))
    lines = data.split(b"\n")
    if not (1 <= line <= len(lines) and 1 <= col <= len(lines[line - 1]) + 1):
        return "crash", f"location {line}:{col} is outside the file: {errors[0][:200]}"
    return "error", ""


class _Hang(Exception):
    pass


def _raise_hang(signum, frame):
    raise _Hang()


def check_in_process(files: Sequence[str]) -> Tuple[Optional[int], str]:
    """`check -q FILES` in this process: its exit status (None on a hang) and stderr."""
    err = io.StringIO()
    previous = signal.signal(signal.SIGALRM, _raise_hang)
    signal.setitimer(signal.ITIMER_REAL, HANG_S)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            status = check.main(["-q", *files])
    except _Hang:
        status = None
    except MemoryError:
        raise  # the caller's memory limit was reached: over-memory, not a crash
    except BaseException as exc:  # what must never happen: a Python error escaping check
        return 1, f"Traceback (in-process): {type(exc).__name__}: {exc}"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    return status, err.getvalue()


def check_in_child(files: Sequence[str]) -> Run:
    """`check -q FILES` in a forked child limited to `HANG_S` and `MEMORY_MB`."""
    started = time.perf_counter()
    result = run_limited(lambda: check_in_process(files), HANG_S + 10, MEMORY_MB)
    elapsed = time.perf_counter() - started
    if result.hang:
        return Run(None, "", result.peak_mb, elapsed)
    if result.out_of_memory:
        return Run(None, "", result.peak_mb, elapsed, over_memory=True)
    error = child_error(result)
    if error is not None:
        return Run(1, f"Traceback (in the child): {error}", result.peak_mb, elapsed)
    status, err = result.value
    return Run(status, err, result.peak_mb, elapsed)


def check_in_subprocess(files: Sequence[str]) -> Run:
    """`python -m pdsketch_mech.check -q FILES` under the same time limit; its peak is its own
    (resident memory of a fresh interpreter, imports included). Run only after the mutant
    passed `check_in_child`, whose address-space limit keeps a runaway from the machine."""
    with tempfile.TemporaryFile() as err_file:
        child = subprocess.Popen([sys.executable, "-m", "pdsketch_mech.check", "-q", *files], cwd=REPO_ROOT,
                                 stdout=subprocess.DEVNULL, stderr=err_file)
        status, seconds, peak = wait_measured(child, HANG_S + 30)
        err_file.seek(0)
        err = err_file.read().decode("utf-8", errors="backslashreplace")
    return Run(status, err, peak, seconds, over_memory=peak > MEMORY_MB)


def run_fuzz(mutants: int, seed: int = 0, subprocess_every: int = 50, progress: bool = False,
             grow: bool = True) -> FuzzReport:
    """Check `mutants` mutants of the seed files (with files grown huge unless not `grow`);
    a mirror of them in a temporary folder keeps relative paths (`:extends "../basis.pddl"`)
    working and the repository untouched."""
    rng = random.Random(seed)
    report = FuzzReport()
    started = time.perf_counter()
    files = seed_files()
    with tempfile.TemporaryDirectory(prefix="pdsketch_fuzz_") as mirror:
        originals: Dict[str, bytes] = {}
        for rel in files:
            os.makedirs(os.path.join(mirror, os.path.dirname(rel)), exist_ok=True)
            shutil.copyfile(os.path.join(REPO_ROOT, rel), os.path.join(mirror, rel))
            with open(os.path.join(REPO_ROOT, rel), "rb") as handle:
                originals[rel] = handle.read()
        needs = companions(files, mirror)
        for rel in files:  # load the simulator and the learned samplers here once, not in every child
            check_in_process([os.path.join(mirror, d) for d in needs.get(rel, [])] + [os.path.join(mirror, rel)])
        for number in range(mutants):
            rel = rng.choice(files)
            data, names = mutate(originals[rel], rng, grow)
            path = os.path.join(mirror, rel)
            with open(path, "wb") as handle:
                handle.write(data)
            inputs = [os.path.join(mirror, d) for d in needs.get(rel, [])] + [path]
            runs = [check_in_child(inputs)]
            stopped = runs[0].status is None
            if subprocess_every and number % subprocess_every == 0 and not stopped:
                runs.append(check_in_subprocess(inputs))
                report.subprocess_runs += 1
            report.peak_mb = max([report.peak_mb, runs[0].peak_mb])
            report.slowest_s = max([report.slowest_s] + [run.seconds for run in runs])
            for index, run in enumerate(runs):
                kind, detail = classify(run.status, run.err, path, data, run.over_memory)
                if index == 0:  # the subprocess run repeats the mutant: counted as a failure only
                    report.counts[kind] += 1
                if kind not in ("ok", "error"):
                    report.failures.append(MutantOutcome(rel, names, kind, detail))
            with open(path, "wb") as handle:
                handle.write(originals[rel])
            if progress and (number + 1) % 100 == 0:
                print(f"  {number + 1} mutants, {len(report.failures)} failures", file=sys.stderr)
    report.seconds = time.perf_counter() - started
    return report
