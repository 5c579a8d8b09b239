"""Formulas -> disjunctive normal form over literals, expanding quantifiers over objects.

Grounding turns each disjunct of a precondition into its own STRIPS operator; effects are
flattened into (condition DNF, add/delete literals) pairs.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Mapping, Sequence, Set, Tuple, Union

from ..lang.errors import PddlError
from ..lang.nodes import And, Atom, Const, Equals, Exists, Forall, Formula, Imply, Not, Or, Term, Var, When

MAX_DISJUNCTS = 4096


@dataclass(frozen=True)
class Literal:
    """An atom or an equality, possibly negated. Terms are Var or Const."""

    positive: bool
    atom: Union[Atom, Equals]


Conjunction = Tuple[Literal, ...]


def substitute(f: Formula, binding: Mapping[str, str]) -> Formula:
    """Replace bound variables by constants (quantifier expansion); locations are kept for errors."""
    def term(t: Term) -> Term:
        return Const(binding[t.name]) if isinstance(t, Var) and t.name in binding else t

    if isinstance(f, Atom):
        return Atom(f.predicate, tuple(term(a) for a in f.args), f.loc)
    if isinstance(f, Equals):
        return Equals(term(f.left), term(f.right), f.loc)
    if isinstance(f, Not):
        return Not(substitute(f.body, binding), f.loc)
    if isinstance(f, (And, Or)):
        return type(f)(tuple(substitute(p, binding) for p in f.parts), f.loc)
    if isinstance(f, Imply):
        return Imply(substitute(f.condition, binding), substitute(f.consequence, binding), f.loc)
    if isinstance(f, (Forall, Exists)):
        inner = {k: v for k, v in binding.items() if k not in {v.name for v in f.variables}}
        return type(f)(f.variables, substitute(f.body, inner), f.loc)
    if isinstance(f, When):
        return When(substitute(f.condition, binding), substitute(f.effect, binding), f.loc)
    raise TypeError(f"not a formula: {f!r}")


def expand_quantifier(f: Union[Forall, Exists], objects_by_type: Mapping[str, Sequence[str]]) -> List[Formula]:
    """One instance of the body per assignment of objects to the quantified variables."""
    bodies = [f.body]
    for var in f.variables:
        bodies = [substitute(b, {var.name: o}) for b in bodies for o in objects_by_type.get(var.type, ())]
    return bodies


def dnf(f: Formula, objects_by_type: Mapping[str, Sequence[str]], positive: bool = True) -> List[Conjunction]:
    """The formula (negated if not `positive`) as a list of conjunctions of literals.

    One Python frame per level of nesting (formulas may nest ~500 deep), and at most
    `MAX_DISJUNCTS` alternatives at any level: nested quantifiers grow exponentially."""
    if isinstance(f, (Atom, Equals)):
        return [(Literal(positive, f),)]
    if isinstance(f, Not):
        return dnf(f.body, objects_by_type, not positive)
    loc = f.loc
    if isinstance(f, Imply):
        f = Or((Not(f.condition), f.consequence))
    if isinstance(f, (Forall, Exists)):
        parts = expand_quantifier(f, objects_by_type)
        f = And(tuple(parts)) if isinstance(f, Forall) else Or(tuple(parts))
    if isinstance(f, (And, Or)):
        conjunctive = isinstance(f, And) == positive
        result: List[Conjunction] = [()] if conjunctive else []
        for part in f.parts:
            branch = dnf(part, objects_by_type, positive)
            result = [left + right for left in result for right in branch] if conjunctive else result + branch
            if len(result) > MAX_DISJUNCTS:
                raise PddlError(f"formula expands to more than {MAX_DISJUNCTS} alternatives", loc)
        return result
    raise PddlError(f"'{type(f).__name__.lower()}' cannot appear here", loc)


def holds(f: Formula, facts: Set[Tuple[str, ...]], objects_by_type: Mapping[str, Sequence[str]] = {},
          binding: Mapping[str, str] = {}) -> bool:
    """Whether condition `f` holds on `facts` (ground atoms as tuples, closed world) under
    `binding`; quantified variables range over `objects_by_type`."""
    def value(term: Term) -> str:
        return binding.get(term.name, term.name)

    for conjunction in dnf(f, objects_by_type):
        if all(((literal.atom.predicate, *map(value, literal.atom.args)) in facts if isinstance(literal.atom, Atom)
                else value(literal.atom.left) == value(literal.atom.right)) == literal.positive
               for literal in conjunction):
            return True
    return False


@dataclass(frozen=True)
class EffectPart:
    """Literals made true/false when `condition` (a DNF; [()] = always) holds before the step."""

    condition: Tuple[Conjunction, ...]
    literals: Tuple[Literal, ...]


def flatten_effect(f: Formula, objects_by_type: Mapping[str, Sequence[str]]) -> List[EffectPart]:
    """An effect as unconditional and conditional parts, with `forall` expanded."""
    parts: List[EffectPart] = []
    unconditional: List[Literal] = []

    def walk(g: Formula, condition: Tuple[Conjunction, ...]) -> None:
        if isinstance(g, Atom):
            (unconditional if condition == ((),) else pending.setdefault(condition, [])).append(Literal(True, g))
        elif isinstance(g, Not):
            (unconditional if condition == ((),) else pending.setdefault(condition, [])).append(Literal(False, g.body))
        elif isinstance(g, And):
            for p in g.parts:
                walk(p, condition)
        elif isinstance(g, Forall):
            for body in expand_quantifier(g, objects_by_type):
                walk(body, condition)
        elif isinstance(g, When):
            walk(g.effect, tuple(dnf(g.condition, objects_by_type)))
        else:
            raise PddlError(f"'{type(g).__name__.lower()}' cannot appear in an effect", getattr(g, "loc", None))

    pending: Dict[Tuple[Conjunction, ...], List[Literal]] = {}
    walk(f, ((),))
    if unconditional:
        parts.append(EffectPart(((),), tuple(unconditional)))
    parts.extend(EffectPart(cond, tuple(lits)) for cond, lits in pending.items())
    return parts
