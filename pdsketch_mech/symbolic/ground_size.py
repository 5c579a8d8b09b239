"""How big grounding a problem would get, estimated before grounding it (`--max-ground`).

Grounding enumerates stream instances (the bilevel planner's optimistic objects), action
operators, mechanism macros and quantifier expansions; each can grow as a power of the
number of objects. `ground_sizes` bounds each of them from above in time linear in the
domain and problem: an action's operators by a join bound over its static preconditions
(facts in `:init` or certified by streams), a quantifier by the product of its variables'
type sizes. `check_ground_size` turns the largest bound over a limit into one located error,
so that an input too big to ground is refused in seconds rather than filling the memory.
"""
from __future__ import annotations

import math
from collections import Counter, defaultdict
from dataclasses import dataclass
from operator import itemgetter
from typing import Callable, Dict, Iterable, List, Optional, Sequence, Set, Tuple

from ..lang.errors import PddlError
from ..lang.nodes import (
    And, Atom, Const, Domain, Exists, Forall, Formula, Imply, Not, Or, Problem, TypedName, Var, When,
)
from ..lang.typecheck import TypeTable

DEFAULT_MAX_GROUND = 5_000_000
STREAM_LEVELS = 2  # as `optimistic_problem`'s max_level: placeholders feed streams once

Positions = Tuple[int, ...]


@dataclass(frozen=True)
class GroundSize:
    """One bounded quantity: `count` of `unit` for `what` (e.g. `action (move ?x ?y)`)."""

    count: float
    unit: str
    what: str


def short_number(value: float) -> str:
    """1.44e10 -> `1.4e10`, 5e6 -> `5e6`, 120 -> `120`: a size for a one-line message."""
    if math.isinf(value):
        return "more than 1e308"
    if value < 1e4:
        return f"{value:.0f}"
    mantissa, exponent = f"{value:.1e}".split("e")
    return f"{mantissa.removesuffix('.0')}e{int(exponent)}"


def signature(name: str, params: Iterable[TypedName]) -> str:
    return "(" + " ".join([name, *(p.name for p in params)]) + ")"


class _Facts:
    """How many facts of each predicate there can be, and how many match a partial binding
    (the fan-out): exact for `:init` facts, 1 per stream once its inputs or an output are
    bound (stream outputs are fresh objects), else the count."""

    def __init__(self, init: Dict[str, List[Tuple[str, ...]]]):
        self.init = init
        self.streams: Dict[str, List[Tuple[float, List[Positions]]]] = defaultdict(list)
        self._cache: Dict[Tuple[str, Positions], int] = {}

    def count(self, predicate: str) -> float:
        return len(self.init.get(predicate, ())) + sum(n for n, _ in self.streams.get(predicate, ()))

    def fanout(self, predicate: str, bound: Positions) -> float:
        total = float(self._init_fanout(predicate, bound))
        for n, keys in self.streams.get(predicate, ()):
            total += 1.0 if any(set(key) <= set(bound) for key in keys) else n
        return total

    def _init_fanout(self, predicate: str, bound: Positions) -> int:
        facts = self.init.get(predicate, ())
        if not bound or not facts:
            return len(facts)
        key = (predicate, bound)
        if key not in self._cache:
            self._cache[key] = max(Counter(map(itemgetter(*bound), facts)).values())
        return self._cache[key]


def join_bound(params: Sequence[TypedName], atoms: Sequence[Atom], type_size: Callable[[str], float],
               facts: _Facts) -> float:
    """An upper bound on the bindings of `params` under which every atom holds: atoms are
    joined greedily, each multiplying by its fan-out given the variables bound so far; the
    variables no atom binds range over their types."""
    types = {p.name: p.type for p in params}
    usable = [a for a in atoms if all(isinstance(t, Const) or t.name in types for t in a.args)]
    bound: Set[str] = set()
    total = 1.0
    while True:
        best: Optional[Tuple[float, Atom, Set[str]]] = None
        for atom in usable:
            new = {t.name for t in atom.args if isinstance(t, Var)} - bound
            if not new:
                continue
            positions = tuple(i for i, t in enumerate(atom.args) if isinstance(t, Const) or t.name in bound)
            options = min(facts.fanout(atom.predicate, positions), math.prod(type_size(types[v]) for v in new))
            if best is None or options < best[0]:
                best = (options, atom, new)
        if best is None:
            break
        total *= best[0]
        bound |= best[2]
        usable.remove(best[1])
    return total * math.prod(type_size(t) for v, t in types.items() if v not in bound)


def conjuncts(formula: Formula) -> List[Formula]:
    """The top-level conjuncts of a formula (nested `and`s flattened, without recursion)."""
    out, stack = [], [formula]
    while stack:
        f = stack.pop()
        if isinstance(f, And):
            stack.extend(reversed(f.parts))
        else:
            out.append(f)
    return out


def expanded_size(formula: Formula, type_size: Callable[[str], float]) -> float:
    """Literals in the formula once its quantifiers are expanded over the objects (without
    recursion: formulas may nest 500 deep)."""
    total, stack = 0.0, [(formula, 1.0)]
    while stack:
        f, times = stack.pop()
        if isinstance(f, (And, Or)):
            stack.extend((part, times) for part in f.parts)
        elif isinstance(f, Not):
            stack.append((f.body, times))
        elif isinstance(f, Imply):
            stack += [(f.condition, times), (f.consequence, times)]
        elif isinstance(f, When):
            stack += [(f.condition, times), (f.effect, times)]
        elif isinstance(f, (Forall, Exists)):
            stack.append((f.body, times * math.prod(type_size(v.type) for v in f.variables)))
        else:
            total += times
    return total


def _effect_predicates(formula: Formula) -> Set[str]:
    out, stack = set(), [formula]
    while stack:
        f = stack.pop()
        if isinstance(f, Atom):
            out.add(f.predicate)
        elif isinstance(f, Not):
            stack.append(f.body)
        elif isinstance(f, And):
            stack.extend(f.parts)
        elif isinstance(f, Forall):
            stack.append(f.body)
        elif isinstance(f, When):
            stack.append(f.effect)
    return out


def _type_sizes(domain: Domain, problem: Problem, types: TypeTable) -> Counter:
    """Objects (and constants) of each type, counting each object under all its ancestors."""
    sizes: Counter = Counter()
    for obj_type in dict((o.name, o.type) for o in domain.constants + problem.objects).values():
        for ancestor in types.ancestors(obj_type):
            sizes[ancestor] += 1
    return sizes


def ground_sizes(domain: Domain, problem: Problem, types: TypeTable) -> List[GroundSize]:
    """Upper bounds of what grounding `problem` enumerates: stream instances (a domain with
    streams), operators of each action times their literals, mechanism macros, the goal."""
    sizes = _type_sizes(domain, problem, types)
    init: Dict[str, List[Tuple[str, ...]]] = defaultdict(list)
    for atom in problem.init:
        init[atom.predicate].append(tuple([t.name for t in atom.args]))
    facts = _Facts(init)
    out: List[GroundSize] = []
    if domain.streams:
        sizes = _stream_sizes(domain, types, sizes, facts, out)
    type_size = sizes.__getitem__
    fluent = set().union(*(_effect_predicates(a.effect) for a in domain.actions))
    for action in domain.actions:
        static = [f for f in conjuncts(action.precondition) if isinstance(f, Atom) and f.predicate not in fluent]
        operators = join_bound(action.parameters, static, type_size, facts)
        literals = expanded_size(action.precondition, type_size) + expanded_size(action.effect, type_size)
        out.append(GroundSize(operators * max(literals, 1.0), "atoms", "action " +
                              signature(action.name, action.parameters)))
    for mechanism in domain.mechanisms:
        objects = [q for q in mechanism.parameters if not types.is_value(q.type)]
        out.append(GroundSize(math.prod(type_size(q.type) for q in objects), "macro groundings",
                              "mechanism " + signature(mechanism.name, objects)))
    out.append(GroundSize(expanded_size(problem.goal, type_size), "atoms", "the goal"))
    return out


def _stream_sizes(domain: Domain, types: TypeTable, objects: Counter, facts: _Facts,
                  out: List[GroundSize]) -> Counter:
    """Stream instances as the optimistic instantiation makes them, level by level; returns
    the type sizes with the placeholder objects added and records certified facts in `facts`."""
    sizes, instances = objects, {}
    for _ in range(STREAM_LEVELS):
        certified: Dict[str, List[Tuple[float, List[Positions]]]] = defaultdict(list)
        after = Counter(objects)
        for stream in domain.streams:
            condition = [f for f in conjuncts(stream.domain) if isinstance(f, Atom)]
            count = join_bound(stream.inputs, condition, sizes.__getitem__, facts)
            instances[stream.name] = count
            for output in stream.outputs:
                for ancestor in types.ancestors(output.type):
                    after[ancestor] += count
            inputs, outputs = {p.name for p in stream.inputs}, {p.name for p in stream.outputs}
            for atom in (f for f in conjuncts(stream.certified) if isinstance(f, Atom)):
                names = [t.name if isinstance(t, Var) else None for t in atom.args]
                keys = [tuple(i for i, n in enumerate(names) if n == o) for o in outputs if o in names]
                if inputs <= set(names):
                    keys.append(tuple(i for i, n in enumerate(names) if n in inputs))
                certified[atom.predicate].append((count, keys))
        facts.streams, sizes = certified, after
    for stream in domain.streams:
        out.append(GroundSize(instances[stream.name], "stream instances",
                              "stream " + signature(stream.name, stream.inputs)))
    return sizes


def check_ground_size(domain: Domain, problem: Problem, types: TypeTable, limit: float) -> None:
    """Raise a `PddlError` at the problem when the largest grounding bound exceeds `limit`."""
    largest = max(ground_sizes(domain, problem, types), key=lambda s: s.count)
    if largest.count > limit:
        raise PddlError(f"the problem grounds to about {short_number(largest.count)} {largest.unit} for "
                        f"{largest.what}; the limit is {short_number(limit)} (--max-ground N)", problem.loc)
