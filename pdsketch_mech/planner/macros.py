"""Mechanisms as macro operators of the grounded task.

A mechanism grounded on objects binds each of its steps to a ground basis operator (its
continuous variables to the placeholders those operators use, consistently across steps);
the macro's precondition is the mechanism's precondition plus what the steps need that
earlier steps do not provide, and its effect is the steps' composed effect (with what each
step's `:then` says physics makes so after it) plus the facts it certifies (refinement checks
both in simulation). The symbolic
search can then use a whole mechanism as one action; refinement expands it again.
"""
from __future__ import annotations

from collections import defaultdict
from itertools import product
from typing import Dict, Iterator, List, Optional, Sequence, Tuple

from ..lang.nodes import Domain, Formula, Mechanism, Problem, Var
from ..lang.typecheck import TypeTable
from ..operators.vocabulary import BASIS, Vocabulary
from ..symbolic.grounding import objects_by_type
from ..symbolic.normalize import dnf, substitute
from ..symbolic.optimistic import is_placeholder
from ..symbolic.task import Operator, StripsTask


def add_mechanism_macros(task: StripsTask, domain: Domain, types: TypeTable, problem: Problem,
                         vocabulary: Vocabulary = BASIS) -> int:
    """Append one macro operator per applicable grounding of each mechanism; returns how many."""
    objects = objects_by_type(domain, problem, types)
    by_signature: Dict[Tuple[str, Tuple[str, ...]], List[int]] = defaultdict(list)
    for op_id, op in enumerate(task.operators):
        by_signature[(op.name, tuple(a for a in op.args if not is_placeholder(a)))].append(op_id)
    supports = other_supports(task, vocabulary)
    added = 0
    for mechanism in domain.mechanisms:
        object_params = [q for q in mechanism.parameters if not types.is_value(q.type)]
        for values in product(*(objects.get(q.type, ()) for q in object_params)):
            binding = {q.name: v for q, v in zip(object_params, values)}
            for step_ids, env in _bind_steps(mechanism, binding, task, by_signature):
                macro = _compose(mechanism, binding, values, step_ids, task, objects, env, supports)
                if macro is not None:
                    task.operators.append(macro)
                    added += 1
                    break  # one binding of the continuous variables is enough symbolically
    return added


def other_supports(task: StripsTask, vocabulary: Vocabulary = BASIS) -> Dict[int, int]:
    """For each fact id saying what supports an object x, the mask of x's other such facts."""
    by_object: Dict[str, int] = defaultdict(int)
    for fact, i in task.fact_ids.items():
        if vocabulary.support_fact(fact):
            by_object[fact[1]] |= 1 << i
    return {i: by_object[fact[1]] & ~(1 << i) for fact, i in task.fact_ids.items() if vocabulary.support_fact(fact)}


def _bind_steps(mechanism: Mechanism, binding: Dict[str, str], task: StripsTask,
                by_signature) -> Iterator[Tuple[List[int], Dict[str, str]]]:
    """Ground basis operators for the steps, continuous variables bound consistently; with
    each choice, the binding of every variable (objects and placeholders)."""
    def walk(i: int, env: Dict[str, str], chosen: List[int]):
        if i == len(mechanism.actions):
            yield list(chosen), dict(env)
            return
        call = mechanism.actions[i]
        names = [env.get(t.name, t.name) if isinstance(t, Var) else t.name for t in call.args]
        objects_only = tuple(n for n in names if not n.startswith("?"))
        for op_id in by_signature.get((call.name, objects_only), ()):
            op = task.operators[op_id]
            if len(op.args) != len(names):
                continue
            extended = dict(env)
            if all(_unify(n, a, extended) for n, a in zip(names, op.args)):
                yield from walk(i + 1, extended, chosen + [op_id])

    yield from walk(0, dict(binding), [])


def _unify(term: str, value: str, env: Dict[str, str]) -> bool:
    if not term.startswith("?"):
        return term == value
    if term in env:
        return env[term] == value
    env[term] = value
    return True


def _compose(mechanism: Mechanism, binding, values, step_ids: Sequence[int], task: StripsTask,
             objects, env: Dict[str, str], supports: Dict[int, int]) -> Optional[Operator]:
    alternatives = formula_masks(mechanism.precondition, binding, task, objects)
    if not alternatives:
        return None
    pre, neg = alternatives[0]  # its first satisfiable disjunct
    then = step_then(mechanism, binding, task, objects)
    if then is None:
        return None
    added = deleted = 0
    for op_id, (then_add, then_delete) in zip(step_ids, then):
        op = task.operators[op_id]
        if op.pre & deleted or op.neg & added:
            return None  # a step needs what an earlier step undid
        pre |= op.pre & ~added
        neg |= op.neg & ~deleted
        added = (added & ~op.delete) | op.add
        deleted = (deleted & ~op.add) | op.delete
        added, deleted = (added & ~then_delete) | then_add, (deleted & ~then_add) | then_delete
    if pre & neg:
        return None
    certified = tuple(formula_masks(mechanism.certified, binding, task, objects))
    if not certified:
        return None  # it promises what can never hold here
    settles = certified_effect(certified[0], added | pre, supports)
    added, deleted = (added & ~settles[1]) | settles[0], (deleted & ~settles[0]) | settles[1]
    # Which of the mechanism's variables each placeholder stands for: learned samplers are
    # trained per variable, and self-play labels its data by them.
    roles = tuple(sorted((value, var) for var, value in env.items() if is_placeholder(value)))
    return Operator(mechanism.name, tuple(values), pre, neg, added, deleted, steps=tuple(step_ids),
                    certified=certified, roles=roles, settles=settles,
                    then=then if any(a or d for a, d in then) else ())


def step_then(mechanism: Mechanism, binding, task: StripsTask, objects) -> Optional[Tuple[Tuple[int, int], ...]]:
    """Each step's `:then` as (add, delete) masks: what physics makes so after it (a pull
    whose target falls off a shelf onto the table). None if one can never hold here."""
    out = []
    for call in mechanism.actions:
        masks = formula_masks(call.then, binding, task, objects)
        if not masks:
            return None
        out.append(masks[0])
    return tuple(out)


def certified_effect(promise: Tuple[int, int], known: int, supports: Dict[int, int]) -> Tuple[int, int]:
    """(add, delete) a mechanism's certified facts impose after its steps. What it certifies
    is its effect too (the paper: the demonstration's goal becomes the mechanism's certified
    effect): a push or a release whose outcome physics decides (a box pushed across a gap, a
    block let go on a ramp it slides off, a box pulled off a shelf onto the table) has no basis
    effect, yet refinement checks that the certified facts hold. An object certified to rest
    on something rests on nothing else it is known to rest on (`known`: what the steps put it
    on, or where the mechanism needs it to lie before) unless certified. A self-contradicting
    promise is left to refinement to refute."""
    promised, refused = promise
    if promised & refused:
        return 0, 0
    superseded = 0
    for fact_id, others in supports.items():
        if promised >> fact_id & 1:
            superseded |= known & others & ~promised
    return promised, refused | superseded


def formula_masks(formula: Formula, binding, task: StripsTask, objects) -> List[Tuple[int, int]]:
    """A formula over the task's facts as alternatives of (true, false) masks, one per
    satisfiable disjunct (static facts and equalities evaluated away)."""
    out = []
    for conjunct in dnf(substitute(formula, binding), objects):
        pre = neg = 0
        ok = True
        for lit in conjunct:
            atom = lit.atom
            if hasattr(atom, "predicate"):
                fact = (atom.predicate,) + tuple(t.name for t in atom.args)
                if fact in task.fact_ids:
                    if lit.positive:
                        pre |= 1 << task.fact_ids[fact]
                    else:
                        neg |= 1 << task.fact_ids[fact]
                elif (fact in task.static_facts) != lit.positive:
                    ok = False
            else:
                equal = atom.left.name == atom.right.name
                ok = ok and equal == lit.positive
        if ok:
            out.append((pre, neg))
    return out
