"""Domain + problem -> `StripsTask`, building only operators reachable in the relaxation.

Each action's precondition is put in DNF (quantifiers expanded over objects); each disjunct
is a rule whose positive atoms are joined, Datalog style, against the facts reachable so
far. Semi-naive fixpoint: after the first round, a rule is only re-joined with one of its
atoms bound to a fact that was new in the previous round.
"""
from __future__ import annotations

import time
from collections import defaultdict
from dataclasses import dataclass
from itertools import product
from typing import Dict, Iterator, List, Mapping, Optional, Sequence, Set, Tuple

from ..lang.nodes import Atom, Const, Domain, Equals, Problem, Var
from ..lang.typecheck import TypeTable
from .normalize import Conjunction, EffectPart, Literal, dnf, flatten_effect
from .task import ConditionalEffect, Fact, Operator, StripsTask, Timeout

Binding = Dict[str, str]


@dataclass
class _Rule:
    """One precondition disjunct of one action."""

    action: str
    params: Tuple[Tuple[str, str], ...]  # (variable, type)
    positive: Tuple[Atom, ...]
    negative: Tuple[Atom, ...]
    equal: Tuple[Equals, ...]
    unequal: Tuple[Equals, ...]
    effects: Tuple[EffectPart, ...]


class _FactIndex:
    """Reachable facts by predicate and by (predicate, position, object)."""

    def __init__(self) -> None:
        self.by_pred: Dict[str, List[Fact]] = defaultdict(list)
        self.by_pos: Dict[Tuple[str, int, str], List[Fact]] = defaultdict(list)
        self.known: Set[Fact] = set()

    def add(self, fact: Fact) -> bool:
        if fact in self.known:
            return False
        self.known.add(fact)
        self.by_pred[fact[0]].append(fact)
        for pos, obj in enumerate(fact[1:]):
            self.by_pos[(fact[0], pos, obj)].append(fact)
        return True


def objects_by_type(domain: Domain, problem: Problem, types: TypeTable) -> Dict[str, List[str]]:
    """Every type -> its objects (constants first, then problem objects, in declaration order)."""
    declared = list(dict.fromkeys([(o.name, o.type) for o in domain.constants + problem.objects]))
    return {t: [name for name, obj_type in declared if types.is_subtype(obj_type, t)] for t in types.parents}


def ground(domain: Domain, problem: Problem, types: TypeTable, prune_irrelevant: bool = True,
           deadline: Optional[float] = None) -> StripsTask:
    """Ground a type-checked domain and problem into a STRIPS task.

    `prune_irrelevant` drops operators that cannot help reach the goal symbolically; the
    bilevel planner keeps them, since effect-free moves and pushes change poses."""
    objects = objects_by_type(domain, problem, types)
    members = {t: set(objs) for t, objs in objects.items()}
    fluent = {lit.atom.predicate for a in domain.actions for part in flatten_effect(a.effect, objects)
              for lit in part.literals}
    init = [(a.predicate,) + tuple(t.name for t in a.args) for a in problem.init]
    static = frozenset(f for f in init if f[0] not in fluent)
    rules = [_make_rule(a.name, tuple((p.name, p.type) for p in a.parameters), conj,
                        tuple(flatten_effect(a.effect, objects)), fluent)
             for a in domain.actions for conj in dnf(a.precondition, objects)]

    index = _FactIndex()
    for fact in init:
        index.add(fact)
    found: Dict[Tuple[int, Tuple[str, ...]], Binding] = {}
    delta: Optional[List[Fact]] = None  # None: first round, join against everything
    while delta is None or delta:
        new_facts: List[Fact] = []
        for rule_id, rule in enumerate(rules):
            if deadline is not None and time.perf_counter() > deadline:
                raise Timeout
            for binding in _rule_bindings(rule, index, objects, members, static, fluent, delta):
                key = (rule_id, tuple(binding[v] for v, _ in rule.params))
                if key in found:
                    continue
                found[key] = binding
                for part in rule.effects:
                    for lit in part.literals:
                        fact = _ground_atom(lit.atom, binding)
                        if lit.positive and index.add(fact):
                            new_facts.append(fact)
        delta = new_facts

    facts = sorted(f for f in index.known if f[0] in fluent)  # sorted: ids independent of set order
    fact_ids = {f: i for i, f in enumerate(facts)}
    operators = [op for (rule_id, _), binding in found.items()
                 for op in [_make_operator(rules[rule_id], binding, fact_ids, static, fluent)] if op]
    task = StripsTask(facts, operators, init=0, goal=0, static_facts=static, fact_ids=fact_ids)
    task.init = task.mask([f for f in init if f[0] in fluent])
    _set_goal(task, problem, objects, static, fluent)
    if prune_irrelevant:
        task.operators = relevant_operators(task)
    return task


def relevant_operators(task: StripsTask) -> List[Operator]:
    """Backward relevance: keep operators that can make a goal-relevant fact true, or false
    where a relevant operator needs it false; their conditions become relevant in turn."""
    relevant, relevant_false = task.goal, task.goal_neg
    keep = [False] * len(task.operators)
    changed = True
    while changed:
        changed = False
        for i, op in enumerate(task.operators):
            if keep[i]:
                continue
            effects = [(op.add, op.delete)] + [(c.add, c.delete) for c in op.conditional]
            if any(add & relevant or delete & relevant_false for add, delete in effects):
                keep[i] = changed = True
                relevant |= op.pre | op.neg | op.delete
                relevant_false |= op.neg
                for c in op.conditional:
                    relevant |= c.pre | c.neg
                    relevant_false |= c.neg
    return [op for i, op in enumerate(task.operators) if keep[i]]


def _make_rule(action: str, params, conj: Conjunction, effects, fluent) -> _Rule:
    pos = tuple(l.atom for l in conj if l.positive and isinstance(l.atom, Atom))
    neg = tuple(l.atom for l in conj if not l.positive and isinstance(l.atom, Atom))
    eq = tuple(l.atom for l in conj if l.positive and isinstance(l.atom, Equals))
    neq = tuple(l.atom for l in conj if not l.positive and isinstance(l.atom, Equals))
    # Static atoms first: they never change, so they prune bindings cheaply.
    pos = tuple(sorted(pos, key=lambda a: a.predicate in fluent))
    return _Rule(action, params, pos, neg, eq, neq, effects)


def _ground_atom(atom: Atom, binding: Mapping[str, str]) -> Fact:
    return (atom.predicate,) + tuple(binding[t.name] if isinstance(t, Var) else t.name for t in atom.args)


def _term(term, binding: Mapping[str, str]) -> str:
    return binding[term.name] if isinstance(term, Var) else term.name


def _rule_bindings(rule: _Rule, index: _FactIndex, objects, members, static, fluent,
                   delta: Optional[List[Fact]]) -> Iterator[Binding]:
    """Complete bindings of the rule's parameters whose positive atoms are all reachable and
    (after the first round) at least one of which uses a fact from `delta`."""
    types = dict(rule.params)
    if delta is None:
        partials = _join(list(rule.positive), {}, index, types, members)
    else:
        fluent_positions = [i for i, a in enumerate(rule.positive) if a.predicate in fluent]
        if not fluent_positions:
            return
        by_pred: Dict[str, List[Fact]] = defaultdict(list)
        for fact in delta:
            by_pred[fact[0]].append(fact)
        partials = (
            full
            for i in fluent_positions
            for fact in by_pred.get(rule.positive[i].predicate, ())
            for start in [_match(rule.positive[i], fact, {}, types, members)] if start is not None
            for full in _join(list(rule.positive[:i] + rule.positive[i + 1:]), start, index, types, members)
        )
    for partial in partials:
        free = [(v, t) for v, t in rule.params if v not in partial]
        for values in product(*(objects.get(t, ()) for _, t in free)):
            binding = dict(partial)
            binding.update(zip((v for v, _ in free), values))
            if all(_term(e.left, binding) == _term(e.right, binding) for e in rule.equal) and \
               all(_term(e.left, binding) != _term(e.right, binding) for e in rule.unequal) and \
               all(_ground_atom(a, binding) not in static for a in rule.negative if a.predicate not in fluent):
                yield binding


def _match(atom: Atom, fact: Fact, binding: Binding, types, members) -> Optional[Binding]:
    if len(fact) != len(atom.args) + 1:
        return None
    out = binding
    for term, value in zip(atom.args, fact[1:]):
        if isinstance(term, Const):
            if term.name != value:
                return None
        elif term.name in out:
            if out[term.name] != value:
                return None
        else:
            if value not in members.get(types.get(term.name, "object"), ()):
                return None
            if out is binding:
                out = dict(binding)
            out[term.name] = value
    return out


def _join(atoms: List[Atom], binding: Binding, index: _FactIndex, types, members) -> Iterator[Binding]:
    if not atoms:
        yield binding
        return
    best, candidates = 0, None
    for i, atom in enumerate(atoms):  # the atom with the fewest matching facts goes next
        options = index.by_pred.get(atom.predicate, [])
        for pos, term in enumerate(atom.args):
            value = term.name if isinstance(term, Const) else binding.get(term.name)
            if value is not None:
                narrowed = index.by_pos.get((atom.predicate, pos, value), [])
                if len(narrowed) < len(options):
                    options = narrowed
        if candidates is None or len(options) < len(candidates):
            best, candidates = i, options
        if not candidates:
            return
    atom, rest = atoms[best], atoms[:best] + atoms[best + 1:]
    for fact in list(candidates):
        extended = _match(atom, fact, binding, types, members)
        if extended is not None:
            yield from _join(rest, extended, index, types, members)


def _literal_masks(literals: Sequence[Literal], binding, fact_ids, static, fluent) -> Optional[Tuple[int, int]]:
    """(required-true mask, required-false mask) of a conjunction; None if it can never hold."""
    pre = neg = 0
    for lit in literals:
        if isinstance(lit.atom, Equals):
            if (_term(lit.atom.left, binding) == _term(lit.atom.right, binding)) != lit.positive:
                return None
            continue
        fact = _ground_atom(lit.atom, binding)
        if fact[0] not in fluent:
            if (fact in static) != lit.positive:
                return None
        elif fact in fact_ids:
            if lit.positive:
                pre |= 1 << fact_ids[fact]
            else:
                neg |= 1 << fact_ids[fact]
        elif lit.positive:  # a fluent never reachable
            return None
    return pre, neg


def _make_operator(rule: _Rule, binding: Binding, fact_ids, static, fluent) -> Optional[Operator]:
    pre = 0
    for atom in rule.positive:
        fact = _ground_atom(atom, binding)
        if fact[0] in fluent:
            pre |= 1 << fact_ids[fact]
    neg = 0
    for atom in rule.negative:
        fact = _ground_atom(atom, binding)
        if fact[0] in fluent and fact in fact_ids:
            neg |= 1 << fact_ids[fact]
    if pre & neg:
        return None
    add = delete = 0
    conditional: List[ConditionalEffect] = []
    for part in rule.effects:
        part_add = part_del = 0
        for lit in part.literals:
            fact = _ground_atom(lit.atom, binding)
            if fact in fact_ids:
                if lit.positive:
                    part_add |= 1 << fact_ids[fact]
                else:
                    part_del |= 1 << fact_ids[fact]
        for conj in part.condition:
            masks = _literal_masks(conj, binding, fact_ids, static, fluent)
            if masks is None:
                continue
            if masks == (0, 0):
                add, delete = add | part_add, delete | part_del
            else:
                conditional.append(ConditionalEffect(masks[0], masks[1], part_add, part_del))
    args = tuple(binding[v] for v, _ in rule.params)
    return Operator(rule.action, args, pre, neg, add, delete, tuple(conditional))


def _set_goal(task: StripsTask, problem: Problem, objects, static, fluent) -> None:
    """A conjunctive goal becomes masks; a disjunctive one an artificial goal fact."""
    alternatives = []
    for conj in dnf(problem.goal, objects):
        for lit in conj:  # a goal fact no operator can reach still gets an id: unsolvable
            if isinstance(lit.atom, Atom) and lit.positive and lit.atom.predicate in fluent:
                fact = _ground_atom(lit.atom, {})
                if fact not in task.fact_ids:
                    task.fact_ids[fact] = len(task.facts)
                    task.facts.append(fact)
        masks = _literal_masks(conj, {}, task.fact_ids, static, fluent)
        if masks is not None:
            alternatives.append(masks)
    if len(alternatives) == 1:
        task.goal, task.goal_neg = alternatives[0]
        return
    goal_fact = len(task.facts)
    task.facts.append(("<goal>",))
    task.fact_ids[("<goal>",)] = goal_fact
    for i, (pre, neg) in enumerate(alternatives):
        task.operators.append(Operator("reach-goal", (str(i),), pre, neg, 1 << goal_fact, 0, artificial=True))
    task.goal = 1 << goal_fact
