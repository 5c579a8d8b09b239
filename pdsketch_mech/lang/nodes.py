"""The syntax tree of the PDDL dialect: small frozen dataclasses.

Every node carries a source location (`loc`) that is excluded from equality, so a tree
parsed from text equals the tree parsed from its written-back form. Names are stored
lower-case (PDDL names are case-insensitive); strings keep their case. Nodes use slots:
a problem may declare millions of objects.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Optional, Tuple, Union


@dataclass(frozen=True, slots=True)
class Loc:
    """Where a node starts in its source file (1-based line and column)."""

    file: str
    line: int
    col: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


@dataclass(frozen=True, slots=True)
class RunLoc(Loc):
    """Where a run of declared names (`a b - block c`) starts, shared by all its names.

    One location per run instead of one per name keeps a problem with a million objects
    small; `name_loc(k)` finds the run's k-th declared name when an error needs it."""

    text: str = ""

    def name_loc(self, index: int) -> Loc:
        """The location of the run's `index`-th declared name (0-based; `- type` skipped)."""
        line, col = self.line, self.col
        typed = False  # the previous word was '-': this one is a type
        for match in _WORD_AND_GAP.finditer(self.text):
            word, gap = match.groups()
            if word == "-" or typed:
                typed = word == "-"
            elif index == 0:
                break
            else:
                index -= 1
            if "\n" in gap:
                line, col = line + gap.count("\n"), len(gap) - gap.rfind("\n")
            else:
                col += match.end() - match.start()
        return Loc(self.file, line, col)

    def dash_loc(self, index: int) -> Loc:
        """The location of the run's `index`-th ` - ` before a type (0-based)."""
        offset = [m.start() for m in _DASH.finditer(self.text)][index]
        before = self.text[:offset]
        if "\n" in before:
            return Loc(self.file, self.line + before.count("\n"), offset - before.rfind("\n"))
        return Loc(self.file, self.line, self.col + offset)


_WORD_AND_GAP = re.compile(r"(\S+)(\s*)")
_DASH = re.compile(r"(?<=\s)-(?=\s)")


def _loc() -> Optional[Loc]:
    return field(default=None, compare=False, repr=False)


# ----------------------------------------------------------------------------- terms
@dataclass(frozen=True, slots=True)
class Var:
    """A variable such as `?x` (the name keeps its leading `?`)."""

    name: str
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class Const:
    """A reference to a named object or constant."""

    name: str
    loc: Optional[Loc] = _loc()


Term = Union[Var, Const]


@dataclass(frozen=True, slots=True)
class TypedName:
    """A declared name with its type: a type and its parent, an object, or a parameter."""

    name: str
    type: str = "object"
    loc: Optional[Loc] = _loc()


# ----------------------------------------------------------------------------- formulas
@dataclass(frozen=True, slots=True)
class Atom:
    predicate: str
    args: Tuple[Term, ...] = ()
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class Equals:
    left: Term
    right: Term
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class Not:
    body: "Formula"
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class And:
    parts: Tuple["Formula", ...] = ()
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class Or:
    parts: Tuple["Formula", ...] = ()
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class Imply:
    condition: "Formula"
    consequence: "Formula"
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class Forall:
    variables: Tuple[TypedName, ...]
    body: "Formula"
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class Exists:
    variables: Tuple[TypedName, ...]
    body: "Formula"
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class When:
    """A conditional effect; only legal inside an action's `:effect`."""

    condition: "Formula"
    effect: "Formula"
    loc: Optional[Loc] = _loc()


Formula = Union[Atom, Equals, Not, And, Or, Imply, Forall, Exists, When]

TRUE = And(())


# ----------------------------------------------------------------------------- domain
@dataclass(frozen=True, slots=True)
class Predicate:
    name: str
    parameters: Tuple[TypedName, ...] = ()
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class Action:
    """An operator schema; basis operators take continuous (value-typed) parameters too."""

    name: str
    parameters: Tuple[TypedName, ...] = ()
    precondition: Formula = TRUE
    effect: Formula = TRUE
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
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


@dataclass(frozen=True, slots=True)
class ActionCall:
    """One step of a mechanism: a basis operator applied to the mechanism's variables, and
    what physics makes so after it beyond the operator's effect (`:then`, a conjunction of
    facts and negated facts; TRUE when nothing)."""

    name: str
    args: Tuple[Term, ...] = ()
    loc: Optional[Loc] = _loc()
    then: Formula = TRUE


@dataclass(frozen=True, slots=True)
class Mechanism:
    """A macro of basis operators with its own sampler (paper Sec. 2.2)."""

    name: str
    parameters: Tuple[TypedName, ...] = ()
    precondition: Formula = TRUE
    certified: Formula = TRUE
    actions: Tuple[ActionCall, ...] = ()
    sampler: Optional[str] = None
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class Domain:
    name: str
    requirements: Tuple[str, ...] = ()
    extends: Tuple[str, ...] = ()
    vocabulary: Optional[str] = None   # the basis vocabulary the planner reads (operators/vocabulary.py)
    vocabulary_loc: Optional[Loc] = _loc()
    types: Tuple[TypedName, ...] = ()
    value_types: Tuple[TypedName, ...] = ()
    constants: Tuple[TypedName, ...] = ()
    predicates: Tuple[Predicate, ...] = ()
    actions: Tuple[Action, ...] = ()
    streams: Tuple[Stream, ...] = ()
    mechanisms: Tuple[Mechanism, ...] = ()
    loc: Optional[Loc] = _loc()


# ----------------------------------------------------------------------------- problem
@dataclass(frozen=True, slots=True)
class Symbol:
    """A bare name used as a scene value (as opposed to a quoted string)."""

    name: str


SceneValue = Union[float, str, Symbol, Tuple["SceneValue", ...]]


@dataclass(frozen=True, slots=True)
class SceneProp:
    """`:key value` in a scene entry; `value` is None for a bare flag such as `:fixed`."""

    key: str
    value: Optional[SceneValue] = None
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class SceneEntry:
    name: str
    props: Tuple[SceneProp, ...] = ()
    loc: Optional[Loc] = _loc()


@dataclass(frozen=True, slots=True)
class Problem:
    name: str
    domain_name: str
    requirements: Tuple[str, ...] = ()
    objects: Tuple[TypedName, ...] = ()
    init: Tuple[Atom, ...] = ()
    goal: Formula = TRUE
    scene: Optional[Tuple[SceneEntry, ...]] = None
    loc: Optional[Loc] = _loc()
