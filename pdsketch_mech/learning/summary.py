"""A freshly extracted mechanism in plain words: what it needs, what it promises, and what
lifting left general (which roles any object may fill, which may coincide). What the roles
may be is what the planner will ground them with: the mechanism's precondition and what its
steps' basis operators need (a pushed object is never fixed, nothing rests on itself)."""
from __future__ import annotations

from itertools import combinations
from typing import Dict, List, Sequence, Set, Tuple

from ..lang.nodes import Action, And, Atom, Equals, Formula, Mechanism, Not, Var
from ..lang.writer import formula
from .lifting import rename_terms

# How a basis fact reads; anything else is written as it is in the fragment.
WORDS = {"support": "{0} rests on {1}", "holding": "{0} is held", "handempty": "the hand is empty",
         "fixed": "{0} is fixed"}


def _literals(f: Formula) -> List[Tuple[bool, Formula]]:
    if isinstance(f, And):
        return [lit for part in f.parts for lit in _literals(part)]
    if isinstance(f, Not):
        return [(not positive, body) for positive, body in _literals(f.body)]
    return [(True, f)]


def _words(positive: bool, f: Formula, names: Dict[str, str]) -> str:
    def name(term) -> str:
        shown = names.get(term.name)
        return f"{term.name} ({shown})" if shown else term.name
    if isinstance(f, Equals):
        return f"{name(f.left)} is {'' if positive else 'not '}{name(f.right)}"
    if isinstance(f, Atom) and f.predicate in WORDS:
        text = WORDS[f.predicate].format(*(name(a) for a in f.args))
        return text if positive else f"not: {text}"
    return formula(f) if positive else f"(not {formula(f)})"


def _step_needs(mechanism: Mechanism, actions: Sequence[Action]) -> List[Tuple[bool, Formula]]:
    """What the mechanism's steps need, in its own variables (`actions`: the basis operators)."""
    by_name = {a.name: a for a in actions}
    out: List[Tuple[bool, Formula]] = []
    for call in mechanism.actions:
        action = by_name.get(call.name)
        if action is not None and len(action.parameters) == len(call.args):
            names = {p.name: a.name for p, a in zip(action.parameters, call.args) if isinstance(a, Var)}
            out += [(positive, rename_terms(f, names)) for positive, f in _literals(action.precondition)]
    return out


def mechanism_summary(mechanism: Mechanism, demo_objects: Dict[str, str],
                      actions: Sequence[Action] = ()) -> List[str]:
    """Lines saying what `mechanism` needs and certifies (`demo_objects`: variable -> the
    demonstration's object, shown beside it once), and what lifting left open, as the planner
    grounds it (`actions`: the basis operators its steps are, whose needs narrow that)."""
    needs = _literals(mechanism.precondition)
    certifies = _literals(mechanism.certified)
    grounded = needs + _step_needs(mechanism, actions)   # what a grounding must satisfy
    lines = [f"{mechanism.name} needs: " + "; ".join(_words(p, f, demo_objects) for p, f in needs),
             f"{mechanism.name} certifies: " + "; ".join(_words(p, f, {}) for p, f in certifies)]
    lines += [f"after step {k} ({call.name}), physics: " + "; ".join(_words(p, f, {}) for p, f in _literals(call.then))
              for k, call in enumerate(mechanism.actions, 1) if _literals(call.then)]
    objects = [p.name for p in mechanism.parameters if p.name in demo_objects]
    fixed = _fixed_literals(grounded, True)
    movable = _fixed_literals(grounded, False) - fixed
    apart: Set[frozenset] = {frozenset((f.left.name, f.right.name)) for p, f in grounded
                             if not p and isinstance(f, Equals) and isinstance(f.left, Var) and isinstance(f.right, Var)}
    # Nothing rests on itself: what rests on what is two bodies.
    apart |= {frozenset(a.name for a in f.args) for p, f in grounded + certifies
              if p and isinstance(f, Atom) and f.predicate == "support" and all(isinstance(a, Var) for a in f.args)}
    kinds = [("any movable object may be", [o for o in objects if o in movable]),
             ("any object, fixed or not, may be", [o for o in objects if o not in fixed and o not in movable])]
    said = [f"{words} {', '.join(names)}" for words, names in kinds if names]
    said += [f"{', '.join(sorted(o for o in objects if o in fixed))} must be fixed"] if fixed & set(objects) else []
    if said:
        lines.append("; ".join(said))
    # Surfaces (what something rests on) that nothing keeps apart may be one body or two: a
    # landing place unified with the tool's support, for instance.
    surfaces = sorted({f.args[1].name for _, f in needs + certifies
                       if isinstance(f, Atom) and f.predicate == "support" and len(f.args) == 2})
    same = [f"{a} and {b}" for a, b in combinations(surfaces, 2) if frozenset((a, b)) not in apart]
    if same:
        lines.append("may be one object or two: " + ", ".join(same))
    return lines


def _fixed_literals(literals: List[Tuple[bool, Formula]], positive: bool) -> Set[str]:
    """The variables `(fixed ?x)` (positive) or `(not (fixed ?x))` names."""
    return {f.args[0].name for p, f in literals
            if p == positive and isinstance(f, Atom) and f.predicate == "fixed" and isinstance(f.args[0], Var)}
