"""Files -> checked domains and problems: resolves `(:extends "path")`, merges fragments.

A domain fragment (e.g. a learned mechanism in `domains/mechanisms/`) names the files it
extends, relative to itself; loading it loads those first and merges everything into one
`Domain` whose name is the root domain's. Several domain files can also be merged directly
(`load_domain([basis, fragment, ...])`), which is what `plan --mechanisms` does.
"""
from __future__ import annotations

import glob
import os
import re
from dataclasses import dataclass, replace
from typing import Dict, FrozenSet, List, Optional, Sequence, Tuple

from .errors import PddlError, PddlWarning
from .nodes import Domain, Problem
from .parser import parse_file
from .typecheck import TypeTable, check_domain, check_problem


@dataclass(frozen=True)
class LoadedDomain:
    """A merged, type-checked domain and the names/files it was built from."""

    domain: Domain
    types: TypeTable
    names: FrozenSet[str]  # every domain name in the merge: a problem may name any of them
    files: Tuple[str, ...]
    warnings: Tuple[PddlWarning, ...] = ()  # accepted oddities, for the command-line tools to print


def read_domain_file(path: str) -> Domain:
    node = parse_file(path)
    if not isinstance(node, Domain):
        raise PddlError(f"expected a domain definition, found problem '{node.name}'", node.loc)
    return node


def read_problem_file(path: str) -> Problem:
    node = parse_file(path)
    if not isinstance(node, Problem):
        raise PddlError(f"expected a problem definition, found domain '{node.name}'", node.loc)
    return node


def load_domain(paths: Sequence[str]) -> LoadedDomain:
    """Parse `paths` (and whatever they extend), merge them in order, and type-check."""
    ordered: List[Tuple[str, Domain]] = []
    for path in paths:
        _collect(os.path.normpath(path), ordered, stack=())
    merged = ordered[0][1]
    for _, domain in ordered[1:]:
        merged = merge_domains(merged, domain)
    warnings: List[PddlWarning] = []
    types = check_domain(merged, warnings)
    return LoadedDomain(merged, types, frozenset(d.name for _, d in ordered), tuple(p for p, _ in ordered),
                        tuple(warnings))


def _collect(path: str, out: List[Tuple[str, Domain]], stack: Tuple[str, ...]) -> None:
    """Depth-first: a file's bases come before it; each file (by real path) is merged once."""
    key = os.path.realpath(path)
    if any(os.path.realpath(p) == key for p, _ in out):
        return
    domain = read_domain_file(path)
    for base in domain.extends:
        base_path = os.path.normpath(os.path.join(os.path.dirname(path), base))
        if not os.path.isfile(base_path):
            raise PddlError(f"extended domain file '{base}' not found (looked for {base_path})", domain.loc)
        if os.path.realpath(base_path) in stack + (key,):
            raise PddlError(f"'{base}' is extended in a cycle", domain.loc)
        _collect(base_path, out, stack + (key,))
    _check_sampler_files(path, domain)
    out.append((path, domain))


def _check_sampler_files(path: str, domain: Domain) -> None:
    """A mechanism's `:sampler` names a checkpoint file beside its fragment: it must exist."""
    for mechanism in domain.mechanisms:
        if mechanism.sampler is None:
            continue
        checkpoint = os.path.normpath(os.path.join(os.path.dirname(path), mechanism.sampler))
        if not os.path.isfile(checkpoint):
            raise PddlError(f"mechanism '{mechanism.name}': :sampler file '{mechanism.sampler}' not found "
                            f"(looked for {checkpoint})", mechanism.loc)


def merge_domains(base: Domain, extra: Domain) -> Domain:
    """`base` plus everything `extra` declares; duplicates are caught by the type checker."""
    return replace(
        base,
        requirements=tuple(dict.fromkeys(base.requirements + extra.requirements)),
        extends=(),
        types=base.types + extra.types,
        value_types=base.value_types + extra.value_types,
        constants=base.constants + extra.constants,
        predicates=base.predicates + extra.predicates,
        actions=base.actions + extra.actions,
        streams=base.streams + extra.streams,
        mechanisms=base.mechanisms + extra.mechanisms,
    )


_DOMAIN_HEADER = re.compile(r"^\s*(?:;[^\n]*\n\s*)*\(\s*define\s*\(\s*domain\s+([^\s()]+)", re.IGNORECASE)


def declared_domain_name(path: str) -> Optional[str]:
    """The name in a file's `(define (domain NAME)` header, without a full parse."""
    try:
        with open(path, encoding="utf-8-sig") as handle:  # a byte-order mark is not text
            match = _DOMAIN_HEADER.match(handle.read(4096))
    except (OSError, UnicodeDecodeError):
        return None
    return match.group(1).lower() if match else None


def find_domain_file(problem: Problem, problem_path: str) -> Optional[str]:
    """Look beside the problem for its domain: `domain.pddl`, any `*.pddl` in the same
    folder, then `../domains/*.pddl`; the first whose name matches `(:domain ...)` wins."""
    folder = os.path.dirname(os.path.abspath(problem_path))
    candidates = [os.path.join(folder, "domain.pddl")]
    candidates += sorted(glob.glob(os.path.join(folder, "*.pddl")))
    candidates += sorted(glob.glob(os.path.join(folder, "..", "domains", "*.pddl")))
    for candidate in candidates:
        if os.path.isfile(candidate) and declared_domain_name(candidate) == problem.domain_name:
            return os.path.relpath(candidate)
    return None


def load_problem(problem_path: str, domains: Sequence[LoadedDomain] = ()) -> Tuple[LoadedDomain, Problem]:
    """Parse a problem, find its domain (among `domains`, else beside it) and type-check it."""
    problem = read_problem_file(problem_path)
    domain = next((d for d in domains if problem.domain_name in d.names), None)
    if domain is None:
        found = find_domain_file(problem, problem_path)
        if found is None:
            given = ", ".join(sorted(n for d in domains for n in d.names)) or "none given"
            raise PddlError(f"no domain named '{problem.domain_name}' (domains: {given}; none beside "
                            "the problem either)", problem.loc)
        domain = load_domain([found])
    check_problem(problem, domain.domain, domain.types)
    return domain, problem


def load_domains_by_name(paths: Sequence[str]) -> Dict[str, LoadedDomain]:
    """Each path loaded separately (with its bases), keyed by every name it answers to."""
    out: Dict[str, LoadedDomain] = {}
    for path in paths:
        loaded = load_domain([path])
        for name in loaded.names:
            out.setdefault(name, loaded)
    return out
