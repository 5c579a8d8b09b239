"""Skeletons as pure data: the basis steps a symbolic plan expands to, what each must produce,
and the keys under which refinement's evidence about a step is shared between skeletons.

Nothing here simulates or remembers: refinement (refine.py), the evidence store
(evidence.py), the schedule and serialisation all import these types, and this module
imports none of them.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Collection, Dict, List, Optional, Sequence, Set, Tuple

from ..operators.vocabulary import BASIS, Vocabulary
from ..samplers.interface import StepContext
from ..symbolic.optimistic import is_placeholder
from ..symbolic.task import Operator, StripsTask

StepKey = Tuple[str, Tuple[str, ...], Optional[str]]     # the step in any skeleton: operator, objects, own samplers
Grounding = Tuple[str, Tuple[str, ...]]                  # a mechanism and its object arguments
Promise = Tuple[Tuple[int, int], ...]                     # what a mechanism's last step certifies
Asked = Tuple[str, Tuple[str, ...], Optional[str]]      # a step as evidence pools it: + its mechanism
Context = Tuple[Asked, Tuple[Asked, ...]]                # that, and the steps before it
Question = Tuple[Asked, int]                              # that, and the contact state before it


@dataclass(frozen=True)
class Step:
    name: str
    args: Tuple[str, ...]
    expected: int                 # symbolic state the step must produce
    mechanism: Optional[str] = None
    certified: Promise = ()       # the last step of a mechanism: what it promised
    index: int = 0                # position in its mechanism (0 for a basis step)
    mechanism_args: Tuple[str, ...] = ()
    roles: Tuple[Tuple[str, str], ...] = ()  # the mechanism's placeholders and their variables
    tolerated: int = 0            # support facts that may hold although `expected` lacks them
    early: Tuple[int, int] = (0, 0)   # inside a mechanism: its certified (add, delete), which may hold already

    def context(self, at_start: bool = False) -> StepContext:
        """What the step's samplers are told about it (`at_start`: its objects lie where the
        scene began)."""
        return StepContext(self.name, self.args, self.mechanism, self.mechanism_args, self.index, self.roles,
                           at_start)


def objects_of(args: Sequence[str]) -> Tuple[str, ...]:
    """The object arguments (placeholders name stream outputs, which differ between skeletons)."""
    return tuple(a for a in args if not is_placeholder(a))


def step_label(operator: str, args: Sequence[str]) -> str:
    """A step as messages name it: its operator and objects (`grasp box table`)."""
    return " ".join((operator, *objects_of(args)))


def skeleton_groundings(steps: Sequence[Step]) -> List[Tuple[Grounding, Promise]]:
    """A skeleton's mechanism groundings, each with what it promises (its last step's
    certified facts)."""
    return [((s.mechanism, s.mechanism_args), s.certified) for s in steps if s.certified]


def fixed_objects(task: StripsTask, vocabulary: Vocabulary = BASIS) -> Set[str]:
    """Objects the initial state calls fixed: never moved, so never 'touched'."""
    return vocabulary.fixed_objects(task)


def touch_masks(task: StripsTask, vocabulary: Vocabulary = BASIS) -> Tuple[List[int], Dict[str, int]]:
    """Per operator, a bitmask of the movable objects it handles; and each object's bit."""
    fixed = fixed_objects(task, vocabulary)
    index: Dict[str, int] = {}
    masks = []
    for op in task.operators:
        mask = 0
        for name in objects_of(op.args):
            if name not in fixed:
                mask |= 1 << index.setdefault(name, len(index))
        masks.append(mask)
    return masks, index


def belief_owner(mechanism: Optional[str], own_samplers: Collection[str]) -> Optional[str]:
    """Whose dead-step belief a step of `mechanism` (None: a basis step) shares: its
    mechanism's where that proposes values of its own (`own_samplers`), else the generic
    samplers' (None)."""
    return mechanism if mechanism in own_samplers else None


def pristine_keys(steps: Sequence[Step], fixed: Set[str], own_samplers: Collection[str] = ()) -> List[Optional[StepKey]]:
    """For each step, its key if no earlier step touched any of its movable objects (it meets
    them as the scene began, in whatever skeleton), else None. The key names the mechanism
    when the step proposes values of its own (`own_samplers`: a demonstration's, anchored),
    else None: a sampler that ran dry speaks for itself (the generic grasps of a box out of
    reach say nothing of the grasp a demonstration showed on it)."""
    touched: Set[str] = set()
    keys: List[Optional[StepKey]] = []
    for step in steps:
        objects = objects_of(step.args)
        movable = {o for o in objects if o not in fixed}
        keys.append((step.name, objects, belief_owner(step.mechanism, own_samplers)) if not movable & touched else None)
        touched |= movable
    return keys


def step_contexts(steps: Sequence[Step]) -> List[Context]:
    """Each step with the steps before it (operators, objects, mechanisms; not the values,
    which differ between skeletons). Skeletons that begin alike start their common steps from
    the same scene, so they ask the same question of it (with the same samplers: a
    mechanism's step is told apart from the basis step), and their outcomes are shared
    evidence. The values drawn differ, so evidence is about the steps, not about a scene."""
    asked = [(step.name, objects_of(step.args), step.mechanism) for step in steps]
    return [(asked[i], tuple(asked[:i])) for i in range(len(asked))]


def step_questions(steps: Sequence[Step], init: int = 0, observable: int = -1) -> List[Question]:
    """Each step with the observable (contact) state the skeleton expects before it. The same
    step from the same contact state asks the scene the same thing in every skeleton, however
    the skeletons got there: held, with the tool on the table, does the box stay on the slope
    once let go?"""
    questions, before = [], init & observable
    for step in steps:
        questions.append(((step.name, objects_of(step.args), step.mechanism), before))
        before = step.expected & observable
    return questions


def detour_steps(task: StripsTask, plan: Sequence[int], masks: Sequence[int], flagged: int) -> int:
    """How many operators of `plan` lie in a detour no dead step explains: a run of operators
    that returns the symbolic state to one seen before (a push, a grasp and a place back)
    handling none of the `flagged` objects (those of steps found dead)."""
    state = task.init
    last_seen: Dict[int, int] = {state: 0}   # state -> after how many operators it was last seen
    in_detour: Set[int] = set()
    for j, op in enumerate(plan, 1):
        state = task.successor(state, task.operators[op])
        i = last_seen.get(state)
        if i is not None:
            handled = 0
            for earlier in plan[i:j]:
                handled |= masks[earlier]
            if not handled & flagged:
                in_detour.update(range(i, j))
        last_seen[state] = j
    return len(in_detour)


def mismatch(observed: int, step: Step, observable: int) -> int:
    """The observable facts where the simulation and the skeleton disagree after `step`:
    a fact the skeleton expects that does not hold, or one that holds unexpected and is
    not tolerated. Inside a mechanism, what its certified facts say may already be so (the
    pull that drops the box off the shelf, before the tool is put back)."""
    diff = (observed ^ step.expected) & observable
    added, deleted = step.early
    return diff & ~(observed & (step.tolerated | added)) & ~(~observed & deleted)


def goal_free_supports(task: StripsTask, vocabulary: Vocabulary = BASIS) -> int:
    """The task's support facts that the goal does not need false (nor any of a
    disjunctive goal's alternatives)."""
    supports = sum(1 << i for fact, i in task.fact_ids.items() if vocabulary.support_fact(fact))
    needed_false = task.goal_neg
    for op in task.operators:
        if op.artificial:
            needed_false |= op.neg
    return supports & ~needed_false


def tolerated_supports(task: StripsTask, candidates: int, step: Operator, later: Sequence[int],
                       vocabulary: Vocabulary = BASIS) -> int:
    """Support facts (of `candidates`) that `step` may add beyond its effects: an object
    that ends up resting on one more body than the skeleton says still rests on the ones
    it says (a weight put on a plate's overhang, its handle on the wall beyond). Not so the
    object a step moves without saying where it ends up (a push: an object pushed onto
    something else did not do what the skeleton says), nor a fact a later step needs false
    (a negative precondition, or a conditional effect's condition)."""
    needed_false = 0
    for op_id in later:
        op = task.operators[op_id]
        needed_false |= op.neg
        for cond in op.conditional:
            needed_false |= cond.pre | cond.neg
    moved = step.args[0] if step.args else None
    own = sum(1 << i for fact, i in task.fact_ids.items() if vocabulary.support_fact(fact) and fact[1] == moved)
    if step.add & own:  # the step says where its object comes to rest
        own = 0
    return candidates & ~needed_false & ~own


def skeleton_steps(task: StripsTask, plan: Sequence[int], vocabulary: Vocabulary = BASIS) -> List[Step]:
    """Basis steps of a skeleton with the state each must produce (macros expanded) and
    the support facts each may add unexpected (`tolerated_supports`). The artificial
    steps that reach a disjunctive goal have no physical content: the states the real
    steps must produce already satisfy one disjunct."""
    basis_ids = [b for op_id in plan if not task.operators[op_id].artificial
                 for b in (task.operators[op_id].steps or (op_id,))]
    steps, state, supports = [], task.init, goal_free_supports(task, vocabulary)
    for op_id in plan:
        op = task.operators[op_id]
        if op.artificial:
            continue
        expansion = op.steps or (op_id,)
        for k, basis_id in enumerate(expansion):
            basis = task.operators[basis_id]
            state = task.successor(state, basis)
            last = k == len(expansion) - 1
            macro = basis_id != op_id
            if macro and op.then:   # what the step's `:then` says physics makes so
                state = (state & ~op.then[k][1]) | op.then[k][0]
            if last and macro:   # where its certified facts say the mechanism leaves things
                state = (state & ~op.settles[1]) | op.settles[0]
            steps.append(Step(basis.name, basis.args, state, op.name if macro else None,
                              op.certified if last and op.steps else (), k if macro else 0,
                              tuple(a for a in op.args if not is_placeholder(a)) if macro else (),
                              op.roles if macro else (),
                              tolerated_supports(task, supports, basis, basis_ids[len(steps) + 1:], vocabulary),
                              _early(task, op, k) if macro and not last else (0, 0)))
    return steps


def _early(task: StripsTask, mechanism: Operator, k: int) -> Tuple[int, int]:
    """What may already be so after step `k` of a mechanism, before the step that says it:
    its certified facts (an object pulled off a ledge falls before the tool is put back) and
    later steps' `:then` (a block slides down as soon as the chock holding it is lifted, in
    the grasp's own lift), except what the steps between need otherwise."""
    added = deleted = needed_true = needed_false = 0
    for j in range(k + 1, len(mechanism.steps)):
        step = task.operators[mechanism.steps[j]]
        needed_true |= step.pre
        needed_false |= step.neg
        if mechanism.then:
            added |= mechanism.then[j][0] & ~needed_false
            deleted |= mechanism.then[j][1] & ~needed_true
    certified_added, certified_deleted = mechanism.settles
    return added | certified_added & ~needed_false, deleted | certified_deleted & ~needed_true


@dataclass
class Skeleton:
    """One skeleton as the planner holds it: its symbolic plan, its basis steps, their
    pristine keys, contexts and questions, its place in the search's order (order, from 1)
    and the order in which the planner came to know it (number, unique)."""

    order: int
    plan: List[int]
    steps: List[Step]
    pristine: List[Optional[StepKey]]
    contexts: List[Context]
    number: int = 0
    questions: List[Question] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.number = self.number or self.order
        self.questions = self.questions or step_questions(self.steps)

    def groundings(self) -> List[Tuple[Grounding, Promise]]:
        return skeleton_groundings(self.steps)

    def label(self, task: StripsTask) -> str:
        return " ".join(task.operators[o].label for o in self.plan)
