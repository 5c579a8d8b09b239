"""Text -> syntax tree (`nodes`), with Lark (LALR, contextual lexer) and `grammar.lark`.

Syntax problems are raised as `PddlError` carrying `file:line:col`; no Lark exception
escapes this module. Nothing here recurses over the input: the parse tree is transformed
without recursion, and nesting deeper than `source.MAX_NESTING` parentheses is rejected up front
so that the recursive passes downstream (type checking, normalisation) stay within
Python's stack.
"""
from __future__ import annotations

import contextlib
import functools
import gc
import hashlib
import json
import math
import os
import re
import sys
from dataclasses import replace
from typing import Callable, Iterator, List, Tuple, Union

import lark
from lark import Lark, Token, Transformer_NonRecursive, v_args
from lark.exceptions import UnexpectedInput, VisitError
from lark.grammar import Rule
from lark.lexer import TerminalDef

from ..util import process
from ..util.disk_cache import entry_path, store
from .errors import PddlError, did_you_mean
from .nodes import (
    Action, ActionCall, And, Atom, Const, Domain, Equals, Exists, Forall, Imply, Loc, Mechanism,
    Not, Or, Predicate, Problem, RunLoc, SceneEntry, SceneProp, Stream, Symbol, TypedName, Var, When,
)
from .runs import split_atoms, split_predicates
from .source import check_nesting, read_text
from .syntax_errors import syntax_error

KNOWN_REQUIREMENTS = frozenset({
    ":strips", ":typing", ":negative-preconditions", ":disjunctive-preconditions", ":equality",
    ":existential-preconditions", ":universal-preconditions", ":quantified-preconditions",
    ":conditional-effects", ":adl", ":streams", ":mechanisms", ":scenes",
})



_GRAMMAR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "grammar.lark")
_OPTIONS = dict(parser="lalr", lexer="contextual", propagate_positions=True, maybe_placeholders=False)


@functools.lru_cache(maxsize=1)
def _lark() -> Lark:
    """The parser, built once per process and its tables cached on disk as JSON: data only,
    never unpickled, so a cache folder others can write cannot run code here (Lark's own
    `save`/`load` pickle). The entry is keyed by grammar, Lark version and options; a
    missing, stale or damaged one is rebuilt."""
    with open(_GRAMMAR, encoding="utf-8") as handle:
        grammar = handle.read()
    key = hashlib.sha256(f"{grammar}{lark.__version__}{sorted(_OPTIONS.items())}".encode()).hexdigest()[:16]
    name = f"grammar-{key}.json"
    try:
        with open(entry_path(name), encoding="utf-8") as handle:
            return Lark.__new__(Lark)._load(json.load(handle, object_hook=_integer_keys))
    except Exception:  # missing, stale or unreadable cache: rebuild below
        pass
    parser = Lark(grammar, **_OPTIONS)
    data, memo = parser.memo_serialize([TerminalDef, Rule])
    store(name, lambda handle: handle.write(json.dumps({"data": data, "memo": memo}).encode()))
    return parser


def _integer_keys(mapping: dict) -> dict:
    """JSON turns the tables' integer keys (states, memo ids) into strings; turn them back."""
    return {(int(key) if key.lstrip("-").isdigit() else key): value for key, value in mapping.items()}


def parse_text(text: str, file: str = "<input>") -> Union[Domain, Problem]:
    """Parse one `(define (domain ...))` or `(define (problem ...))` from `text`."""
    check_nesting(text, file)
    with _no_cycle_collection():
        try:
            tree = _lark().parse(text)
        except UnexpectedInput as exc:
            raise syntax_error(exc, text, file, _lark().terminals) from None
        try:
            return _ToNodes(file).transform(tree)
        except VisitError as exc:
            if isinstance(exc.orig_exc, (PddlError, MemoryError)):
                raise exc.orig_exc from None
            raise


@contextlib.contextmanager
def _no_cycle_collection() -> Iterator[None]:
    """Pause the cyclic garbage collector: parsing creates millions of objects and no cycles,
    and the collector's repeated passes over them would make parsing quadratic in practice
    (a 1.2-million-object problem: 3.3 s instead of 0.9 s). In a command, the nodes are then
    frozen out of the collector's view, or the passes come back while the file is checked
    (frozen objects are still freed by reference counting); a library caller's collector is
    left as it was."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if process.is_command():
            gc.freeze()
        if enabled:
            gc.enable()


def parse_file(path: str) -> Union[Domain, Problem]:
    """Parse the file at `path`; an unreadable file is a `PddlError` too."""
    return parse_text(read_text(path), path)


# ----------------------------------------------------------------------------- tree -> nodes
_TYPE_DASH = re.compile(r"\s+-\s+")  # inside a NAME_RUN token: `names - type names - type`


def _tagged(tag: str):
    """A transformer callback turning `(:key value)` into a (tag, value, loc) triple."""
    @v_args(meta=True)
    def build(self, meta, children):
        return tag, children[0] if children else (), self._loc(meta)
    return build


class _ToNodes(Transformer_NonRecursive):
    """Builds nodes bottom-up. Sections and properties come up as (tag, value, loc) triples."""

    def __init__(self, file: str):
        super().__init__()
        self.file = file

    def _loc(self, item) -> Loc:
        """The location of a token or of a rule's `meta`."""
        return Loc(self.file, item.line, item.column)

    def _fields(self, items, where: str) -> dict:
        """Collect (tag, value, loc) triples into a dict, rejecting repeats.

        Actions, streams and mechanisms arrive as nodes and are gathered in lists by class
        name; predicate sections may repeat and are concatenated.
        """
        out: dict = {}
        for item in items:
            if not isinstance(item, tuple):
                out.setdefault(type(item).__name__, []).append(item)
                continue
            tag, value, loc = item
            if tag == "predicates":
                out.setdefault(tag, []).extend(value)
            elif tag in out:
                raise PddlError(f"duplicate :{tag.replace('_', '-')} in {where}", loc)
            else:
                out[tag] = value
        return out

    # -- top level
    def start(self, children):
        return children[0]

    @v_args(meta=True)
    def domain(self, meta, children):
        name, *items = children
        f = self._fields(items, f"domain '{name.lower()}'")
        return Domain(
            name=name.lower(), requirements=f.get("requirements", ()), extends=f.get("extends", ()),
            vocabulary=(f.get("vocabulary") or (None, None))[0], vocabulary_loc=(f.get("vocabulary") or (None, None))[1],
            types=f.get("types", ()), value_types=f.get("value_types", ()),
            constants=f.get("constants", ()), predicates=tuple(f.get("predicates", ())),
            actions=tuple(f.get("Action", ())), streams=tuple(f.get("Stream", ())),
            mechanisms=tuple(f.get("Mechanism", ())), loc=self._loc(meta),
        )

    @v_args(meta=True)
    def problem(self, meta, children):
        name, *items = children
        f = self._fields(items, f"problem '{name.lower()}'")
        loc = self._loc(meta)
        if "domain" not in f:
            raise PddlError(f"problem '{name.lower()}' names no domain: add (:domain NAME)", loc)
        return Problem(
            name=name.lower(), domain_name=f["domain"], requirements=f.get("requirements", ()),
            objects=f.get("objects", ()), init=f.get("init", ()), goal=f.get("goal", And(())),
            scene=f.get("scene"), loc=loc,
        )

    # -- sections (tagged)
    @v_args(meta=True)
    def extends(self, meta, tokens):
        return "extends", tuple(t[1:-1] for t in tokens), self._loc(meta)

    @v_args(meta=True)
    def vocabulary(self, meta, tokens):
        return "vocabulary", (str(tokens[0]).lower(), self._loc(tokens[0])), self._loc(meta)

    @v_args(meta=True)
    def requirements(self, meta, tokens):
        for token in tokens:
            if token.lower() not in KNOWN_REQUIREMENTS:
                hint = did_you_mean(token.lower(), KNOWN_REQUIREMENTS)
                raise PddlError(f"unsupported requirement '{token}'{hint}", self._loc(token))
        return "requirements", tuple(t.lower() for t in tokens), self._loc(meta)

    types = _tagged("types")
    value_types = _tagged("value_types")
    constants = _tagged("constants")
    objects = _tagged("objects")

    def _with_runs(self, children, split) -> list:
        """The children, each run token (lang/runs.py) split into the items it holds."""
        out = []
        for child in children:
            if isinstance(child, Token):
                out.extend(split(self.file, child.value, child.line, child.column))
            else:
                out.append(child)
        return out

    @v_args(meta=True)
    def predicates(self, meta, children):
        return "predicates", self._with_runs(children, split_predicates), self._loc(meta)

    @v_args(meta=True)
    def problem_domain(self, meta, children):
        return "domain", children[0].lower(), self._loc(meta)

    @v_args(meta=True)
    def init(self, meta, children):
        return "init", tuple(self._with_runs(children, split_atoms)), self._loc(meta)

    @v_args(meta=True)
    def goal(self, meta, children):
        return "goal", children[0], self._loc(meta)

    # -- typed lists
    def names(self, runs):
        return list(runs)

    def type_ref(self, children):
        return children[0]

    def either_type(self, children):
        raise PddlError("'either' types are not supported; declare a common parent type instead",
                        self._loc(children[0]))

    def typed_names(self, children):
        """`a b - t c` -> TypedNames. Children are lists of NAME_RUN tokens, which may hold
        `- type` parts themselves, and type tokens after a separate '-'."""
        out: List[TypedName] = []
        pending: List[Tuple[List[str], Loc]] = []  # names still waiting for their type

        def assign(type_: str, dash: Callable[[], Loc]) -> None:
            if not any(names for names, _ in pending):
                raise PddlError(f"'- {type_}' has no names before it", dash())
            flush(sys.intern(type_))

        def flush(type_: str) -> None:
            for names, loc in pending:
                out.extend(TypedName(name, type_, loc) for name in names)
            pending.clear()

        for child in children:
            if isinstance(child, Token):  # the type after a separate '-'
                assign(child.lower(), lambda: self._loc(child))
                continue
            for run in child:
                loc = RunLoc(self.file, run.line, run.column, run.value)  # the text, not the token: one copy
                first, *typed_parts = _TYPE_DASH.split(run.lower())
                pending.append((first.split(), loc))
                for number, part in enumerate(typed_parts):
                    type_, *names = part.split()
                    assign(type_, lambda: loc.dash_loc(number))
                    pending.append((names, loc))
        flush("object")
        return tuple(out)

    def vars(self, tokens):
        return list(tokens)

    def typed_vars(self, children):
        out, pending = [], []
        for child in children:
            if isinstance(child, list):
                pending.extend(child)
            else:
                out.extend(TypedName(t.lower(), child.lower(), self._loc(t)) for t in pending)
                pending = []
        out.extend(TypedName(t.lower(), "object", self._loc(t)) for t in pending)
        return tuple(out)

    @v_args(meta=True)
    def predicate_decl(self, meta, children):
        name, params = children
        return Predicate(name.lower(), params, self._loc(meta))

    # -- actions, streams, mechanisms
    @v_args(meta=True)
    def action(self, meta, children):
        name, *props = children
        f = self._fields(props, f"action '{name.lower()}'")
        return Action(name.lower(), f.get("parameters", ()), f.get("precondition", And(())),
                      f.get("effect", And(())), self._loc(meta))

    @v_args(meta=True)
    def stream(self, meta, children):
        name, *props = children
        f = self._fields(props, f"stream '{name.lower()}'")
        return Stream(name.lower(), f.get("inputs", ()), f.get("domain", And(())), f.get("outputs", ()),
                      f.get("certified", And(())), f.get("sampler"), self._loc(meta))

    @v_args(meta=True)
    def mechanism(self, meta, children):
        name, *props = children
        f = self._fields(props, f"mechanism '{name.lower()}'")
        return Mechanism(name.lower(), f.get("parameters", ()), f.get("precondition", And(())),
                         f.get("certified", And(())), f.get("actions", ()), f.get("sampler"),
                         self._loc(meta))

    parameters = _tagged("parameters")
    precondition = _tagged("precondition")
    effect = _tagged("effect")
    inputs = _tagged("inputs")
    stream_domain = _tagged("domain")
    outputs = _tagged("outputs")
    certified = _tagged("certified")

    @v_args(meta=True)
    def sampler(self, meta, children):
        token = children[0]
        value = token[1:-1] if token.type == "STRING" else token.lower()
        return "sampler", value, self._loc(meta)

    @v_args(meta=True)
    def steps(self, meta, children):
        calls: list = []
        for child in children:
            if isinstance(child, ActionCall):
                calls.append(child)
            elif not calls or calls[-1].then != And(()):
                raise PddlError(":then must follow a step (one :then per step)", child[1])
            else:
                calls[-1] = replace(calls[-1], then=child[0])
        return "actions", tuple(calls), self._loc(meta)

    @v_args(meta=True)
    def then(self, meta, children):
        return children[0], self._loc(meta)

    @v_args(meta=True)
    def call(self, meta, children):
        name, *args = children
        return ActionCall(name.lower(), tuple(args), self._loc(meta))

    # -- formulas
    def formula_or_empty(self, children):
        return children[0]

    @v_args(meta=True)
    def empty_formula(self, meta, children):
        return And((), self._loc(meta))

    @v_args(meta=True)
    def atom(self, meta, children):
        name, *args = children
        return Atom(name.lower(), tuple(args), self._loc(meta))

    init_atom = atom

    def var(self, children):
        return Var(children[0].lower(), self._loc(children[0]))

    def const(self, children):
        return Const(children[0].lower(), self._loc(children[0]))

    @v_args(meta=True)
    def equals(self, meta, children):
        return Equals(children[0], children[1], self._loc(meta))

    @v_args(meta=True)
    def and_(self, meta, children):
        return And(tuple(children), self._loc(meta))

    @v_args(meta=True)
    def or_(self, meta, children):
        return Or(tuple(children), self._loc(meta))

    @v_args(meta=True)
    def not_(self, meta, children):
        return Not(children[0], self._loc(meta))

    @v_args(meta=True)
    def imply(self, meta, children):
        return Imply(children[0], children[1], self._loc(meta))

    @v_args(meta=True)
    def forall(self, meta, children):
        return Forall(children[0], children[1], self._loc(meta))

    @v_args(meta=True)
    def exists(self, meta, children):
        return Exists(children[0], children[1], self._loc(meta))

    @v_args(meta=True)
    def when(self, meta, children):
        return When(children[0], children[1], self._loc(meta))

    # -- scene
    @v_args(meta=True)
    def scene(self, meta, children):
        return "scene", tuple(children), self._loc(meta)

    @v_args(meta=True)
    def scene_entry(self, meta, children):
        name, *props = children
        return SceneEntry(name.lower(), tuple(props), self._loc(meta))

    @v_args(meta=True)
    def scene_prop(self, meta, children):
        key = children[0].lower()
        return SceneProp(key, children[1] if len(children) > 1 else None, self._loc(meta))

    def number(self, children):
        value = float(children[0])
        if not math.isfinite(value):
            raise PddlError(f"number {_shorten(children[0])} is out of range: numbers must be finite "
                            "(at most ~1.8e308 in magnitude)",
                            self._loc(children[0]))
        return value

    def string(self, children):
        return str(children[0][1:-1])

    def symbol(self, children):
        return Symbol(children[0].lower())

    def vector(self, children):
        return tuple(children)


def _shorten(word: str, limit: int = 24) -> str:
    """A long literal, cut for a one-line message."""
    return word if len(word) <= limit else f"{word[:limit - 8]}...{word[-5:]} ({len(word)} characters)"
