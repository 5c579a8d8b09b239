"""Optimistic stream instantiation (PDDLStream's idea) for the symbolic search.

Before continuous values exist, each stream whose inputs are available is assumed to
succeed once: it yields fresh placeholder objects (`#grasp1`, `#traj3`, ...) for its
outputs and certifies its facts about them. A placeholder's level is one more than the
highest level among its stream's inputs (objects are level 0); `max_level` bounds how
deep streams may chain. The bilevel planner later replaces placeholders by sampled values.
"""
from __future__ import annotations

import math
from collections import defaultdict
from dataclasses import dataclass, replace
from itertools import product
from typing import Dict, Iterable, Iterator, List, Mapping, Set, Tuple

from ..lang.nodes import Atom, Const, Domain, Problem, Stream, TypedName
from ..lang.typecheck import TypeTable
from .grounding import objects_by_type
from .normalize import dnf, holds

Fact = Tuple[str, ...]


@dataclass(frozen=True)
class Placeholder:
    name: str
    type: str
    stream: str
    inputs: Tuple[str, ...]
    level: int


def is_placeholder(name: str) -> bool:
    return name.startswith("#")


def optimistic_problem(domain: Domain, problem: Problem, types: TypeTable,
                       max_level: int = 2) -> Tuple[Problem, Dict[str, Placeholder]]:
    """`problem` plus placeholder objects and the facts their streams would certify.

    Stream `:domain` conditions are evaluated on the initial facts and on facts certified
    by other streams: they should name static (stream-certified or never-changed) facts.
    """
    objects = objects_by_type(domain, problem, types)
    facts: Set[Fact] = {(a.predicate,) + tuple(t.name for t in a.args) for a in problem.init}
    by_predicate: Dict[str, List[Fact]] = defaultdict(list)
    for fact in facts:
        by_predicate[fact[0]].append(fact)
    placeholders: Dict[str, Placeholder] = {}
    instantiated: Set[Tuple[str, Tuple[str, ...]]] = set()
    counters: Dict[str, int] = {}
    new_objects: List[TypedName] = []
    new_facts: List[Fact] = []
    changed = True
    while changed:
        changed = False
        for stream in domain.streams:
            candidates = [list(objects.get(p.type, ())) for p in stream.inputs]
            for values in _candidate_values(stream, candidates, by_predicate, objects):
                key = (stream.name, values)
                if key in instantiated:
                    continue
                level = 1 + max((placeholders[v].level for v in values if v in placeholders), default=0)
                binding = {p.name: v for p, v in zip(stream.inputs, values)}
                if level > max_level or not holds(stream.domain, facts, objects, binding):
                    continue
                instantiated.add(key)
                changed = True
                for out in stream.outputs:
                    counters[out.type] = counters.get(out.type, 0) + 1
                    name = f"#{out.type}{counters[out.type]}"
                    placeholders[name] = Placeholder(name, out.type, stream.name, values, level)
                    binding[out.name] = name
                    new_objects.append(TypedName(name, out.type))
                    for t in types.ancestors(out.type):
                        objects.setdefault(t, []).append(name)
                for conj in dnf(stream.certified, objects):
                    for lit in conj:
                        if lit.positive and isinstance(lit.atom, Atom):
                            fact = _ground(lit.atom, binding)
                            if fact not in facts:
                                facts.add(fact)
                                new_facts.append(fact)
                                by_predicate[fact[0]].append(fact)
                    break  # certified facts are a conjunction: its one disjunct
    init = problem.init + tuple(Atom(f[0], tuple(Const(a) for a in f[1:])) for f in new_facts)
    return replace(problem, objects=problem.objects + tuple(new_objects), init=init), placeholders


def _candidate_values(stream: Stream, candidates: List[List[str]], by_predicate: Mapping[str, List[Fact]],
                      objects) -> Iterable[Tuple[str, ...]]:
    """The input tuples worth testing, in `product(*candidates)` order (placeholder numbers
    depend on it). When the stream's `:domain` is one conjunction, only tuples matching its
    positive atoms can hold: joining them with the facts visits those instead of the whole
    product (a placement's motion stream: n^2 facts, not n^2 objects x n^2 placements)."""
    alternatives = dnf(stream.domain, objects)
    atoms = [lit.atom for lit in alternatives[0] if lit.positive and isinstance(lit.atom, Atom)] \
        if len(alternatives) == 1 else []
    joined = math.prod(len(by_predicate.get(a.predicate, ())) for a in atoms)
    if not atoms or joined >= math.prod(len(c) for c in candidates) or _certifies(stream, atoms):
        # the join would visit more; or the stream's own facts, found while its tuples are
        # tested, could let later tuples hold: only the lazy product sees them as before
        return product(*candidates)
    names = [p.name for p in stream.inputs]
    index = [{value: i for i, value in enumerate(c)} for c in candidates]
    found = set()
    for binding in _join(atoms, {}, by_predicate):
        free = [k for k, name in enumerate(names) if name not in binding]
        for extra in product(*(candidates[k] for k in free)):
            values = [binding.get(name) for name in names]
            for k, value in zip(free, extra):
                values[k] = value
            if all(value in index[k] for k, value in enumerate(values)):
                found.add(tuple(values))
    return sorted(found, key=lambda values: [index[k][v] for k, v in enumerate(values)])


def _certifies(stream: Stream, atoms: List[Atom]) -> bool:
    """Whether the stream certifies a predicate its own :domain asks for."""
    certified = {a.predicate for a in _atoms(stream.certified)}
    return any(a.predicate in certified for a in atoms)


def _atoms(formula) -> List[Atom]:
    out, stack = [], [formula]
    while stack:
        f = stack.pop()
        if isinstance(f, Atom):
            out.append(f)
        else:
            stack.extend(getattr(f, "parts", ()))
    return out


def _join(atoms: List[Atom], binding: Dict[str, str], by_predicate: Mapping[str, List[Fact]]
          ) -> Iterator[Dict[str, str]]:
    """Bindings of the atoms' variables under which every atom is one of the facts."""
    if not atoms:
        yield binding
        return
    atom, rest = atoms[0], atoms[1:]
    for fact in by_predicate.get(atom.predicate, ()):
        if len(fact) != len(atom.args) + 1:
            continue
        extended = dict(binding)
        for term, value in zip(atom.args, fact[1:]):
            name = term.name
            if isinstance(term, Const):
                if name != value:
                    break
            elif extended.setdefault(name, value) != value:
                break
        else:
            yield from _join(rest, extended, by_predicate)


def _ground(atom: Atom, binding: Mapping[str, str]) -> Fact:
    return (atom.predicate,) + tuple(binding.get(t.name, t.name) for t in atom.args)
