"""A freshly extracted mechanism in plain words: what it needs, what it promises, and what
lifting left general (which roles any object may fill, which may coincide)."""
from __future__ import annotations

from itertools import combinations
from typing import Dict, List, Set, Tuple

from ..lang.nodes import And, Atom, Equals, Formula, Mechanism, Not
from ..lang.writer import formula

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


def mechanism_summary(mechanism: Mechanism, demo_objects: Dict[str, str]) -> List[str]:
    """Lines saying what `mechanism` needs and certifies (`demo_objects`: variable -> the
    demonstration's object, shown beside it once), and what lifting left open."""
    needs = _literals(mechanism.precondition)
    certifies = _literals(mechanism.certified)
    lines = [f"{mechanism.name} needs: " + "; ".join(_words(p, f, demo_objects) for p, f in needs),
             f"{mechanism.name} certifies: " + "; ".join(_words(p, f, {}) for p, f in certifies)]
    objects = [p.name for p in mechanism.parameters if p.name in demo_objects]
    fixed = {f.args[0].name for p, f in needs if p and isinstance(f, Atom) and f.predicate == "fixed"}
    apart: Set[frozenset] = {frozenset((f.left.name, f.right.name)) for p, f in needs
                             if not p and isinstance(f, Equals)}
    free = [o for o in objects if o not in fixed]
    if free:
        lines.append(f"any object, fixed or not, may be {', '.join(free)}"
                     + (f"; {', '.join(sorted(fixed))} must be fixed" if fixed else ""))
    # Surfaces (what something rests on) that nothing keeps apart may be one body or two: a
    # landing place unified with the tool's support, for instance.
    surfaces = sorted({f.args[1].name for _, f in needs + certifies
                       if isinstance(f, Atom) and f.predicate == "support" and len(f.args) == 2})
    same = [f"{a} and {b}" for a, b in combinations(surfaces, 2) if frozenset((a, b)) not in apart]
    if same:
        lines.append("may be one object or two: " + ", ".join(same))
    return lines
