"""Contact-mode segments -> basis operators (the paper's Table 1), checked symbolically.

The paper's table gives one operator per contact-mode family. In `domains/basis.pddl`
grasp, place, move-cont and transit-cont each plan their own arm motion up to the contact
they make (`grasp-motion`, `place-motion`, `push-motion` streams), so a segment of pure
motion — free (transit) or holding something that touches nothing (move) — changes no
contact and is folded into the trajectory of the step that follows it; a trailing one (the
lift after the last grasp) changes nothing either and is dropped. The mapping, by what
changes between two segments:

    hand empty -> holds x            grasp x s        s: x's support just before
    holds x -> hand empty            place x s        s: what x rests on when let go
    holds x, x starts pushing y      move-cont x y s  s: y's support when the push starts
    hand empty, hand starts pushing  transit-cont y s s: y's support when the push starts

When an object has several supports, the one the symbolic state already has is chosen
(e.g. the tipped plate of Lever touches the table as well as its ledge: the ledge it was
on is the one `grasp` takes it from); each step is then checked against the basis domain's
own precondition and effect, so a demonstration the basis operators cannot explain is an
error rather than a fragment that never applies. One thing the basis operators leave to
physics is explained by it: a step that needs an object to rest where the contacts show it,
after an earlier step moved it there without saying so (a pull drops a box off a shelf onto
the table, which is then grasped from the table). The earlier step's `then` says so, and the
mechanism's step carries it as `:then` (language.md), which refinement checks.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, FrozenSet, List, Optional, Sequence, Set, Tuple

import numpy as np

from ..lang.nodes import Action, Domain, Equals, Formula
from ..symbolic.normalize import dnf, flatten_effect, substitute
from .contact_modes import CONTACT_DISTANCE
from .segmentation import Segmentation

Fact = Tuple[str, ...]


class ExtractionError(Exception):
    """The demonstration cannot be turned into a mechanism; the message says why."""


@dataclass(frozen=True)
class DemoStep:
    """One basis operator grounded on the recording's bodies (header indices)."""

    operator: str
    objects: Tuple[int, ...]
    segment: int          # the segment this step's contact change starts
    frame: int            # the frame where it happens
    then: Tuple[FrozenSet[Fact], FrozenSet[Fact]] = (frozenset(), frozenset())  # physics after it: (add, delete)

    def text(self, names: Sequence[str]) -> str:
        return "(" + " ".join([self.operator, *(names[o] for o in self.objects)]) + ")"


@dataclass
class Explanation:
    """The steps of a demonstration and the facts around them."""

    steps: List[DemoStep]
    initial: Set[Fact]                 # contact-mode facts at the start (all bodies)
    final: Set[Fact]                   # at the end of the recording
    involved: List[int]                # bodies the mechanism is about, in order of appearance
    moved: List[int]                   # the involved bodies the robot moved (held or pushed)
    indirect: Set[int] = field(default_factory=set)   # touched by a pushed/held object


def graph_facts(seg: Segmentation, frame: int, held: Optional[int]) -> Set[Fact]:
    """The basis domain's contact-mode facts at `frame` (a held object has no support)."""
    names = seg.bodies.names
    graph = seg.graphs[frame]
    facts: Set[Fact] = {("holding", names[held])} if held is not None else {("handempty",)}
    facts |= {("support", names[x], names[y]) for x, y in graph.support if x != held}
    facts |= {("touching", *sorted((names[x], names[y]))) for x, y in graph.touching
              if (x, y) not in graph.support and (y, x) not in graph.support}
    return facts


def pair_force(seg: Segmentation, frame: int, a: int, b: int) -> float:
    """Total normal force between bodies a and b at `frame` (to rank several supports)."""
    rows = seg.recording.contacts(frame)
    pair = sorted((a, b))
    mask = np.array([sorted(p) == pair and d < CONTACT_DISTANCE
                     for p, d in zip(rows["bodies"].tolist(), rows["distance"])], dtype=bool)
    return float(np.asarray(rows["force"])[mask].sum()) if mask.any() else 0.0


class _Basis:
    """The basis operators' preconditions and effects over ground facts."""

    def __init__(self, domain: Domain):
        self.actions: Dict[str, Action] = {a.name: a for a in domain.actions}
        self.value_types = {t.name for t in domain.value_types}
        # Facts certified by streams are about continuous values: the samplers' business.
        self.stream_predicates = {lit.atom.predicate for s in domain.streams
                                  for conj in dnf(s.certified, {}) for lit in conj if hasattr(lit.atom, "predicate")}

    def _binding(self, name: str, objects: Sequence[str]) -> Dict[str, str]:
        action = self.actions[name]
        object_params = [p for p in action.parameters if p.type not in self.value_types]
        return {p.name: o for p, o in zip(object_params, objects)}

    def unmet(self, name: str, objects: Sequence[str], facts: Set[Fact]) -> Optional[str]:
        """The first precondition literal that fails in `facts`, as text; None if all hold."""
        formula = substitute(self.actions[name].precondition, self._binding(name, objects))
        failures = []
        for conj in dnf(formula, {}):
            bad = next((lit for lit in conj if not self._holds(lit, facts)), None)
            if bad is None:
                return None
            failures.append(bad)
        lit = failures[0]
        text = _literal_text(lit.atom)
        return text if lit.positive else f"(not {text})"

    def needs(self, name: str, objects: Sequence[str]) -> List[Fact]:
        """The facts `name`'s precondition needs true (each disjunct's), ground."""
        formula = substitute(self.actions[name].precondition, self._binding(name, objects))
        return [(lit.atom.predicate, *(t.name for t in lit.atom.args)) for conj in dnf(formula, {})
                for lit in conj if lit.positive and not isinstance(lit.atom, Equals)]

    def _holds(self, lit, facts: Set[Fact]) -> bool:
        atom = lit.atom
        if isinstance(atom, Equals):
            return (atom.left.name == atom.right.name) == lit.positive
        if atom.predicate in self.stream_predicates:
            return True
        fact = (atom.predicate, *(t.name for t in atom.args))
        return (fact in facts) == lit.positive

    def apply(self, name: str, objects: Sequence[str], facts: Set[Fact]) -> Set[Fact]:
        effect: Formula = substitute(self.actions[name].effect, self._binding(name, objects))
        out = set(facts)
        for part in flatten_effect(effect, {}):
            for lit in part.literals:
                fact = (lit.atom.predicate, *(t.name for t in lit.atom.args))
                (out.add if lit.positive else out.discard)(fact)
        return out


def _literal_text(atom) -> str:
    if isinstance(atom, Equals):
        return f"(= {atom.left.name} {atom.right.name})"
    return "(" + " ".join([atom.predicate, *(t.name for t in atom.args)]) + ")"


class _Physics(Exception):
    """A step's precondition is unmet because physics moved an object after an earlier step:
    that step's `then` should say so (`explain` starts over with it)."""

    def __init__(self, step: int, then: Tuple[FrozenSet[Fact], FrozenSet[Fact]]):
        super().__init__(step)
        self.step, self.then = step, then


def explain(seg: Segmentation, basis: Domain) -> Explanation:
    """The basis steps that explain the segmentation, checked against `basis`. Where a step
    needs an object to rest where physics put it (a pull drops it off a shelf, a chock lifted
    away lets it slide down a slope), the step in progress when it left where it was says so
    in its `then`: the object rests where the contacts show it, and no longer where it was."""
    thens: Dict[int, Tuple[FrozenSet[Fact], FrozenSet[Fact]]] = {}
    while True:   # each pass that fails adds a fact it had not: it ends
        try:
            return _explain(seg, basis, thens)
        except _Physics as found:
            previous = thens.get(found.step, (frozenset(), frozenset()))
            thens[found.step] = (previous[0] | found.then[0], previous[1] | found.then[1])


def _physics_then(seg: Segmentation, ops: "_Basis", steps: List[DemoStep], op: str, ground: Sequence[str],
                  state: Set[Fact], frame: int) -> Optional[_Physics]:
    """If `op`'s unmet precondition is an object resting where the contacts show it, moved
    there by physics (it fell, tipped or slid) after an earlier step began: the step in
    progress when it left where it was, and that step's `then`."""
    names = list(seg.bodies.names)
    before = max(0, frame - 1)
    needed = [f for f in ops.needs(op, ground) if f[0] == "support" and f not in state
              and names.index(f[2]) in seg.supports_of(names.index(f[1]), before)]
    for fact in needed:
        obj, now = names.index(fact[1]), set(seg.supports_of(names.index(fact[1]), before))
        left = frozenset(f for f in state if f[0] == "support" and f[1] == fact[1] and names.index(f[2]) not in now)
        old = {names.index(f[2]) for f in left}
        # When it left: the frame after it last rested on a support it had; with none gone,
        # when it came to rest where it is now for good.
        if old:
            moved = _after_last(seg, obj, before, lambda supports: bool(old & supports))
        else:
            moved = _after_last(seg, obj, before, lambda supports: names.index(fact[2]) not in supports)
        during = [k for k, st in enumerate(steps) if moved is not None and st.frame <= moved]
        if during:
            return _Physics(during[-1], (frozenset([fact]), left))
    return None


def _after_last(seg: Segmentation, obj: int, frame: int, test) -> Optional[int]:
    """The frame after the last one up to `frame` where `test(obj's supports)` holds, or None."""
    return next((f + 1 for f in range(frame, -1, -1) if test(set(seg.supports_of(obj, f)))), None)


def _explain(seg: Segmentation, basis: Domain, thens: Dict[int, Tuple[FrozenSet[Fact], FrozenSet[Fact]]]) -> Explanation:
    names = seg.bodies.names
    ops = _Basis(basis)
    segments = seg.segments
    static = {("fixed", names[o]) for o in seg.bodies.fixed}
    first = segments[0].mode
    initial = graph_facts(seg, 0, first.held)
    state = initial | static
    steps: List[DemoStep] = []
    moved: List[int] = []
    indirect: Set[int] = set()

    def add(op: str, objects: Tuple[int, ...], index: int, frame: int) -> None:
        nonlocal state
        ground = [names[o] for o in objects]
        problem = ops.unmet(op, ground, state)
        if problem is not None:
            physics = _physics_then(seg, ops, steps, op, ground, state, frame)
            if physics is not None and physics.then[0] - thens.get(physics.step, (frozenset(),))[0]:
                raise physics
            raise ExtractionError(
                f"at t = {seg.time(frame):.2f} s the demonstration does ({op} {' '.join(ground)}), but its "
                f"precondition {problem} does not hold after the steps before it: the basis operators cannot "
                "explain this demonstration")
        state = ops.apply(op, ground, state)
        then = thens.get(len(steps), (frozenset(), frozenset()))
        state = (state - then[1]) | then[0]
        steps.append(DemoStep(op, objects, index, frame, then))

    def support(obj: int, frame: int, window: Tuple[int, int]) -> int:
        """obj's support at `frame`: the one the symbolic state has, else the strongest."""
        found = seg.supports_of(obj, frame)
        if not found:
            for f in range(window[0], window[1] + 1):   # e.g. still settling at that frame
                found = seg.supports_of(obj, f)
                if found:
                    break
        if not found:
            raise ExtractionError(f"at t = {seg.time(frame):.2f} s {names[obj]} rests on nothing: "
                                  "no support to ground the step on")
        known = [y for y in found if ("support", names[obj], names[y]) in state]
        if known:
            return known[0]
        return max(found, key=lambda y: (pair_force(seg, frame, obj, y), -y))

    for i, s in enumerate(segments):
        prev = segments[i - 1].mode if i else None
        mode = s.mode
        if prev is not None and prev.held is not None and prev.held != mode.held:
            x = prev.held
            # What x rests on when let go (or first lands on): where the robot put it. What it
            # slides or tips onto afterwards is physics, and the demonstration's goal says it.
            add("place", (x, support(x, s.start, (s.start, s.end))), i, s.start)
        if prev is not None and mode.held is not None and prev.held != mode.held:
            x = mode.held
            before = max(0, s.start - 1)
            add("grasp", (x, support(x, before, (max(0, before - 10), s.start))), i, s.start)
        if mode.pushed:
            already: FrozenSet[int] = prev.pushed if prev is not None and prev.held == mode.held else frozenset()
            for y in sorted(mode.pushed - already):
                sy = support(y, s.start, (s.start, s.end))
                if mode.held is not None:
                    add("move-cont", (mode.held, y, sy), i, s.start)
                else:
                    add("transit-cont", (y, sy), i, s.start)
            # Indirect contacts: what the pushed objects touch while they are pushed.
            for f in range(s.start, s.end + 1):
                for a, b in seg.graphs[f].touching:
                    for y in mode.pushed:
                        other = b if a == y else a if b == y else None
                        if other is not None and other != mode.held and other not in mode.pushed:
                            indirect.add(other)
        for o in ([mode.held] if mode.held is not None else []) + sorted(mode.pushed):
            if o not in moved:
                moved.append(o)
    if not steps:
        raise ExtractionError("no contact mode changes in the demonstration: nothing to learn "
                              f"(the robot's mode is '{first.describe(names)}' throughout)")
    final = graph_facts(seg, seg.recording.frames - 1, segments[-1].mode.held)
    involved: List[int] = []
    for o in [o for st in steps for o in st.objects] + sorted(indirect):
        if o not in involved:
            involved.append(o)
    return Explanation(steps, initial, final, involved, [o for o in moved if o in involved], indirect)
