"""An independent plan validator that interprets the syntax tree directly (no grounding).

It is the oracle the planner is checked against, so it shares no code with grounding:
closed-world PDDL semantics over the domain's constants and the problem's objects.
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import product
from typing import Dict, FrozenSet, Iterator, Mapping, Optional, Sequence, Set, Tuple

from ..lang.nodes import (
    And, Atom, Domain, Equals, Exists, Forall, Formula, Imply, Not, Or, Problem, Term, TypedName,
    Var, When,
)
from ..lang.writer import formula as write_formula

GroundAtom = Tuple[str, ...]
State = FrozenSet[GroundAtom]
Binding = Mapping[str, str]  # variable name (with '?') -> object name


@dataclass(frozen=True)
class ValidationResult:
    """The verdict; `final_state` is the last state reached (before a failing step)."""

    ok: bool
    message: str
    failed_step: Optional[int] = None  # 1-based; None if ok or if only the goal failed
    final_state: FrozenSet[GroundAtom] = frozenset()


def show(atom: GroundAtom) -> str:
    """`("on", "a", "b")` -> `(on a b)`."""
    return "(" + " ".join(atom) + ")"


class _World:
    """Objects with their types, and formula evaluation over a state."""

    def __init__(self, domain: Domain, problem: Problem) -> None:
        self.parents = {t.name: t.type for t in domain.types + domain.value_types}
        self.objects: Dict[str, str] = {o.name: o.type for o in domain.constants + problem.objects}

    def is_a(self, type_name: str, target: str) -> bool:
        """`type_name` is `target` or one of its subtypes (every type is an `object`)."""
        seen: Set[str] = set()
        current: Optional[str] = type_name
        while current is not None and current not in seen:
            if current == target:
                return True
            seen.add(current)
            current = self.parents.get(current)
        return target == "object"

    def bindings(self, variables: Sequence[TypedName], binding: Binding) -> Iterator[Dict[str, str]]:
        """Every extension of `binding` giving each variable an object of its type."""
        choices = [[o for o, t in self.objects.items() if self.is_a(t, v.type)] for v in variables]
        for values in product(*choices):
            yield {**binding, **{v.name: value for v, value in zip(variables, values)}}

    @staticmethod
    def ground(atom: Atom, binding: Binding) -> GroundAtom:
        return (atom.predicate,) + tuple(_value(a, binding) for a in atom.args)

    def holds(self, f: Formula, b: Binding, state: State) -> bool:
        """Truth of a condition (closed world: an atom is true iff it is in `state`).
        Loops rather than all()/any() over generators: one Python frame per level of a
        formula that may nest ~500 deep."""
        if isinstance(f, Atom):
            return self.ground(f, b) in state
        if isinstance(f, Equals):
            return _value(f.left, b) == _value(f.right, b)
        if isinstance(f, Not):
            return not self.holds(f.body, b, state)
        if isinstance(f, Imply):
            return not self.holds(f.condition, b, state) or self.holds(f.consequence, b, state)
        if isinstance(f, (And, Or)):
            cases = [(part, b) for part in f.parts]
        elif isinstance(f, (Forall, Exists)):
            cases = [(f.body, inner) for inner in self.bindings(f.variables, b)]
        else:
            raise ValueError(f"not a condition: {write_formula(f)}")
        decisive = isinstance(f, (Or, Exists))  # one true part decides an or, one false part an and
        for part, binding in cases:
            if self.holds(part, binding, state) == decisive:
                return decisive
        return not decisive

    def why_false(self, f: Formula, b: Binding, state: State) -> str:
        """A short reason why the (false) condition `f` fails, naming the culprit atom."""
        if isinstance(f, Atom):
            return f"{show(self.ground(f, b))} is false"
        if isinstance(f, Not) and isinstance(f.body, Atom):
            return f"{show(self.ground(f.body, b))} is true"
        if isinstance(f, Equals):
            return f"(= {_value(f.left, b)} {_value(f.right, b)}) is false"
        if isinstance(f, Not) and isinstance(f.body, Equals):
            return f"(not (= {_value(f.body.left, b)} {_value(f.body.right, b)})) is false"
        if isinstance(f, And):
            part = next(p for p in f.parts if not self.holds(p, b, state))
            return self.why_false(part, b, state)
        if isinstance(f, Forall):
            inner = next(i for i in self.bindings(f.variables, b) if not self.holds(f.body, i, state))
            return self.why_false(f.body, inner, state)
        bound = ", ".join(f"{k} = {v}" for k, v in b.items())
        return f"{write_formula(f)} is false" + (f" (with {bound})" if bound else "")

    def effects(self, f: Formula, b: Binding, state: State, adds: Set[GroundAtom],
                deletes: Set[GroundAtom]) -> None:
        """Collect the adds and deletes of effect `f`, conditions judged in the pre-state."""
        if isinstance(f, Atom):
            adds.add(self.ground(f, b))
        elif isinstance(f, Not) and isinstance(f.body, Atom):
            deletes.add(self.ground(f.body, b))
        elif isinstance(f, And):
            for part in f.parts:
                self.effects(part, b, state, adds, deletes)
        elif isinstance(f, Forall):
            for inner in self.bindings(f.variables, b):
                self.effects(f.body, inner, state, adds, deletes)
        elif isinstance(f, When):
            if self.holds(f.condition, b, state):
                self.effects(f.effect, b, state, adds, deletes)
        else:
            raise ValueError(f"not an effect: {write_formula(f)}")


def _value(t: Term, binding: Binding) -> str:
    """The object a term denotes under `binding`."""
    if isinstance(t, Var):
        if t.name not in binding:
            raise ValueError(f"unbound variable {t.name}")
        return binding[t.name]
    return t.name


def validate_plan(domain: Domain, problem: Problem,
                  plan: Sequence[Tuple[str, Sequence[str]]]) -> ValidationResult:
    """Execute `plan` from `problem.init` and check every step and then the goal."""
    world = _World(domain, problem)
    actions = {a.name: a for a in domain.actions}
    state: State = frozenset(world.ground(atom, {}) for atom in problem.init)
    for index, (name, raw_args) in enumerate(plan, 1):
        name, args = name.lower(), tuple(a.lower() for a in raw_args)
        where = f"step {index} {show((name,) + args)}"

        def fail(reason: str) -> ValidationResult:
            return ValidationResult(False, f"{where}: {reason}", index, state)

        action = actions.get(name)
        if action is None:
            return fail(f"unknown action '{name}'")
        if len(args) != len(action.parameters):
            return fail(f"action '{name}' takes {len(action.parameters)} argument(s), got {len(args)}")
        for position, (arg, param) in enumerate(zip(args, action.parameters), 1):
            if arg not in world.objects:
                return fail(f"argument {position} '{arg}' is not a known object")
            if not world.is_a(world.objects[arg], param.type):
                return fail(f"argument {position} '{arg}' is of type '{world.objects[arg]}', "
                            f"but {param.name} must be of type '{param.type}'")
        binding = {p.name: arg for p, arg in zip(action.parameters, args)}
        if not world.holds(action.precondition, binding, state):
            reason = world.why_false(action.precondition, binding, state)
            return fail(f"precondition does not hold: {reason}")
        adds: Set[GroundAtom] = set()
        deletes: Set[GroundAtom] = set()
        world.effects(action.effect, binding, state, adds, deletes)
        state = (state - deletes) | adds
    steps = len(plan)
    if not world.holds(problem.goal, {}, state):
        reason = world.why_false(problem.goal, {}, state)
        return ValidationResult(False, f"goal does not hold after {steps} steps: {reason}", None, state)
    return ValidationResult(True, f"plan valid: {steps} steps reach the goal", None, state)
