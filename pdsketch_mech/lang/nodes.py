"""The syntax tree of the PDDL dialect: small frozen dataclasses.

Every node carries a source location (`loc`) that is excluded from equality, so a tree
parsed from text equals the tree parsed from its written-back form. Names are stored
lower-case (PDDL names are case-insensitive); strings keep their case.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional, Tuple, Union


@dataclass(frozen=True)
class Loc:
    """Where a node starts in its source file (1-based line and column)."""

    file: str
    line: int
    col: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


def _loc() -> Optional[Loc]:
    return field(default=None, compare=False, repr=False)


# ----------------------------------------------------------------------------- terms
@dataclass(frozen=True)
class Var:
    """A variable such as `?x` (the name keeps its leading `?`)."""

    name: str
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Const:
    """A reference to a named object or constant."""

    name: str
    loc: Optional[Loc] = _loc()


Term = Union[Var, Const]


@dataclass(frozen=True)
class TypedName:
    """A declared name with its type: a type and its parent, an object, or a parameter."""

    name: str
    type: str = "object"
    loc: Optional[Loc] = _loc()


# ----------------------------------------------------------------------------- formulas
@dataclass(frozen=True)
class Atom:
    predicate: str
    args: Tuple[Term, ...] = ()
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Equals:
    left: Term
    right: Term
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Not:
    body: "Formula"
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class And:
    parts: Tuple["Formula", ...] = ()
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Or:
    parts: Tuple["Formula", ...] = ()
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Imply:
    condition: "Formula"
    consequence: "Formula"
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Forall:
    variables: Tuple[TypedName, ...]
    body: "Formula"
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Exists:
    variables: Tuple[TypedName, ...]
    body: "Formula"
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class When:
    """A conditional effect; only legal inside an action's `:effect`."""

    condition: "Formula"
    effect: "Formula"
    loc: Optional[Loc] = _loc()


Formula = Union[Atom, Equals, Not, And, Or, Imply, Forall, Exists, When]

TRUE = And(())


# ----------------------------------------------------------------------------- domain
@dataclass(frozen=True)
class Predicate:
    name: str
    parameters: Tuple[TypedName, ...] = ()
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Action:
    """An operator schema; basis operators take continuous (value-typed) parameters too."""

    name: str
    parameters: Tuple[TypedName, ...] = ()
    precondition: Formula = TRUE
    effect: Formula = TRUE
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Stream:
    """A PDDLStream-style conditional generator, implemented by the Python sampler `sampler`.

    A stream without outputs is a test. When `sampler` is None the stream's own name is used.
    """

    name: str
    inputs: Tuple[TypedName, ...] = ()
    domain: Formula = TRUE
    outputs: Tuple[TypedName, ...] = ()
    certified: Formula = TRUE
    sampler: Optional[str] = None
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class ActionCall:
    """One step of a mechanism: a basis operator applied to the mechanism's variables."""

    name: str
    args: Tuple[Term, ...] = ()
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Mechanism:
    """A macro of basis operators with its own sampler (paper Sec. 2.2)."""

    name: str
    parameters: Tuple[TypedName, ...] = ()
    precondition: Formula = TRUE
    certified: Formula = TRUE
    actions: Tuple[ActionCall, ...] = ()
    sampler: Optional[str] = None
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Domain:
    name: str
    requirements: Tuple[str, ...] = ()
    extends: Tuple[str, ...] = ()
    types: Tuple[TypedName, ...] = ()
    value_types: Tuple[TypedName, ...] = ()
    constants: Tuple[TypedName, ...] = ()
    predicates: Tuple[Predicate, ...] = ()
    actions: Tuple[Action, ...] = ()
    streams: Tuple[Stream, ...] = ()
    mechanisms: Tuple[Mechanism, ...] = ()
    loc: Optional[Loc] = _loc()


# ----------------------------------------------------------------------------- problem
@dataclass(frozen=True)
class Symbol:
    """A bare name used as a scene value (as opposed to a quoted string)."""

    name: str


SceneValue = Union[float, str, Symbol, Tuple["SceneValue", ...]]


@dataclass(frozen=True)
class SceneProp:
    """`:key value` in a scene entry; `value` is None for a bare flag such as `:fixed`."""

    key: str
    value: Optional[SceneValue] = None
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class SceneEntry:
    name: str
    props: Tuple[SceneProp, ...] = ()
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True)
class Problem:
    name: str
    domain_name: str
    requirements: Tuple[str, ...] = ()
    objects: Tuple[TypedName, ...] = ()
    init: Tuple[Atom, ...] = ()
    goal: Formula = TRUE
    scene: Optional[Tuple[SceneEntry, ...]] = None
    loc: Optional[Loc] = _loc()
