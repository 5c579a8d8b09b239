"""Failures on untouched objects are learned once and shared between skeletons (planner/
pristine.py), and the symbolic search tells paths apart by the objects they handled, so a
tool use that puts the box back where the symbols had it is still enumerated."""
import os

import pytest

from pdsketch_mech.envs import TASKS, sample
from pdsketch_mech.lang.loader import load_domain
from pdsketch_mech.lang.parser import parse_text
from pdsketch_mech.planner.bilevel import bilevel_plan, prepare_task
from pdsketch_mech.planner.budget import DEFAULT_BUDGET
from pdsketch_mech.planner.evidence import Evidence

DEAD_AFTER = DEFAULT_BUDGET.dead_after
from pdsketch_mech.planner.skeleton import Step, fixed_objects, pristine_keys
from pdsketch_mech.planner.supply import skeleton_order
from pdsketch_mech.symbolic.skeletons import iter_skeletons
from pdsketch_mech.world.build import build_world

from conftest import ROOT
from plan_fakes import empty_evidence, skeleton_of

BASIS = os.path.join(ROOT, "domains", "basis.pddl")
MECHANISMS = [os.path.join(ROOT, "domains", "mechanisms", f"{m}.pddl")
              for m in ("com", "edge", "hook-use", "lever", "poking", "slope-blocker")]


def _step(name, *args):
    return Step(name, args, expected=0)


def test_a_step_is_pristine_until_an_earlier_step_touches_one_of_its_movable_objects():
    steps = [_step("grasp", "tool", "table", "#g1"), _step("place", "tool", "slope", "#p1"),
             _step("grasp", "box", "table", "#g2"), _step("move-cont", "tool", "box", "table"),
             _step("grasp", "box", "table", "#g3")]
    keys = pristine_keys(steps, fixed={"table", "slope"})
    assert keys == [("grasp", ("tool", "table"), None), None, ("grasp", ("box", "table"), None), None, None]


def test_a_pristine_step_dies_after_repeated_dry_visits_unless_it_was_ever_feasible():
    memo = empty_evidence()
    grasp, push = ("grasp", ("box", "table"), None), ("transit-cont", ("box", "table"))
    for _ in range(DEAD_AFTER - 1):
        assert not memo.ran_dry(grasp)
    assert memo.ran_dry(grasp) and memo.blocks([None, grasp])
    assert not memo.blocks([push, None])
    memo.found(push)
    for _ in range(DEAD_AFTER + 2):
        assert not memo.ran_dry(push)       # a feasible value once: never dead
    memo.found(grasp)                        # a revived skeleton found one after all
    assert not memo.blocks([grasp]) and memo.labels() == {}
    assert not memo.ran_dry(None)            # steps on touched objects are not tracked


@pytest.fixture(scope="module")
def hook_slope():
    """Hook-then-Place-on-Slope, dev instance 0: a box beyond reach, a ladle, a brick."""
    problem = parse_text(sample(TASKS["hook-slope"], "dev", 0).problem_text(), "hook-slope-dev-0.pddl")
    loaded = load_domain([BASIS] + MECHANISMS)
    return loaded, problem


def test_fixed_objects_are_read_from_the_initial_state(hook_slope):
    loaded, problem = hook_slope
    task, _ = prepare_task(loaded, problem)
    assert fixed_objects(task) == {"table", "slope"}


def test_once_the_box_is_found_dead_where_it_lies_the_hook_and_put_back_comes_early(hook_slope):
    # Symbolically the hook and the put-back return to the initial state. Plain, the search
    # cuts that path off among the no-op pushes into that state; once grasping the untouched
    # box is dead, paths that would repeat it wait and the box's handling tells paths apart.
    loaded, problem = hook_slope
    task, _ = prepare_task(loaded, problem)
    wanted = "(hook-use tool target table) (place target table"

    def rank(skeletons, limit):
        for k, plan in zip(range(1, limit + 1), skeletons):
            label = " ".join(task.operators[o].label for o in plan)
            if label.startswith(wanted) and "(slope-blocker" in label:
                return k
        return None
    assert rank(skeleton_order(task), 1500) is None
    memo = Evidence(task)
    skeletons = skeleton_order(task, evidence=memo)
    for _ in range(DEAD_AFTER):
        memo.ran_dry(("grasp", ("target", "table"), None))
    assert rank(skeletons, 1500) is not None
    assert rank(iter_skeletons(task), 1500) is None


def test_an_operator_is_blocked_only_where_its_dead_step_is_still_pristine(hook_slope):
    loaded, problem = hook_slope
    task, _ = prepare_task(loaded, problem)
    memo = Evidence(task)
    masks = memo.masks
    for _ in range(DEAD_AFTER):
        memo.ran_dry(("grasp", ("target", "table"), None))
    ops = {op.label: i for i, op in enumerate(task.operators)}
    grasp = next(i for label, i in ops.items() if label.startswith("(grasp target table"))
    hook = ops["(hook-use tool target table)"]
    blocker = ops["(slope-blocker brick target table slope)"]
    assert memo.blocks_operator(0, grasp) and memo.blocks_operator(0, blocker)
    assert not memo.blocks_operator(0, hook)                 # its grasp comes after the pull
    assert not memo.blocks_operator(masks[hook], blocker)   # the box was hooked closer first


@pytest.mark.slow
def test_the_planner_finds_the_unreachable_box_dead_and_defers_what_grasps_it_first(hook_slope):
    loaded, problem = hook_slope
    with build_world(problem) as world:
        result = bilevel_plan(loaded, problem, world, timeout=60, seed=0, validate=False)
    stats = result.stats
    assert "(grasp target table)" in stats["dead_steps"] and stats["deferred"] > 20
    # The log lists the solving search's skeletons first: read the mechanisms' search's alone.
    created = [entry["skeleton"] for entry in stats["skeleton_log"] if entry["search"] == "mechanisms"]
    assert any(s.startswith("(hook-use tool target table) (place target table") for s in created[:40])   # the priced order shares the ranks
    # after the grasp died, a skeleton that grasps the untouched box first comes only to
    # revisit the belief, one per revisit
    died = stats["dead_steps"]["(grasp target table)"]
    late = [e["skeleton"] for e in stats["skeleton_log"] if e["created_s"] > died]
    assert late and sum(s.startswith("(grasp target table") for s in late) <= stats["revived"]


class _DryFirst:
    """A step sampler whose first `dry` visits find nothing, as a stochastic grasp sampler
    sometimes does on a thin object."""

    def __init__(self, dry: int):
        self.dry, self.visits = dry, 0

    def samples(self, world, step, rng, parents):
        self.visits += 1
        if self.visits <= self.dry:
            return iter(())
        return iter([{"#g1": "a grasp"}])

    def note_simulated(self, values):
        pass


def _refinement(sampler, memo):
    from types import SimpleNamespace

    import numpy as np

    from pdsketch_mech.planner.refine import Refinement
    world = SimpleNamespace(restore=lambda snapshot: None, bodies={})
    steps = [_step("grasp", "spoon", "table", "#g1")]
    return Refinement(skeleton_of(steps, fixed={"table"}), start=None, world=world, task=SimpleNamespace(fact_ids={}),
                      sampler=sampler, rng=np.random.default_rng(0), evidence=memo)


def test_one_dry_visit_of_the_first_step_does_not_end_a_skeleton_until_the_step_is_dead():
    lucky = _refinement(_DryFirst(dry=1), empty_evidence())
    assert lucky.run(deadline=float("inf"), max_work=1) is None and not lucky.exhausted
    # never feasible: dead after DEAD_AFTER dry visits, and only then is the skeleton over
    memo = empty_evidence()
    hopeless = _refinement(_DryFirst(dry=10 ** 6), memo)
    for visit in range(1, DEAD_AFTER + 1):
        hopeless.run(deadline=float("inf"), max_work=1)
        assert hopeless.exhausted == (visit == DEAD_AFTER)
    assert ("grasp", ("spoon", "table"), None) in memo.dead
    # without a shared record (self-play) one dry visit still ends it
    alone = _refinement(_DryFirst(dry=1), None)
    alone.run(deadline=float("inf"), max_work=1)
    assert alone.exhausted


def test_a_dead_step_met_again_with_its_objects_where_they_began_is_not_sampled():
    """A tool put down on the box out of reach leaves the box where it was: the grasp of the
    box after it is the dead step again (skipped); after a push that moved it, it is not."""
    from types import SimpleNamespace

    import numpy as np

    from pdsketch_mech.planner.refine import Refinement
    memo = empty_evidence()
    memo.bits = {"tool": 0, "box": 1}
    steps = [_step("place", "tool", "box", "#p1"), _step("grasp", "box", "table", "#g2")]
    moved = set()
    world = SimpleNamespace(moved_since=lambda snapshot, name: name in moved)
    refinement = Refinement(skeleton_of(steps, fixed={"table"}), start=None, world=world,
                            task=SimpleNamespace(fact_ids={}), sampler=None, rng=np.random.default_rng(0), evidence=memo)
    assert refinement.pristine[1] is None                # the place touched the box symbolically
    assert not refinement._dead_where_it_began(1)        # nothing is dead yet
    for _ in range(DEAD_AFTER):
        memo.ran_dry(("grasp", ("box", "table"), None))
    assert refinement._dead_where_it_began(1)
    moved.add("tool")                                    # the tool moved, the box did not
    assert refinement._dead_where_it_began(1)
    moved.add("box")
    assert not refinement._dead_where_it_began(1)
    assert not refinement._dead_where_it_began(0)        # the place is not dead
