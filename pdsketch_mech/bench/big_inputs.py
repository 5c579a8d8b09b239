"""`bench big-inputs`: time and peak memory of `check` (and `plan`) on huge input files.

The cases of issue 58, built in a temporary folder: every problem in `problems/` with
120,000 extra objects (typed as the problem's first objects, and untyped), the basis domain
with 1,200,000 extra `(p)` declarations, a 300,000-fact `:init` (an IPC ferry problem with
548 locations) and a classical problem too big to ground (gripper with 150,000 balls; also
given to `plan`). Each runs as a fresh `python -m pdsketch_mech.X` process; its peak is its
resident memory (VmHWM, polled), interpreter and imports included. Targets: every case answered
(checked, or refused with one located error line) within `TARGET_S` and `TARGET_MB`; the
300,000-fact `:init` accepted within `INIT_TARGET_S`.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

from ..util.data import REPO_ROOT
from .child import wait_measured

TARGET_S, TARGET_MB, INIT_TARGET_S = 5.0, 1024.0, 3.0
LIMIT_S = 60.0  # a case still running then is stopped (and misses its target)
OBJECTS, PREDICATES, FERRY_LOCATIONS, GRIPPER_BALLS = 120_000, 1_200_000, 548, 150_000
_OBJECTS = re.compile(r"\(\s*:objects([^()]*)\)", re.IGNORECASE)
_PREDICATES = re.compile(r"\(\s*:predicates", re.IGNORECASE)


@dataclass
class Case:
    name: str
    command: Tuple[str, ...]        # after `python -m`
    expect_ok: bool = False         # must be accepted (exit 0), not only answered
    target_s: float = TARGET_S


@dataclass
class Measured:
    name: str
    command: str
    status: int
    seconds: float
    peak_mb: float
    answer: str          # the last line on stderr (the error), or "ok"
    met: bool


def _write(folder: str, name: str, text: str) -> str:
    path = os.path.join(folder, name)
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(text)
    return path


def _read(rel: str) -> str:
    with open(os.path.join(REPO_ROOT, rel), encoding="utf-8") as handle:
        return handle.read()


def with_objects(text: str, count: int, typed: bool) -> str:
    """`text` with `count` more names in :objects: first in the section (so they take the
    type of its first names), or last (untyped, of type object)."""
    names = " ".join(f"extra{k}" for k in range(count))
    match = _OBJECTS.search(text)
    inner = f" {names} {match.group(1)}" if typed else f"{match.group(1)}\n {names}"
    return text[:match.start()] + f"(:objects{inner})" + text[match.end():]


def ferry_problem(locations: int) -> str:
    """An IPC ferry problem with `locations` locations, one car per 10: not-eq for every
    ordered pair makes the :init about locations^2 facts."""
    locs = [f"l{i}" for i in range(locations)]
    cars = [f"c{i}" for i in range(locations // 10)]
    facts = [f"(location {l})" for l in locs] + [f"(car {c})" for c in cars]
    facts += [f"(not-eq {a} {b})" for a in locs for b in locs if a != b]
    facts += [f"(at {c} l{i % locations})" for i, c in enumerate(cars)] + ["(at-ferry l0)", "(empty-ferry)"]
    goal = " ".join(f"(at {c} l{(i + 1) % locations})" for i, c in enumerate(cars))
    return (f"(define (problem ferry-big)\n(:domain ferry)\n(:objects {' '.join(locs)}\n {' '.join(cars)})\n"
            "(:init\n" + "\n".join(facts) + f")\n(:goal (and {goal})))\n")


def gripper_problem(balls: int) -> str:
    """An IPC gripper problem with `balls` balls in room a (two facts each)."""
    names = " ".join(f"ball{i}" for i in range(balls))
    facts = "\n".join(f"(ball ball{i}) (at ball{i} rooma)" for i in range(balls))
    return ("(define (problem gripper-big) (:domain gripper-strips)\n"
            f"(:objects rooma roomb left right {names})\n"
            "(:init (room rooma) (room roomb) (gripper left) (gripper right) (at-robby rooma) (free left) "
            f"(free right)\n{facts})\n(:goal (and (at ball0 roomb) (at ball1 roomb))))\n")


def build_cases(folder: str) -> List[Case]:
    """Write the inputs into `folder`; the cases that check (or plan) them."""
    basis = os.path.join(REPO_ROOT, "domains", "basis.pddl")
    cases: List[Case] = []
    for rel in sorted(f"problems/{f}" for f in os.listdir(os.path.join(REPO_ROOT, "problems")) if f.endswith(".pddl")):
        stem = os.path.basename(rel)[:-5]
        for typed in (True, False):
            kind = "typed" if typed else "untyped"
            path = _write(folder, f"{stem}-{kind}.pddl", with_objects(_read(rel), OBJECTS, typed))
            cases.append(Case(f"{rel} + 120,000 {kind} objects", ("pdsketch_mech.check", "-q", basis, path)))
    domain = _read("domains/basis.pddl")
    at = _PREDICATES.search(domain).end()
    path = _write(folder, "basis-predicates.pddl", domain[:at] + "\n" + "(p) " * PREDICATES + "\n" + domain[at:])
    cases.append(Case("domains/basis.pddl + 1,200,000 (p)", ("pdsketch_mech.check", "-q", path)))
    ferry = os.path.join(REPO_ROOT, "tests", "data", "ipc", "ferry", "domain.pddl")
    path = _write(folder, "ferry-300k.pddl", ferry_problem(FERRY_LOCATIONS))
    cases.append(Case("ferry, 300,000-fact :init", ("pdsketch_mech.check", "-q", ferry, path), expect_ok=True,
                      target_s=INIT_TARGET_S))
    gripper = os.path.join(REPO_ROOT, "tests", "data", "ipc", "gripper", "domain.pddl")
    path = _write(folder, "gripper-150k.pddl", gripper_problem(GRIPPER_BALLS))
    cases.append(Case("gripper, 150,000 balls: check", ("pdsketch_mech.check", "-q", gripper, path)))
    cases.append(Case("gripper, 150,000 balls: plan", ("pdsketch_mech.plan", gripper, path)))
    typed_com = os.path.join(folder, "com-typed.pddl")
    cases.append(Case("problems/com.pddl + 120,000 typed objects: plan", ("pdsketch_mech.plan", basis, typed_com)))
    return cases


def measure(case: Case) -> Measured:
    """Run one case in a fresh process: exit status, wall time, peak resident memory."""
    with tempfile.TemporaryFile() as err_file:
        child = subprocess.Popen([sys.executable, "-m", *case.command], cwd=REPO_ROOT, stdout=subprocess.DEVNULL,
                                 stderr=err_file)
        status, seconds, peak_mb = wait_measured(child, LIMIT_S)
        err_file.seek(0)
        lines = err_file.read().decode("utf-8", errors="backslashreplace").strip().splitlines()
    if status is None:
        lines = [f"stopped after {LIMIT_S:g} s"]
    answer = "ok" if child.returncode == 0 else (lines[-1] if lines else f"exit {child.returncode}")
    answered = child.returncode == 0 or (child.returncode == 2 and len(lines) == 1)
    met = answered and (child.returncode == 0 or not case.expect_ok) and seconds <= case.target_s \
        and peak_mb <= TARGET_MB
    return Measured(case.name, "python -m " + " ".join(case.command), child.returncode, seconds, peak_mb, answer, met)


def run_big_inputs(names: Optional[Sequence[str]] = None) -> List[Measured]:
    """Build and measure every case (or those whose name contains one of `names`)."""
    with tempfile.TemporaryDirectory(prefix="pdsketch_big_") as folder:
        cases = build_cases(folder)
        if names:
            cases = [c for c in cases if any(n in c.name for n in names)]
        return [measure(case) for case in cases]


def _short(answer: str, width: int = 90) -> str:
    answer = re.sub(r"^\S*/", "", answer)  # the temporary folder is not worth printing
    return answer if len(answer) <= width else answer[:width - 3] + "..."


def report(results: Sequence[Measured]) -> List[str]:
    """One line per case, and a summary against the targets."""
    width = max(len(r.name) for r in results)
    lines = [f"big inputs: time and peak memory of a fresh process (targets {TARGET_S:g} s, {TARGET_MB:g} MB; "
             f"the 300,000-fact :init accepted in {INIT_TARGET_S:g} s)"]
    for r in results:
        lines.append(f"  {r.name:<{width}}  {r.seconds:6.2f} s  {r.peak_mb:6.0f} MB  exit {r.status}  "
                     f"{'ok ' if r.met else 'MISSED'}  {_short(r.answer)}")
    missed = [r.name for r in results if not r.met]
    lines.append(f"{len(results) - len(missed)} of {len(results)} cases within their targets"
                 + (f"; missed: {', '.join(missed)}" if missed else ""))
    return lines
