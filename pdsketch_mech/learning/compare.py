"""Are two mechanisms the same up to variable names? And if not, what differs?

The variable correspondence is read off the steps (unifying the two `:actions` lists
argument by argument); parameters that no step uses are matched in order among those of the
same type. Preconditions compare as sets of conjuncts (their order is presentation).
"""
from __future__ import annotations

from typing import Dict, List, Optional

from ..lang.nodes import And, Formula, Mechanism, Var
from ..lang.writer import formula as formula_text
from .lifting import rename_terms


def _conjuncts(f: Formula) -> List[Formula]:
    return list(f.parts) if isinstance(f, And) else [f]


def _same(a: Formula, b: Formula) -> bool:
    """Whether two conjunctions say the same, in any order."""
    return {formula_text(f) for f in _conjuncts(a)} == {formula_text(f) for f in _conjuncts(b)}


def correspondence(a: Mechanism, b: Mechanism) -> Optional[Dict[str, str]]:
    """A renaming of a's variables into b's that the steps agree on, or None."""
    if [c.name for c in a.actions] != [c.name for c in b.actions]:
        return None
    mapping: Dict[str, str] = {}
    for ca, cb in zip(a.actions, b.actions):
        if len(ca.args) != len(cb.args):
            return None
        for x, y in zip(ca.args, cb.args):
            if isinstance(x, Var) != isinstance(y, Var):
                return None
            if not isinstance(x, Var):
                if x.name != y.name:
                    return None
                continue
            if mapping.setdefault(x.name, y.name) != y.name:
                return None
    if len(set(mapping.values())) != len(mapping):
        return None
    left = [p for p in a.parameters if p.name not in mapping]
    right = [p for p in b.parameters if p.name not in set(mapping.values())]
    for p in left:
        match = next((q for q in right if q.type == p.type), None)
        if match is None:
            return None
        right.remove(match)
        mapping[p.name] = match.name
    return mapping


def differences(existing: Mechanism, new: Mechanism) -> List[str]:
    """What differs between two mechanisms, up to variable names; [] if they are equivalent."""
    out: List[str] = []
    if existing.name != new.name:
        out.append(f"the mechanism's name: {existing.name} vs {new.name}")
    mapping = correspondence(existing, new)
    if mapping is None:
        steps = lambda m: " ".join(f"({c.name} ...)" for c in m.actions)  # noqa: E731
        out.append(f"the steps: {steps(existing)} vs {steps(new)}")
        return out
    types_a = sorted((mapping[p.name], p.type) for p in existing.parameters)
    types_b = sorted((p.name, p.type) for p in new.parameters)
    if types_a != types_b:
        out.append("the parameters (after renaming): "
                   f"{' '.join(f'{n} - {t}' for n, t in types_a)} vs {' '.join(f'{n} - {t}' for n, t in types_b)}")
    pre_a = {formula_text(f) for f in _conjuncts(rename_terms(existing.precondition, mapping))}
    pre_b = {formula_text(f) for f in _conjuncts(new.precondition)}
    if pre_a - pre_b:
        out.append(f"the precondition: only the existing fragment has {' '.join(sorted(pre_a - pre_b))}")
    if pre_b - pre_a:
        out.append(f"the precondition: only the extracted one has {' '.join(sorted(pre_b - pre_a))}")
    cert_a, cert_b = rename_terms(existing.certified, mapping), new.certified
    if not _same(cert_a, cert_b):
        out.append(f"the certified effect: {formula_text(cert_a)} vs {formula_text(cert_b)}")
    for k, (ca, cb) in enumerate(zip(existing.actions, new.actions), 1):
        then_a, then_b = rename_terms(ca.then, mapping), cb.then
        if not _same(then_a, then_b):
            said = [formula_text(f) if _conjuncts(f) else "nothing" for f in (then_a, then_b)]
            out.append(f"what physics does after step {k} (:then): {said[0]} vs {said[1]}")
    if existing.sampler != new.sampler:
        out.append(f"the sampler: {existing.sampler or 'generic'} vs {new.sampler or 'generic'}")
    return out


def equivalent(a: Mechanism, b: Mechanism) -> bool:
    return not differences(a, b)
