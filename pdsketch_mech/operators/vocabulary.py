"""The basis vocabulary: what the planner needs to know about a basis domain, declared once.

The planner (`planner/`) names no predicate or operator of the basis domain. It asks a
`Vocabulary`: which predicates the simulation observes (the contact graph), which one says
what supports what and which one marks scene furniture, which operators only move the arm
through free space, and how each operator executes in the world. A domain names its
vocabulary, `(:vocabulary basis)` in domains/basis.pddl, and `vocabulary_of` finds it here
(VOCABULARIES); mechanisms over it need no planner code. A domain that names none is read
with the basis vocabulary.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable, Dict, Mapping, Optional, Sequence, Set, Tuple

from ..lang.errors import PddlError
from ..lang.nodes import Domain
from ..world.contacts import read_contacts
from ..world.values import OPERATOR_VALUES, Contact, Grasp, Placement, Trajectory
from . import basis
from .execution import FrameRecorder

if TYPE_CHECKING:
    from ..symbolic.task import StripsTask
    from ..world.world import World

# An operator's execution: the world, its arguments, their values bound, a recorder.
Executor = Callable[["World", Sequence[str], Sequence[object], Optional[FrameRecorder]], basis.Outcome]


def _of(kind, bound: Sequence[object]):
    return next((v for v in bound if isinstance(v, kind)), None)


def _grasp(world, args, bound, recorder):
    return basis.grasp(world, args[0], _of(Grasp, bound), _of(Trajectory, bound), recorder)


def _place(world, args, bound, recorder):
    return basis.place(world, args[0], _of(Placement, bound), _of(Trajectory, bound), recorder)


def _push(world, args, bound, recorder):
    return basis.push(world, _of(Contact, bound), _of(Trajectory, bound), recorder)


def _transit(world, args, bound, recorder):
    return basis.transit(world, _of(Trajectory, bound), recorder)


@dataclass(frozen=True)
class Vocabulary:
    """A basis domain as the planner reads it (module docstring)."""

    contacts: Tuple[str, ...]          # predicates the simulation observes after every step
    support: str                       # (support ?x ?y): ?y supports ?x
    fixed: str                         # (fixed ?x): furniture, never moved
    free_motions: Tuple[str, ...]      # operators that only move the arm through free space
    executors: Mapping[str, Executor]  # operator -> how it runs in the world
    values: Mapping[str, tuple]        # operator -> the value types it needs bound

    def contact_mask(self, task: "StripsTask") -> int:
        """The task facts the simulation can observe (the contact-mode graph)."""
        mask = 0
        for fact, i in task.fact_ids.items():
            if fact[0] in self.contacts:
                mask |= 1 << i
        return mask

    def observed(self, task: "StripsTask", world: "World") -> int:
        """The observable facts true in the world, as task bits."""
        state = 0
        for fact in read_contacts(world).facts():
            i = task.fact_ids.get(tuple(fact))
            if i is not None and fact[0] in self.contacts:
                state |= 1 << i
        return state

    def fixed_objects(self, task: "StripsTask") -> Set[str]:
        """Objects the initial state calls fixed: never moved, so never 'touched'."""
        held = [fact for i, fact in enumerate(task.facts) if task.init >> i & 1] + list(task.static_facts)
        return {fact[1] for fact in held if fact[0] == self.fixed}

    def support_fact(self, fact: Tuple[str, ...]) -> bool:
        """Whether `fact` says that something supports an object."""
        return fact[0] == self.support and len(fact) == 3

    def execute(self, world: "World", action: str, args: Sequence[str], values: Mapping[str, object],
                recorder: Optional[FrameRecorder] = None) -> basis.Outcome:
        """Run operator `action` with its arguments' sampled values."""
        run = self.executors.get(action)
        if run is None:
            raise ValueError(f"action '{action}' has no operator implementation; basis operators are "
                             f"{', '.join(self.executors)}")
        bound = [values.get(a, a) for a in args]
        missing = [kind.__name__.lower() for kind in self.values[action] if _of(kind, bound) is None]
        if missing:
            return basis.Outcome(False, f"no {' or '.join(missing)} value")
        return run(world, args, bound, recorder)


EXECUTORS: Dict[str, Executor] = {"transit": _transit, "move": _transit, "grasp": _grasp, "place": _place,
                                  "transit-cont": _push, "move-cont": _push}

BASIS = Vocabulary(contacts=("holding", "support", "handempty"), support="support", fixed="fixed",
                   free_motions=("transit", "move"), executors=EXECUTORS, values=OPERATOR_VALUES)

VOCABULARIES: Dict[str, Vocabulary] = {"basis": BASIS}


def vocabulary_of(domain: Domain) -> Vocabulary:
    """The vocabulary `domain` names (`(:vocabulary NAME)`), the basis one if it names none."""
    if domain.vocabulary is None:
        return BASIS
    found = VOCABULARIES.get(domain.vocabulary)
    if found is None:
        raise PddlError(f"unknown vocabulary '{domain.vocabulary}'; known: {', '.join(sorted(VOCABULARIES))}",
                        domain.vocabulary_loc)
    return found
