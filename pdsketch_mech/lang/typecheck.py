"""Type checking of parsed (and merged) domains and of problems against their domain.

Raises `PddlError` at the first problem, located at the offending node. What it checks:
declared types/predicates/operators/streams/objects, arities, argument types, bound
variables, duplicate definitions, effect forms, mechanism steps, and the problem's scene.
What is accepted but suspicious goes to a list of `PddlWarning`s: a predicate declaring a
parameter name twice (IPC files do, e.g. logistics' `(in ?obj ?obj)`; only the types matter).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Mapping, Optional, Sequence

from .errors import PddlError, PddlWarning, did_you_mean, known_names
from .nodes import (
    Action, ActionCall, And, Atom, Domain, Equals, Exists, Forall, Formula, Imply, Loc,
    Mechanism, Not, Or, Predicate, Problem, RunLoc, Stream, Term, TypedName, Var, When,
)
from .scene import build_scene

ROOT_TYPE = "object"


@dataclass
class TypeTable:
    """Type hierarchy of a domain: parent of each type; value types are continuous."""

    parents: Dict[str, Optional[str]] = field(default_factory=lambda: {ROOT_TYPE: None})
    value_types: set = field(default_factory=set)

    def ancestors(self, name: str):
        while name is not None:
            yield name
            name = self.parents.get(name)

    def is_subtype(self, sub: str, sup: str) -> bool:
        return sup in self.ancestors(sub)

    def compatible(self, a: str, b: str) -> bool:
        """Some object could have both types (one is a subtype of the other)."""
        return self.is_subtype(a, b) or self.is_subtype(b, a)

    def is_value(self, name: str) -> bool:
        return any(t in self.value_types for t in self.ancestors(name))


def type_table(domain: Domain) -> TypeTable:
    """Build and validate the type hierarchy (declared parents, no cycles, no duplicates)."""
    table = TypeTable()
    declared = list(domain.types) + list(domain.value_types)
    for index, item in enumerate(declared):
        if item.name in table.parents:
            raise PddlError(f"type '{item.name}' is defined twice", name_loc(declared, index))
        table.parents[item.name] = item.type
    table.value_types = {t.name for t in domain.value_types}
    for index, item in enumerate(declared):
        if item.type not in table.parents:
            raise PddlError(f"unknown parent type '{item.type}' of type '{item.name}'"
                            f"{did_you_mean(item.type, table.parents)}", name_loc(declared, index))
        seen = set()
        for name in table.ancestors(item.name):
            if name in seen:
                raise PddlError(f"type '{item.name}' is its own ancestor", name_loc(declared, index))
            seen.add(name)
    for index, item in enumerate(domain.value_types):
        if item.type != ROOT_TYPE and item.type not in table.value_types:
            raise PddlError(f"value type '{item.name}' must extend another value type or object",
                            name_loc(domain.value_types, index))
    return table


def name_loc(items: Sequence[TypedName], index: int) -> Optional[Loc]:
    """Where `items[index]` is declared. The names of one run in a declaration list share a
    `RunLoc` (and sit next to each other), so the name's place in its run is counted back."""
    loc = items[index].loc
    if not isinstance(loc, RunLoc):
        return loc
    first = index
    while first > 0 and items[first - 1].loc is loc:
        first -= 1
    return loc.name_loc(index - first)


@dataclass
class _Context:
    """What names mean while checking one formula."""

    types: TypeTable
    predicates: Mapping[str, Predicate]
    objects: Mapping[str, str]  # constants and problem objects -> type


def check_domain(domain: Domain, warnings: Optional[List[PddlWarning]] = None) -> TypeTable:
    """Type-check a (merged) domain, appending warnings to `warnings`; returns its type table."""
    types = type_table(domain)
    constants = _declare_objects(domain.constants, types, "constant", {})
    predicates: Dict[str, Predicate] = {}
    for predicate in domain.predicates:
        _unique(predicates, predicate.name, predicate.loc, "predicate")
        _check_parameters(predicate.parameters, types, f"predicate '{predicate.name}'",
                          repeats=[] if warnings is None else warnings)
        predicates[predicate.name] = predicate
    ctx = _Context(types, predicates, constants)

    operators: Dict[str, object] = {}
    for action in domain.actions:
        _unique(operators, action.name, action.loc, "action")
        operators[action.name] = action
        scope = _check_parameters(action.parameters, types, f"action '{action.name}'")
        _check_condition(action.precondition, scope, ctx)
        _check_effect(action.effect, scope, ctx)
    for stream in domain.streams:
        _unique(operators, stream.name, stream.loc, "stream")
        operators[stream.name] = stream
        _check_stream(stream, ctx)
    actions = {a.name: a for a in domain.actions}
    for mechanism in domain.mechanisms:
        _unique(operators, mechanism.name, mechanism.loc, "mechanism")
        operators[mechanism.name] = mechanism
        _check_mechanism(mechanism, actions, ctx)
    return types


def check_problem(problem: Problem, domain: Domain, types: Optional[TypeTable] = None) -> None:
    """Type-check `problem` against an already checked `domain`."""
    types = types or type_table(domain)
    constants = {c.name: c.type for c in domain.constants}
    objects = _declare_objects(problem.objects, types, "object", constants)
    ctx = _Context(types, {p.name: p for p in domain.predicates}, objects)
    _check_init(problem.init, ctx)
    _check_condition(problem.goal, {}, ctx)
    if problem.scene is not None:
        build_scene(problem)


# ----------------------------------------------------------------------------- declarations
def _unique(seen: Mapping[str, object], name: str, loc: Optional[Loc], kind: str) -> None:
    if name in seen:
        other = seen[name]
        where = f" (first defined at {other.loc})" if getattr(other, "loc", None) else ""
        raise PddlError(f"{kind} '{name}' is already defined{where}", loc)


def _check_type(type_name: str, types: TypeTable, loc: Optional[Loc]) -> None:
    if type_name not in types.parents:
        raise PddlError(f"unknown type '{type_name}'{did_you_mean(type_name, types.parents)}", loc)


def _check_parameters(params: Sequence[TypedName], types: TypeTable, owner: str,
                      repeats: Optional[List[PddlWarning]] = None) -> Dict[str, str]:
    """Parameter name -> type; a repeated name is an error, or a warning put in `repeats`."""
    scope: Dict[str, str] = {}
    for param in params:
        _check_type(param.type, types, param.loc)
        if param.name in scope and repeats is not None:
            repeats.append(PddlWarning(f"parameter {param.name} appears twice in {owner}; accepted, "
                                       "as only a predicate's parameter types matter", param.loc))
        elif param.name in scope:
            raise PddlError(f"parameter {param.name} appears twice in {owner}", param.loc)
        scope[param.name] = param.type
    return scope


def _declare_objects(items: Sequence[TypedName], types: TypeTable, kind: str,
                     existing: Mapping[str, str]) -> Dict[str, str]:
    """Name -> type of `existing` and `items`. Linear in the number of items: a problem may
    declare millions of objects."""
    objects = dict(existing)
    redeclared = set()  # constants declared again with their own type (allowed once)
    value_type: Dict[str, bool] = {}
    for index, item in enumerate(items):
        if item.type not in value_type:
            _check_type(item.type, types, name_loc(items, index))
            value_type[item.type] = types.is_value(item.type)
        if value_type[item.type]:
            raise PddlError(f"{kind} '{item.name}' has value type '{item.type}'; values come from "
                            "streams, not from declarations", name_loc(items, index))
        if item.name in objects:
            if item.name not in existing or item.name in redeclared:
                raise PddlError(f"{kind} '{item.name}' is declared twice", name_loc(items, index))
            if objects[item.name] != item.type:
                raise PddlError(f"{kind} '{item.name}' is already a constant of type "
                                f"'{objects[item.name]}'", name_loc(items, index))
            redeclared.add(item.name)
        objects[item.name] = item.type
    return objects


# ----------------------------------------------------------------------------- formulas
def _term_type(value: Term, scope: Mapping[str, str], ctx: _Context) -> str:
    if isinstance(value, Var):
        if value.name not in scope:
            raise PddlError(f"unbound variable {value.name}{did_you_mean(value.name, scope)}", value.loc)
        return scope[value.name]
    if value.name not in ctx.objects:
        raise PddlError(f"unknown object '{value.name}'{did_you_mean(value.name, ctx.objects)}", value.loc)
    return ctx.objects[value.name]


def _check_args(args: Sequence[Term], params: Sequence[TypedName], what: str,
                loc: Optional[Loc], scope: Mapping[str, str], ctx: _Context) -> None:
    if len(args) != len(params):
        raise PddlError(f"{what} takes {len(params)} argument{'s' * (len(params) != 1)}, "
                        f"got {len(args)}", loc)
    for index, (arg, param) in enumerate(zip(args, params), 1):
        arg_type = _term_type(arg, scope, ctx)
        if not ctx.types.compatible(arg_type, param.type):
            raise PddlError(f"argument {index} of {what} must be of type '{param.type}', "
                            f"but {arg.name} is of type '{arg_type}'", arg.loc or loc)


def _check_atom(atom: Atom, scope: Mapping[str, str], ctx: _Context) -> None:
    predicate = ctx.predicates.get(atom.predicate)
    if predicate is None:
        # In the domain's order, as its author grouped them (sorted, related names would scatter).
        known = f"known: {known_names(ctx.predicates)}" if ctx.predicates else "the domain declares no predicates"
        raise PddlError(f"unknown predicate '{atom.predicate}'"
                        f"{did_you_mean(atom.predicate, ctx.predicates)}; {known}", atom.loc)
    _check_args(atom.args, predicate.parameters, f"predicate '{atom.predicate}'", atom.loc, scope, ctx)


def _check_init(atoms: Sequence[Atom], ctx: _Context) -> None:
    """`_check_atom` on every fact, each predicate and combination of argument types checked
    once: an :init may hold millions of facts over a few types."""
    seen = set()
    types = ctx.objects.get
    for atom in atoms:
        key = (atom.predicate, *[types(arg.name) for arg in atom.args])
        if key not in seen:
            _check_atom(atom, {}, ctx)  # an unknown object (type None) fails here, located
            seen.add(key)


def _bind(variables: Sequence[TypedName], scope: Mapping[str, str], ctx: _Context) -> Dict[str, str]:
    inner = dict(scope)
    for var in variables:
        _check_type(var.type, ctx.types, var.loc)
        inner[var.name] = var.type
    return inner


def _check_condition(f: Formula, scope: Mapping[str, str], ctx: _Context) -> None:
    """A precondition, goal, or certified formula: no conditional effects."""
    if isinstance(f, Atom):
        _check_atom(f, scope, ctx)
    elif isinstance(f, Equals):
        _term_type(f.left, scope, ctx)
        _term_type(f.right, scope, ctx)
    elif isinstance(f, Not):
        _check_condition(f.body, scope, ctx)
    elif isinstance(f, (And, Or)):
        for part in f.parts:
            _check_condition(part, scope, ctx)
    elif isinstance(f, Imply):
        _check_condition(f.condition, scope, ctx)
        _check_condition(f.consequence, scope, ctx)
    elif isinstance(f, (Forall, Exists)):
        _check_condition(f.body, _bind(f.variables, scope, ctx), ctx)
    elif isinstance(f, When):
        raise PddlError("'when' is a conditional effect; it cannot appear in a condition", f.loc)
    else:
        raise TypeError(f"not a formula: {f!r}")


def _check_effect(f: Formula, scope: Mapping[str, str], ctx: _Context, in_when: bool = False) -> None:
    if isinstance(f, Atom):
        _check_atom(f, scope, ctx)
    elif isinstance(f, Not) and isinstance(f.body, Atom):
        _check_atom(f.body, scope, ctx)
    elif isinstance(f, And):
        for part in f.parts:
            _check_effect(part, scope, ctx, in_when)
    elif isinstance(f, Forall):
        _check_effect(f.body, _bind(f.variables, scope, ctx), ctx, in_when)
    elif isinstance(f, When):
        if in_when:
            raise PddlError("'when' cannot be nested inside another 'when'", f.loc)
        _check_condition(f.condition, scope, ctx)
        _check_effect(f.effect, scope, ctx, in_when=True)
    else:
        kind = {Not: "a negated non-atom", Or: "'or'", Imply: "'imply'", Exists: "'exists'",
                Equals: "'='"}.get(type(f), type(f).__name__)
        raise PddlError(f"{kind} is not allowed in an effect; effects are atoms, (not atom), "
                        "and, forall and when", f.loc)


# ----------------------------------------------------------------------------- streams, mechanisms
def _check_stream(stream: Stream, ctx: _Context) -> None:
    owner = f"stream '{stream.name}'"
    inputs = _check_parameters(stream.inputs, ctx.types, owner)
    _check_condition(stream.domain, inputs, ctx)
    outputs = _check_parameters(stream.outputs, ctx.types, owner)
    for out in stream.outputs:
        if out.name in inputs:
            raise PddlError(f"{out.name} is both an input and an output of {owner}", out.loc)
        if not ctx.types.is_value(out.type):
            raise PddlError(f"output {out.name} of {owner} has type '{out.type}', which is not a "
                            "value type (declare it in :value-types)", out.loc)
    _check_condition(stream.certified, {**inputs, **outputs}, ctx)
    if stream.certified == And(()) and stream.outputs:
        raise PddlError(f"{owner} certifies nothing: add :certified facts about its outputs", stream.loc)


def _check_mechanism(mechanism: Mechanism, actions: Mapping[str, Action], ctx: _Context) -> None:
    owner = f"mechanism '{mechanism.name}'"
    scope = _check_parameters(mechanism.parameters, ctx.types, owner)
    _check_condition(mechanism.precondition, scope, ctx)
    _check_condition(mechanism.certified, scope, ctx)
    if not mechanism.actions:
        raise PddlError(f"{owner} has no :actions", mechanism.loc)
    for step in mechanism.actions:
        _check_step(step, actions, scope, ctx)


def _check_step(step: ActionCall, actions: Mapping[str, Action], scope: Mapping[str, str],
                ctx: _Context) -> None:
    action = actions.get(step.name)
    if action is None:
        raise PddlError(f"mechanism step names unknown operator '{step.name}'"
                        f"{did_you_mean(step.name, actions)}", step.loc)
    _check_args(step.args, action.parameters, f"operator '{step.name}'", step.loc, scope, ctx)
    _check_condition(step.then, scope, ctx)
    for part in step.then.parts if isinstance(step.then, And) else (step.then,):
        atom = part.body if isinstance(part, Not) else part
        if not isinstance(atom, Atom):
            raise PddlError(f"the :then of step '{step.name}' must be facts and negated facts joined by "
                            "'and' (what physics makes so after the step)", getattr(atom, "loc", None) or step.loc)
