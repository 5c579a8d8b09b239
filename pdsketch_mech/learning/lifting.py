"""Lifting grounded steps to a mechanism: objects become typed variables named by their roles.

Roles come from what the demonstration did with each body (its contacts), never from its
name or category; the first rule that fits names it:

    target    moved by the robot (held or pushed) and named by the goal
    tool      held while it pushes another object (move-cont's ?x)
    pushed    pushed (by the hand or a tool), not named by the goal
    weight    moved, and ends up resting on a target
    blocker   moved, and ends up touching a target without supporting it
    object    moved, none of the above
    landing   named by the goal only, as what a moved object comes to rest on by itself
              (falls, tips or slides onto: no step puts it there)
    support   supports a moved object at the start; the first one found is `support`, the
              others `<role>-support` after the role of what they support (Lever: the
              ledge under the target is `target-support`)
    surface   something a moved object is put down on that supported nothing at the start
    contacted touched by a pushed or held object (an "indirect" contact)

A role held by several bodies is numbered (`target1`, `target2`). Continuous parameters are
the basis operators' value parameters, named by type — g(rasp), p(lacement), c(ontact),
q (conf), t(raj) — and numbered in step order when a type occurs more than once.

The precondition is the initial contact-mode graph restricted to the involved bodies — the
hand (`handempty` / `holding`) and every `support` — plus `(not (= ?a ?b))` for each pair of
moved bodies (two of them may otherwise be grounded on one object). `touching` facts are
left out: no basis operator maintains them, so requiring one would only stop the mechanism
from applying. A body neither that graph nor the goal mentions (a ramp something is put on
to slide off), and a landing place, are pinned by what the demonstration shows of them:
`(fixed ?x)` if fixed in the scene, and `(not (= ?x ?y))` for every other parameter. The
certified effect is the demonstration's goal, lifted the same way.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Collection, Dict, Hashable, List, Sequence, Set, Tuple

from ..lang.nodes import (ActionCall, And, Atom, Const, Domain, Equals, Formula, Mechanism, Not, Term,
                          TypedName, Var)
from ..symbolic.normalize import dnf
from .steps import Explanation, Fact

OBJECT_TYPE = "item"
VALUE_LETTERS = {"grasp": "g", "placement": "p", "contact": "c", "conf": "q", "traj": "t"}


@dataclass
class Lifted:
    mechanism: Mechanism
    roles: Dict[int, str]          # body index -> variable name (with `?`)
    reasons: Dict[int, str]        # body index -> why it has that role


def goal_objects(goal: Formula) -> Set[str]:
    """Every object (constant) the goal mentions."""
    out: Set[str] = set()
    for conj in dnf(goal, {}):
        for lit in conj:
            atom = lit.atom
            terms = (atom.left, atom.right) if isinstance(atom, Equals) else atom.args
            out |= {t.name for t in terms if isinstance(t, Const)}
    return out


def _landing_places(goal: Formula, moved: Set[str]) -> Set[str]:
    """What the goal says a moved object rests on: `(support X Y)` with X moved, positive."""
    out: Set[str] = set()
    for conj in dnf(goal, {}):
        for lit in conj:
            atom = lit.atom
            if (lit.positive and isinstance(atom, Atom) and atom.predicate == "support"
                    and len(atom.args) == 2 and all(isinstance(t, Const) for t in atom.args) and atom.args[0].name in moved):
                out.add(atom.args[1].name)
    return out


def assign_roles(ex: Explanation, names: Sequence[str], goal: Formula) -> Tuple[Dict[int, str], Dict[int, str]]:
    """Role names (without numbering) for every involved body, and the reason for each."""
    in_goal = {i for i, n in enumerate(names) if n in goal_objects(goal)}
    pushers = {st.objects[0] for st in ex.steps if st.operator == "move-cont"}
    pushed = {st.objects[1] for st in ex.steps if st.operator == "move-cont"} | \
             {st.objects[0] for st in ex.steps if st.operator == "transit-cont"}
    targets = [o for o in ex.moved if o in in_goal]
    final_support = {(f[1], f[2]) for f in ex.final if f[0] == "support"}
    initial_support = [(f[1], f[2]) for f in sorted(ex.initial) if f[0] == "support"]
    index = {n: i for i, n in enumerate(names)}
    role: Dict[int, str] = {}
    why: Dict[int, str] = {}

    def on_target(o: int) -> bool:
        return any((names[o], names[t]) in final_support for t in targets)

    def touches_target(o: int) -> bool:
        return any(f[0] == "touching" and {f[1], f[2]} == {names[o], names[t]} for f in ex.final for t in targets)

    for o in ex.moved:
        if o in targets:
            role[o], why[o] = "target", "moved by the robot, named by the goal"
        elif o in pushers:
            role[o], why[o] = "tool", "held while it pushes another object"
        elif o in pushed:
            role[o], why[o] = "pushed", "pushed, not named by the goal"
        elif on_target(o):
            role[o], why[o] = "weight", "moved, ends up resting on the target"
        elif touches_target(o):
            role[o], why[o] = "blocker", "moved, ends up touching the target without supporting it"
        else:
            role[o], why[o] = "object", "moved"
    moved = set(ex.moved)
    for o in ex.involved:
        if o in role:
            continue
        held_up = [index[x] for x, y in initial_support if index[y] == o and index[x] in moved]
        if held_up:
            first = "support" not in role.values()
            role[o] = "support" if first else f"{role[held_up[0]]}-support"
            why[o] = f"supports the {', '.join(sorted({role[x] for x in held_up}))} at the start"
        elif any(st.operator == "place" and st.objects[1] == o for st in ex.steps):
            role[o], why[o] = "surface", "something is put down on it"
        elif o in ex.indirect:
            role[o], why[o] = "contacted", "touched by a pushed or held object"
        else:
            role[o], why[o] = "object", "involved"
    return role, why


def _number(kinds: Sequence[Tuple[Hashable, str]]) -> Dict[Hashable, str]:
    """`?role` for a role held once, `?role1`, `?role2`, ... otherwise (in order), as in the
    paper's Fig. 3b (`?g1 ?t1 ... ?g2 ?t4`)."""
    counts: Dict[str, int] = {}
    for _, r in kinds:
        counts[r] = counts.get(r, 0) + 1
    seen: Dict[str, int] = {}
    out = {}
    for key, r in kinds:
        seen[r] = seen.get(r, 0) + 1
        out[key] = f"?{r}" if counts[r] == 1 else f"?{r}{seen[r]}"
    return out


def rename_terms(f: Formula, names: Dict[str, str], strict: bool = False) -> Formula:
    """`f` with every constant or variable whose name is in `names` replaced by the variable
    `names[name]`. With `strict`, a formula other than atoms, equalities, negations and
    conjunctions/disjunctions is an error (extraction lifts only those)."""
    def term(t: Term) -> Term:
        return Var(names[t.name]) if isinstance(t, (Const, Var)) and t.name in names else t

    if isinstance(f, Atom):
        return Atom(f.predicate, tuple(term(a) for a in f.args))
    if isinstance(f, Equals):
        return Equals(term(f.left), term(f.right))
    if isinstance(f, Not):
        return Not(rename_terms(f.body, names, strict))
    if hasattr(f, "parts"):
        return type(f)(tuple(rename_terms(p, names, strict) for p in f.parts))
    if strict:
        raise ValueError(f"cannot lift a goal with {type(f).__name__}: extraction lifts conjunctions, "
                         "disjunctions and negations of atoms")
    return f


def lift(ex: Explanation, names: Sequence[str], goal: Formula, basis: Domain, name: str,
         fixed: Collection[int] = ()) -> Lifted:
    """The mechanism `name` that the explanation `ex` of a demonstration with goal `goal` lifts
    to (`fixed`: the bodies that never move)."""
    role, why = assign_roles(ex, names, goal)
    # Bodies only the goal names (not involved in any step) become parameters too.
    landed_on = _landing_places(goal, {names[m] for m in ex.moved})
    for o, n in enumerate(names):
        if n in goal_objects(goal) and o not in role and o != 0:
            role[o], why[o] = (("landing", "a moved object comes to rest on it by itself (the goal)") if n in landed_on
                               else ("object", "named by the goal"))
    order = [o for o in ex.moved if o in role] + [o for o in ex.involved if o in role and o not in ex.moved]
    order += [o for o in role if o not in order]
    variables = _number([(o, role[o]) for o in order])
    by_name = {names[o]: v for o, v in variables.items()}

    actions = {a.name: a for a in basis.actions}
    value_types = {t.name for t in basis.value_types}
    slots: List[Tuple[int, int, str]] = []     # (step, position, type) of every value parameter
    for k, st in enumerate(ex.steps):
        for pos, p in enumerate(actions[st.operator].parameters):
            if p.type in value_types:
                slots.append((k, pos, p.type))
    value_names = _number([((k, pos), VALUE_LETTERS.get(t, t[0])) for k, pos, t in slots])

    calls, value_params = [], []
    for k, st in enumerate(ex.steps):
        objects = iter(st.objects)
        args: List[Term] = []
        for pos, p in enumerate(actions[st.operator].parameters):
            if p.type in value_types:
                v = value_names[(k, pos)]
                args.append(Var(v))
                value_params.append(TypedName(v, p.type))
            else:
                args.append(Var(variables[next(objects)]))
        calls.append(ActionCall(st.operator, tuple(args), then=_then(st.then, by_name)))

    involved = set(variables)
    pre: List[Formula] = []
    hand = [f for f in ex.initial if f[0] in ("handempty", "holding")]
    for f in sorted(hand):
        pre.append(_atom(f, by_name))
    supports = [f for f in ex.initial if f[0] == "support" and _index(f[1], names) in involved
                and _index(f[2], names) in involved]
    for o in order:                         # each body's supports, in parameter order
        pre += [_atom(f, by_name) for f in sorted(supports) if f[1] == names[o]]
    moved = [o for o in order if o in ex.moved]
    for i, a in enumerate(moved):
        for b in moved[i + 1:]:
            pre.append(Not(Equals(Var(variables[a]), Var(variables[b]))))
    pre += _moved_between(ex, by_name)
    certified = rename_terms(goal, by_name, strict=True)
    mentioned = _variables(And(tuple(pre + [certified])))
    pre += _pinned([o for o in order if variables[o] not in mentioned or role[o] == "landing"], order, variables, fixed)
    parameters = tuple(TypedName(variables[o], OBJECT_TYPE) for o in order) + tuple(value_params)
    mechanism = Mechanism(name, parameters, And(tuple(pre)) if len(pre) != 1 else pre[0], certified, tuple(calls))
    return Lifted(mechanism, {o: variables[o] for o in order}, why)


def _then(then: Tuple[Collection[Fact], Collection[Fact]], by_name: Dict[str, str]) -> Formula:
    """A step's `then` (facts physics adds and deletes after it), lifted."""
    added, deleted = (sorted(f for f in facts if all(a in by_name for a in f[1:])) for facts in then)
    parts = [_atom(f, by_name) for f in added] + [Not(_atom(f, by_name)) for f in deleted]
    return And(tuple(parts)) if len(parts) != 1 else parts[0]


def _moved_between(ex: Explanation, by_name: Dict[str, str]) -> List[Formula]:
    """`(not (= ?to ?from))` for each support physics moved an object between after a step
    (its `then`): a fall from one surface onto the same one is no fall."""
    out: List[Formula] = []
    for st in ex.steps:
        for to in sorted(st.then[0]):
            for source in sorted(st.then[1]):
                if to[0] == source[0] == "support" and to[1] == source[1] and to[2] in by_name and source[2] in by_name:
                    inequality = Not(Equals(Var(by_name[to[2]]), Var(by_name[source[2]])))
                    out += [inequality] if inequality not in out else []
    return out


def _pinned(free: Sequence[int], order: Sequence[int], variables: Dict[int, str],
            fixed: Collection[int]) -> List[Formula]:
    """For a body the precondition does not mention (the ramp something is put on to slide
    off, the platform a pushed object falls onto), what the demonstration shows of it: fixed
    or not, and another body than the others; otherwise the mechanism would apply with any
    object in its place (the table it started on, the object itself)."""
    out: List[Formula] = []
    for o in free:
        if o in fixed:
            out.append(Atom("fixed", (Var(variables[o]),)))
        out += [Not(Equals(Var(variables[o]), Var(variables[other]))) for other in order if other != o]
    return out


def _variables(f: Formula) -> Set[str]:
    """The variable names a formula mentions."""
    if isinstance(f, Atom):
        return {t.name for t in f.args if isinstance(t, Var)}
    if isinstance(f, Equals):
        return {t.name for t in (f.left, f.right) if isinstance(t, Var)}
    found: Set[str] = set()
    for child in getattr(f, "parts", ()) or ((f.body,) if hasattr(f, "body") else ()):
        found |= _variables(child)
    return found


def _index(name: str, names: Sequence[str]) -> int:
    return list(names).index(name)


def _atom(fact: Fact, by_name: Dict[str, str]) -> Atom:
    return Atom(fact[0], tuple(Var(by_name[a]) for a in fact[1:]))
