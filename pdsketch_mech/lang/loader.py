"""Files -> checked domains and problems: resolves `(:extends "path")`, merges fragments.

A domain fragment (e.g. a learned mechanism in `domains/mechanisms/`) names the files it
extends, relative to itself; loading it loads those first and merges everything into one
`Domain` whose name is the root domain's. Several domain files can also be merged directly
(`load_domain([basis, fragment, ...])`), which is what `plan --mechanisms` does.
"""
from __future__ import annotations

import glob
import json
import os
import re
from dataclasses import dataclass, replace
from typing import FrozenSet, List, Optional, Sequence, Tuple

from ..util.data import data_path
from .errors import PddlError, PddlWarning
from .nodes import Domain, Problem
from .parser import parse_file
from .typecheck import TypeTable, check_domain, check_problem

# `(:extends "basis")` names the shipped basis domain (when no file of that name is beside the
# fragment): a user's fragment then works wherever the package is installed.
SHIPPED_BASIS = "basis"


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


def load_domain(paths: Sequence[str], samplers_required: bool = True) -> LoadedDomain:
    """Parse `paths` (and whatever they extend), merge them in order, and type-check.
    A mechanism's missing `:sampler` file is an error, or with `samplers_required=False`
    (a caller that will not load learned samplers) a warning."""
    ordered: List[Tuple[str, Domain]] = []
    for path in paths:
        _collect(os.path.normpath(path), ordered, stack=())
    warnings: List[PddlWarning] = []
    for path, domain in ordered:
        _check_sampler_files(path, domain, samplers_required, warnings)
    merged = ordered[0][1]
    for _, domain in ordered[1:]:
        merged = merge_domains(merged, domain)
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
        if not os.path.isfile(base_path) and base == SHIPPED_BASIS:
            base_path = data_path("domains", "basis.pddl")
        if not os.path.isfile(base_path):
            raise PddlError(f"extended domain file '{base}' not found (looked for {base_path})", domain.loc)
        if os.path.realpath(base_path) in stack + (key,):
            raise PddlError(f"'{base}' is extended in a cycle", domain.loc)
        _collect(base_path, out, stack + (key,))
    out.append((path, domain))


def _check_sampler_files(path: str, domain: Domain, required: bool, warnings: List[PddlWarning]) -> None:
    """A mechanism's `:sampler` names a checkpoint file beside its fragment: it must exist,
    unless it will not be loaded (`required` false), when its absence is only a warning."""
    for mechanism in domain.mechanisms:
        if mechanism.sampler is None:
            continue
        checkpoint = os.path.normpath(os.path.join(os.path.dirname(path), mechanism.sampler))
        if not os.path.isfile(checkpoint):
            message = (f"mechanism '{mechanism.name}': :sampler file '{mechanism.sampler}' not found "
                       f"(looked for {checkpoint})")
            if required:
                raise PddlError(message, mechanism.loc)
            warnings.append(PddlWarning(f"{message}; its learned samplers are not used", mechanism.loc))
            continue
        weak = _weak_training(checkpoint)
        if weak:
            warnings.append(PddlWarning(f"mechanism '{mechanism.name}': its learned samplers were trained on {weak}: "
                                        "they may rank worse than the generic ones (more `learn train "
                                        "--episodes`, or plan --no-learned-samplers)", mechanism.loc))


MIN_EPISODES = 20   # self-play episodes below which a checkpoint's ranking is a guess


def _weak_training(checkpoint: str) -> str:
    """What is thin about the training of `checkpoint` (its metadata beside it), or ''."""
    metadata = checkpoint[:-len(".safetensors")] + ".json" if checkpoint.endswith(".safetensors") else ""
    try:
        with open(metadata, encoding="utf-8") as handle:
            info = json.load(handle)
    except (OSError, ValueError):
        return ""
    if not isinstance(info, dict):   # a malformed file is the checkpoint loader's to report
        return ""
    episodes = info.get("episodes")
    aucs = [v.get("auc") for v in (info.get("validation") or {}).values() if isinstance(v, dict)]
    aucs = [a for a in aucs if isinstance(a, (int, float))]
    if isinstance(episodes, int) and episodes < MIN_EPISODES:
        return f"{episodes} self-play episodes"
    if aucs and max(aucs) <= 0.5:
        return f"data none of whose classifiers ranks better than chance on validation (AUC at most {max(aucs):.2f})"
    return ""


def merge_domains(base: Domain, extra: Domain) -> Domain:
    """`base` plus everything `extra` declares; duplicates are caught by the type checker,
    a fragment naming another vocabulary than its base here."""
    if base.vocabulary and extra.vocabulary and base.vocabulary != extra.vocabulary:
        raise PddlError(f"vocabulary '{extra.vocabulary}' differs from '{base.vocabulary}', the vocabulary of "
                        f"domain '{base.name}' that this domain extends", extra.vocabulary_loc)
    return replace(
        base,
        requirements=tuple(dict.fromkeys(base.requirements + extra.requirements)),
        extends=(),
        vocabulary=base.vocabulary or extra.vocabulary,
        vocabulary_loc=base.vocabulary_loc if base.vocabulary else extra.vocabulary_loc,
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


class DomainNotFound(PddlError):
    """A problem's `(:domain NAME)` is neither among the domains given nor beside it."""


def _domain_candidates(problem_path: str, shipped: bool = True) -> List[str]:
    """Where a problem's domain is looked for, in order (see `find_domain_file`); without
    `shipped`, only beside the problem."""
    folder = os.path.dirname(problem_path) or os.curdir  # as the user wrote it, to name files in messages
    candidates = [os.path.join(folder, "domain.pddl")]
    candidates += sorted(glob.glob(os.path.join(glob.escape(folder), "*.pddl")))
    candidates += sorted(glob.glob(os.path.join(glob.escape(folder), "..", "domains", "*.pddl")))
    # Last, the package's own (util/data.py): a problem of the basis domain anywhere needs no path to it.
    if shipped:
        candidates += sorted(glob.glob(os.path.join(glob.escape(data_path("domains")), "*.pddl")))
    return [c for c in dict.fromkeys(map(os.path.normpath, candidates)) if os.path.isfile(c)]


def _shown(path: str) -> str:
    """`path` relative to the working folder when it lies inside it, else as it is."""
    relative = os.path.relpath(path)
    return path if relative.startswith(os.pardir) else relative


def find_domain_file(problem: Problem, problem_path: str) -> Optional[str]:
    """Look beside the problem for its domain: `domain.pddl`, any `*.pddl` in the same
    folder, then `../domains/*.pddl`, then the shipped domains; the first whose name matches
    `(:domain ...)` wins."""
    for candidate in _domain_candidates(problem_path):
        if declared_domain_name(candidate) == problem.domain_name:
            return os.path.relpath(candidate)
    return None


def _not_found(problem: Problem, problem_path: str, domains: Sequence[LoadedDomain]) -> DomainNotFound:
    """The error for a problem whose domain was not found, saying what was looked at beside it
    and, when a fragment there extends the domain (it declares its own name), which files to give."""
    name = problem.domain_name
    given = ", ".join(sorted(n for d in domains for n in d.names)) or "none given"
    beside = [c for c in _domain_candidates(problem_path, shipped=False) if declared_domain_name(c) is not None]
    for candidate in beside:
        chain: List[Tuple[str, Domain]] = []
        try:
            _collect(os.path.normpath(candidate), chain, stack=())
        except PddlError:  # a broken file is reported when it is given, not here
            continue
        declaring = next((p for p, d in chain if d.name == name), None)
        if declaring is not None:
            return DomainNotFound(
                f"no domain named '{name}' (domains: {given}); beside the problem, {_shown(candidate)} "
                f"is a fragment of domain '{declared_domain_name(candidate)}' that extends it: give that fragment, "
                f"or {_shown(declaring)}, which declares '{name}'", problem.loc)
    looked = ", ".join(_shown(c) for c in beside[:5]) + (f" and {len(beside) - 5} more" if len(beside) > 5 else "")
    where = f"none of the domain files beside the problem declares it: {looked}" if beside else \
        "no domain file beside the problem either"
    return DomainNotFound(f"no domain named '{name}' (domains: {given}; {where})", problem.loc)


def load_problem(problem_path: str, domains: Sequence[LoadedDomain] = (),
                 samplers_required: bool = True) -> Tuple[LoadedDomain, Problem]:
    """Parse a problem, find its domain (among `domains`, else beside it) and type-check it.
    `samplers_required` is `load_domain`'s, for a domain found beside the problem."""
    problem = read_problem_file(problem_path)
    domain = next((d for d in domains if problem.domain_name in d.names), None)
    if domain is None:
        found = find_domain_file(problem, problem_path)
        if found is None:
            raise _not_found(problem, problem_path, domains)
        domain = load_domain([found], samplers_required)
    check_problem(problem, domain.domain, domain.types)
    return domain, problem
