"""A recorded demonstration -> a mechanism fragment (paper Sec. 3.1): segment by contact
modes, explain the segments with basis operators, lift, write with the language's writer,
parse back and type-check.

    extraction = extract(load_recording(path), name="hook-use")
    text = fragment_text(extraction, out_path)       # the .pddl file's text
"""
from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass, replace
from typing import Dict, List, Optional, Sequence, Set, Tuple

from ..lang.errors import PddlError
from ..lang.loader import SHIPPED_BASIS, load_domain
from ..lang.nodes import Action, Domain, Formula, Problem
from ..lang.parser import parse_text
from ..lang.writer import formula, write_domain
from ..symbolic.normalize import holds
from ..world.recording import Recording
from .lifting import Lifted, lift
from .paths import BASIS
from .segmentation import Segmentation, segment
from .steps import Explanation, ExtractionError, Fact, explain



@dataclass
class Extraction:
    name: str
    source: str                    # the recording's path, as given
    problem: Problem               # the demonstration's own problem (its goal)
    segmentation: Segmentation
    explanation: Explanation
    lifted: Lifted

    @property
    def names(self) -> Sequence[str]:
        return self.segmentation.bodies.names


def load_basis(path: str = BASIS) -> Domain:
    return load_domain([path]).domain


def _facts_text(facts: Set[Fact]) -> str:
    return " ".join("(" + " ".join(f) + ")" for f in sorted(facts))


def check_complete(recording: Recording, goal: Formula, ex: Explanation, static: Set[Fact]) -> None:
    """A recording cut off before its end is refused: its header's frame count must match
    its arrays, and the goal must hold in the contact graph of its last frame."""
    frames = recording.header.get("frames")
    if frames is not None and frames != recording.frames:
        raise ExtractionError(f"the recording holds {recording.frames} frames but its header says {frames}: "
                              "it was cut off (re-record it)")
    if not holds(goal, ex.final | static):
        end = float(recording.arrays["time"][-1])
        raise ExtractionError(f"the goal {formula(goal)} does not hold when the recording ends "
                              f"(t = {end:.2f} s; contacts then: {_facts_text(ex.final)}): it is incomplete or "
                              "cut off, so it demonstrates nothing to extract")


def extract(recording: Recording, name: str, source: str = "", basis: Optional[Domain] = None) -> Extraction:
    """Everything `learn extract` computes; ExtractionError if the demonstration cannot be explained."""
    basis = basis or load_basis()
    problem_text = recording.header.get("problem")
    if not problem_text:
        raise ExtractionError("the recording's header has no problem (its goal is needed)")
    try:
        problem = parse_text(problem_text, file=recording.header.get("problem_file", "<recording>"))
    except PddlError as exc:
        raise ExtractionError(f"the recording's problem does not parse: {exc}") from None
    if not isinstance(problem, Problem):
        raise ExtractionError("the recording's problem text is not a problem")
    seg = segment(recording)
    ex = explain(seg, basis)
    static = {("fixed", seg.bodies.names[o]) for o in seg.bodies.fixed}
    check_complete(recording, problem.goal, ex, static)
    lifted = lift(ex, seg.bodies.names, problem.goal, basis, name, seg.bodies.fixed)
    return Extraction(name, source, problem, seg, ex, lifted)


def fragment_domain(extraction: Extraction, out_path: str, basis_path: str = BASIS,
                    sampler: Optional[str] = None) -> Domain:
    basis, folder = os.path.abspath(basis_path), os.path.dirname(os.path.abspath(out_path))
    # A fragment among the shipped domains names the basis by its relative path; anywhere else
    # by the shipped name (never this checkout's or installation's absolute path).
    shipped = os.path.abspath(basis_path) == os.path.abspath(BASIS)
    inside = os.path.commonpath([os.path.dirname(basis), folder]) == os.path.dirname(basis)
    if shipped and not inside:
        extends = SHIPPED_BASIS
    else:
        shared = os.path.commonpath([basis, folder])
        extends = os.path.relpath(basis, folder) if shared != os.path.dirname(shared) else basis
    mechanism = replace(extraction.lifted.mechanism, sampler=sampler)
    return Domain(extraction.name, requirements=(":mechanisms",), extends=(extends.replace(os.sep, "/"),),
                  mechanisms=(mechanism,))


def header_comment(extraction: Extraction, command: str) -> List[str]:
    """The fragment's leading comment: where it came from and what its variables stand for."""
    h = extraction.segmentation.recording.header
    names = extraction.names
    lines = [f"; Mechanism {extraction.name}: extracted from the demonstration "
             f"{h.get('name', os.path.basename(extraction.source))} ({h.get('mechanism', '?')}, instance "
             f"{h.get('instance', '?')}) by",
             f";   {command}",
             "; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a",
             "; learned sampler (:sampler); re-extracting keeps that name.",
             "; Steps (demonstration time):"]
    seg = extraction.segmentation
    for k, st in enumerate(extraction.explanation.steps, 1):
        lines.append(f";   {k}. {st.text(names)} at {seg.time(st.frame):.2f} s")
        if st.then[0] or st.then[1]:
            lines.append(f";      then physics: {_facts_text(set(st.then[0]))}"
                         + (f", no longer {_facts_text(set(st.then[1]))}" if st.then[1] else ""))
    lines.append("; Variables (role: why):")
    for o, var in extraction.lifted.roles.items():
        lines.append(f";   {var} = {names[o]}: {extraction.lifted.reasons[o]}")
    return lines


def fragment_text(extraction: Extraction, out_path: str, command: str, basis_path: str = BASIS,
                  sampler: Optional[str] = None) -> str:
    """The fragment's text: comment lines, then the writer's output; `sampler`: the learned
    sampler's file the mechanism names (kept from the fragment being replaced)."""
    body = write_domain(fragment_domain(extraction, out_path, basis_path, sampler))
    return "\n".join(header_comment(extraction, command)) + "\n" + body


def check_fragment(text: str, out_path: str) -> Tuple[Domain, Tuple[Action, ...]]:
    """Parse `text` back and type-check it with what it extends, as if it were at `out_path`
    (a temporary file beside it, so `:extends` resolves the same way). Returns the fragment
    and the actions it extends (what its steps need)."""
    folder = os.path.dirname(os.path.abspath(out_path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix=".pddl")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
        actions = load_domain([tmp]).domain.actions
        fragment = parse_text(text, file=out_path)
    finally:
        os.unlink(tmp)
    if not isinstance(fragment, Domain):
        raise ExtractionError("the written fragment does not parse as a domain")
    return fragment, actions




def role_table(extraction: Extraction) -> Dict[str, str]:
    """{variable: demo object} (for messages and tests)."""
    return {v: extraction.names[o] for o, v in extraction.lifted.roles.items()}
