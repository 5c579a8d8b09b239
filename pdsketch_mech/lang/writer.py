"""Syntax tree -> text. `parse_text(write(node)) == node` for every domain and problem.

Learning writes domain fragments with this, so the output is meant to be read and
committed by people: one declaration per line, conjunctions broken over lines.
"""
from __future__ import annotations

from typing import Iterable, List, Sequence, Union

from .nodes import (
    Action, And, Atom, Const, Domain, Equals, Exists, Forall, Formula, Imply, Mechanism, Not, Or,
    Problem, SceneValue, Stream, Symbol, Term, TypedName, Var, When,
)

_WIDTH = 88


def write(node: Union[Domain, Problem]) -> str:
    """The text of a domain or problem, ending with a newline."""
    if isinstance(node, Domain):
        return write_domain(node)
    if isinstance(node, Problem):
        return write_problem(node)
    raise TypeError(f"cannot write a {type(node).__name__}; pass a Domain or a Problem")


def write_domain(domain: Domain) -> str:
    out = [f"(define (domain {domain.name})"]
    if domain.extends:
        out.append(f"  (:extends {' '.join(string_literal(p) for p in domain.extends)})")
    if domain.vocabulary:
        out.append(f"  (:vocabulary {domain.vocabulary})")
    if domain.requirements:
        out.append(f"  (:requirements {' '.join(domain.requirements)})")
    for keyword, names in ((":types", domain.types), (":value-types", domain.value_types),
                           (":constants", domain.constants)):
        if names:
            out.append(f"  ({keyword} {typed_list(names)})")
    if domain.predicates:
        out.append("  (:predicates")
        out.extend(f"    ({_join(p.name, typed_list(p.parameters))})" for p in domain.predicates)
        out[-1] += ")"
    for action in domain.actions:
        out.append(_action(action))
    for stream in domain.streams:
        out.append(_stream(stream))
    for mechanism in domain.mechanisms:
        out.append(write_mechanism(mechanism))
    return "\n".join(out) + ")\n"


def write_problem(problem: Problem) -> str:
    out = [f"(define (problem {problem.name})", f"  (:domain {problem.domain_name})"]
    if problem.requirements:
        out.append(f"  (:requirements {' '.join(problem.requirements)})")
    if problem.objects:
        out.append(f"  (:objects {typed_list(problem.objects)})")
    out.append("  (:init" + "".join(f"\n    {formula(a)}" for a in problem.init) + ")")
    out.append(f"  (:goal {_block(problem.goal, 4)})")
    if problem.scene is not None:
        lines = ["  (:scene"]
        for entry in problem.scene:
            props = "".join(
                f" {p.key}" + ("" if p.value is None else f" {scene_value(p.value)}") for p in entry.props)
            lines.append(f"    ({entry.name}{props})")
        out.append("\n".join(lines) + ")")
    return "\n".join(out) + ")\n"


# ----------------------------------------------------------------------------- pieces
def typed_list(names: Sequence[TypedName]) -> str:
    """`a b - t c - u`: consecutive names of one type share their `- type`."""
    groups: List[List[str]] = []
    types: List[str] = []
    for item in names:
        if types and types[-1] == item.type:
            groups[-1].append(item.name)
        else:
            groups.append([item.name])
            types.append(item.type)
    return " ".join(f"{' '.join(g)} - {t}" for g, t in zip(groups, types))


def term(value: Term) -> str:
    if not isinstance(value, (Var, Const)):
        raise TypeError(f"not a term: {value!r}")
    return value.name


def formula(f: Formula) -> str:
    """A formula on one line."""
    if isinstance(f, Atom):
        return f"({_join(f.predicate, ' '.join(term(a) for a in f.args))})"
    if isinstance(f, Equals):
        return f"(= {term(f.left)} {term(f.right)})"
    if isinstance(f, Not):
        return f"(not {formula(f.body)})"
    if isinstance(f, (And, Or)):
        return f"({_join('and' if isinstance(f, And) else 'or', ' '.join(formula(p) for p in f.parts))})"
    if isinstance(f, Imply):
        return f"(imply {formula(f.condition)} {formula(f.consequence)})"
    if isinstance(f, (Forall, Exists)):
        word = "forall" if isinstance(f, Forall) else "exists"
        return f"({word} ({typed_list(f.variables)}) {formula(f.body)})"
    if isinstance(f, When):
        return f"(when {formula(f.condition)} {formula(f.effect)})"
    raise TypeError(f"not a formula: {f!r}")


def scene_value(value: SceneValue) -> str:
    if isinstance(value, bool):
        raise TypeError("scene values are numbers, strings, names or vectors, not booleans")
    if isinstance(value, (int, float)):
        return repr(float(value))
    if isinstance(value, str):
        return string_literal(value)
    if isinstance(value, Symbol):
        return value.name
    if isinstance(value, tuple):
        return "(" + " ".join(scene_value(v) for v in value) + ")"
    raise TypeError(f"not a scene value: {value!r}")


def _block(f: Formula, indent: int) -> str:
    """A formula on one line if it fits, else a conjunction with one part per line."""
    flat = formula(f)
    if len(flat) + indent <= _WIDTH or not isinstance(f, And) or not f.parts:
        return flat
    pad = " " * (indent + 2)
    return "(and" + "".join(f"\n{pad}{_block(p, indent + 2)}" for p in f.parts) + ")"


def _properties(head: str, props: Iterable[str]) -> str:
    return "\n".join([f"  ({head}", *(f"    {p}" for p in props)]) + ")"


def _formula_props(*pairs) -> List[str]:
    """`:key formula` lines for the formulas that are not the empty conjunction."""
    return [f"{key} {_block(f, 4)}" for key, f in pairs if f != And(())]


def _sampler_prop(sampler) -> List[str]:
    return [] if sampler is None else [f":sampler {string_literal(sampler)}"]


def _action(action: Action) -> str:
    props = [f":parameters ({typed_list(action.parameters)})",
             *_formula_props((":precondition", action.precondition), (":effect", action.effect))]
    return _properties(f":action {action.name}", props)


def _stream(stream: Stream) -> str:
    outputs = [f":outputs ({typed_list(stream.outputs)})"] if stream.outputs else []
    props = [f":inputs ({typed_list(stream.inputs)})", *_formula_props((":domain", stream.domain)),
             *outputs, *_formula_props((":certified", stream.certified)), *_sampler_prop(stream.sampler)]
    return _properties(f":stream {stream.name}", props)


def write_mechanism(mechanism: Mechanism) -> str:
    """One mechanism's definition as it appears in a domain file."""
    steps = "".join(
        f"\n      ({_join(c.name, ' '.join(term(a) for a in c.args))})"
        + (f"\n        :then {formula(c.then)}" if c.then != And(()) else "") for c in mechanism.actions)
    props = [f":parameters ({typed_list(mechanism.parameters)})",
             *_formula_props((":precondition", mechanism.precondition), (":certified", mechanism.certified)),
             f":actions ({steps})", *_sampler_prop(mechanism.sampler)]
    return _properties(f":mechanism {mechanism.name}", props)


def string_literal(text: str) -> str:
    """`text` as a quoted string of the language."""
    if '"' in text or "\n" in text:
        raise ValueError(f"a string cannot hold a quote or a newline: {text!r}")
    return f'"{text}"'


def _join(head: str, rest: str) -> str:
    return f"{head} {rest}" if rest else head
