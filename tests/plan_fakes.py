"""Small stand-ins for the planner's tests: a skeleton from hand-written steps, a world and a
sampler that simulate nothing."""
from types import SimpleNamespace
from typing import Iterable, List, Sequence

from pdsketch_mech.planner.skeleton import Skeleton, Step, pristine_keys, step_contexts


def skeleton_of(steps: Sequence[Step], number: int = 1, fixed: Iterable[str] = ("table", "slope"),
                plan: Sequence[int] = ()) -> Skeleton:
    """A Skeleton of `steps` with the keys and contexts the supply would give it."""
    return Skeleton(number, list(plan), list(steps), pristine_keys(steps, set(fixed)), step_contexts(steps))


def still_world(bodies=None, moved=lambda name: True):
    """A world whose restores and snapshots do nothing."""
    return SimpleNamespace(bodies=bodies or {}, restore=lambda snapshot: None, snapshot=object,
                           moved_since=lambda snapshot, name: moved(name))


class OneValueSampler:
    """One value a visit for every step."""

    def samples(self, world, context, rng, parents):
        return iter([{"#v": context.operator}])

    def note_simulated(self, values):
        pass

    def note_outcome(self, values, ok):
        pass


def hook_steps(*after: Step) -> List[Step]:
    """Grasp the tool, pull the box with it, grasp the box; then `after`."""
    return [Step("grasp", ("tool", "table", "#g1"), 0), Step("move-cont", ("tool", "box", "table", "#c"), 0),
            Step("grasp", ("box", "table", "#g2"), 0)] + list(after)


def empty_evidence():
    """An evidence store for a task with no operators (skeletons written by hand)."""
    from pdsketch_mech.planner.evidence import Evidence
    task = SimpleNamespace(operators=[], facts=[], init=0, static_facts=[], successor=None)
    return Evidence(task)
