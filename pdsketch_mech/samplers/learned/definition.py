"""Which definitions of a mechanism a checkpoint serves: the one it was trained for, and any
that only narrows it.

A checkpoint's classifiers read the mechanism's objects by their place in its parameter list
and its values by name, and were trained on what its steps did and whether its certified
facts held. A definition that differs only in what its object parameters are called, or in
preconditions added (fewer groundings, each one the classifiers were trained on), asks them
nothing new: the checkpoint serves it. Anything else (other steps, other certified facts, a
precondition dropped, a value renamed, a parameter of another type) does not, and the
checkpoint is refused as before. The case in point: extraction learning to pin a landing
place, which renames `?object` to `?landing` and adds `(fixed ?landing)` and inequalities.
"""
from __future__ import annotations

import hashlib
import re
from dataclasses import replace
from typing import AbstractSet, FrozenSet, Optional, Tuple

from ...lang.errors import PddlError
from ...lang.nodes import TRUE, And, Domain, Mechanism
from ...lang.parser import parse_text
from ...lang.writer import formula, write_mechanism

_VARIABLE = re.compile(r"\?[^\s()]+")


def definition_text(mechanism: Mechanism) -> str:
    """The mechanism as written, without its `:sampler` (what a checkpoint records)."""
    return write_mechanism(replace(mechanism, sampler=None))


def mechanism_hash(mechanism: Mechanism) -> str:
    """sha256 of `definition_text`: the exact definition a checkpoint was trained for."""
    return hashlib.sha256(definition_text(mechanism).encode()).hexdigest()


def serves(trained: Optional[str], trained_hash: Optional[str], mechanism: Mechanism,
           value_names: AbstractSet[str]) -> bool:
    """Whether classifiers trained for the definition `trained` (its text, checked against
    `trained_hash`) serve `mechanism`: the same definition, or one that renames object
    parameters and adds preconditions only. `value_names`: the variables the classifiers
    name (they must keep their names and places)."""
    if trained_hash == mechanism_hash(mechanism):
        return True
    if not isinstance(trained, str) or hashlib.sha256(trained.encode()).hexdigest() != trained_hash:
        return False
    old = _parse(trained)
    if old is None or old.name != mechanism.name or len(old.parameters) != len(mechanism.parameters):
        return False
    for before, now in zip(old.parameters, mechanism.parameters):
        if before.type != now.type or ((before.name in value_names or now.name in value_names)
                                       and before.name != now.name):
            return False
    old_shape, old_needs = _by_place(old)
    new_shape, new_needs = _by_place(mechanism)
    return old_shape == new_shape and old_needs <= new_needs


def _parse(text: str) -> Optional[Mechanism]:
    try:
        node = parse_text(f"(define (domain checkpoint) (:requirements :mechanisms) {text})", "<checkpoint>")
    except (PddlError, RecursionError):   # a metadata file written by hand: not a definition
        return None
    return node.mechanisms[0] if isinstance(node, Domain) and len(node.mechanisms) == 1 else None


def _by_place(mechanism: Mechanism) -> Tuple[str, FrozenSet[str]]:
    """The definition without its precondition, and the precondition's conjuncts, with every
    parameter named by its place in the list."""
    places = {p.name: f"?{i}" for i, p in enumerate(mechanism.parameters)}

    def renamed(text: str) -> str:
        return _VARIABLE.sub(lambda m: places.get(m.group(0), m.group(0)), text)
    pre = mechanism.precondition
    parts = pre.parts if isinstance(pre, And) else (pre,)
    shape = renamed(write_mechanism(replace(mechanism, precondition=TRUE, sampler=None)))
    return shape, frozenset(renamed(formula(p)) for p in parts)
