"""Learned samplers (samplers/learned/, learning/sampler_*.py, `learn train`): the PointNet++
pieces, training that learns a rule from labelled values, checkpoints that round-trip and
refuse another mechanism's definition, ranking that reorders but never drops proposals, and
the command end to end on a tiny configuration (Center-of-Mass, 4 episodes, 2 epochs)."""
from __future__ import annotations

import itertools
import os
import shutil
from dataclasses import replace

import numpy as np
import pytest
import torch

from pdsketch_mech.commands import learn, plan
from pdsketch_mech.lang.loader import load_domain
from pdsketch_mech.learning.sampler_data import param_data, parent_specs
from pdsketch_mech.learning.sampler_training import TrainConfig, roc_auc, to_batch, train_mechanism
from pdsketch_mech.samplers.interface import SampleRequest, StepContext
from pdsketch_mech.samplers.learned.checkpoint import CheckpointError, load, load_numpy, save
from pdsketch_mech.samplers.learned.encoding import VALUE_LAYOUT
from pdsketch_mech.samplers.learned.forward import NumpyClassifiers
from pdsketch_mech.samplers.learned.pointnet import ball_query, farthest_points
from pdsketch_mech.samplers.budget import SamplerBudget
from pdsketch_mech.samplers.learned.ranked import RankedSampler
from pdsketch_mech.samplers.learned.trust import Trust
from pdsketch_mech.samplers.learned.walk import walk
from pdsketch_mech.samplers.learned.specs import ParamSpec

BUDGET = SamplerBudget()   # the defaults the planner ranks with
EXPLORE, GAP, TOP_UPS = BUDGET.learned_explore, BUDGET.learned_top_up_gap, BUDGET.learned_top_ups

from learned_data import TINY, AllVerify, Numbers, synthetic_episodes

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def test_farthest_points_spread_out_and_ball_query_stays_inside():
    xyz = torch.tensor([[[0.0, 0, 0], [0.01, 0, 0], [1, 0, 0], [0, 1, 0], [0.02, 0.01, 0]]])
    chosen = farthest_points(xyz, 3)[0].tolist()
    assert chosen[0] == 0 and set(chosen[1:]) == {2, 3}  # the far corners before the near points
    group = ball_query(xyz, xyz[:, :1], radius=0.05, k=4)[0, 0]
    assert set(group.tolist()) <= {0, 1, 4}               # nothing from outside the ball
    assert (torch.cdist(xyz[0, group], xyz[0, :1]) <= 0.05).all()


def test_roc_auc():
    assert roc_auc(np.array([0.1, 0.4, 0.35, 0.8]), np.array([0, 0, 1, 1])) == 0.75
    assert roc_auc(np.array([0.2, 0.9]), np.array([0, 1])) == 1.0
    assert roc_auc(np.array([0.5, 0.5]), np.array([0, 1])) == 0.5
    assert roc_auc(np.array([0.5, 0.5]), np.array([1, 1])) is None


def test_training_learns_which_grasps_succeed():
    episodes = synthetic_episodes(30)
    specs = parent_specs(episodes)
    assert specs["?p"].parents == (("?g", "grasp"),) and specs["?g"].parents == ()
    model, reports = train_mechanism(episodes, TrainConfig(epochs=40, encoder=TINY, seed=1))
    grasp = next(r for r in reports if r.variable == "?g")
    assert grasp.validation_rows > 0 and grasp.auc is not None and grasp.auc > 0.9, grasp
    assert grasp.rejected > 0 and grasp.verify_auc > 0.9, grasp
    placement = next(r for r in reports if r.variable == "?p")
    assert placement.positives == 30
    # the score ranks raw proposals: a grasp that verifies and is used first, then one that is
    # reachable but not used, last one on the +x half that cannot be reached
    data = param_data(episodes, specs["?g"])
    classifier = model.classifier("?g")
    with torch.no_grad():
        ranked = []
        for x, y in [(0.02, 0.0), (-0.02, 0.0), (0.02, -0.025)]:
            rows = np.flatnonzero((np.sign(data.value[:, 0]) == np.sign(x))
                                  & ((data.value[:, 1] < -0.015) == (y < -0.015)) & (np.abs(data.value[:, 1]) > 0.005))
            ranked.append(float(classifier.log_score(to_batch(data, rows, torch.from_numpy(data.clouds()))).mean()))
    assert ranked[0] > ranked[1] > ranked[2], ranked
    # calibrated: P(used) of a proposal is below 1 even where the balanced heads are sure
    assert float(classifier.prior_shift[1]) != 0.0


def test_training_reports_how_the_first_step_ranks_across_episodes():
    """Probes compare groundings by the first step's scores (planner/probes.py), across
    episodes, failed ones included: training reports that AUC apart. Here every other episode
    fails whatever its grasps (a grounding that cannot work, which nothing in the data shows);
    the classifier learns from successful episodes only, so its ranking across episodes is
    worse than within them, and the report says so."""
    episodes = synthetic_episodes(30)
    for e, ep in enumerate(episodes):
        ep["step"] = np.array([0] * 12 + [1])
        if e % 2 == 0:                       # a failed episode: nothing used
            ep["label"][:] = 0
            ep["episode_success"] = np.array([False])
    _, reports = train_mechanism(episodes, TrainConfig(epochs=20, encoder=TINY, seed=1))
    grasp = next(r for r in reports if r.variable == "?g")
    assert grasp.grounding_auc is not None and grasp.auc is not None
    assert 0.5 < grasp.grounding_auc < grasp.auc, grasp
    placement = next(r for r in reports if r.variable == "?p")
    assert placement.grounding_auc is None    # not a first-step parameter


def test_rejected_proposals_beyond_the_cap_are_subsampled_and_weighted():
    episodes = synthetic_episodes(3)
    for ep in episodes:                      # 1000 rejected grasps per episode
        n = 1000
        extra = np.full((n, 16), np.nan)
        extra[:, :8] = np.c_[np.zeros((n, 1)), np.full((n, 1), -0.02), np.zeros((n, 1)),
                             np.tile([0, 0, 0, 1.0], (n, 1)), np.full(n, 0.05)]
        for key, rows in [("value", extra), ("proposal", extra), ("verified", np.zeros(n, np.int8)),
                          ("label", np.zeros(n, np.int8)), ("kind", np.array(["grasp"] * n)),
                          ("param", np.array(["?g"] * n)), ("param_index", np.full(n, 3)),
                          ("parents", np.full((n, 12), -1)), ("poses", np.repeat(ep["poses"][:1], n, axis=0))]:
            ep[key] = np.concatenate([ep[key], rows])
    data = param_data(episodes, parent_specs(episodes)["?g"])
    rejected = data.verified < 0.5
    total = 3 * 1000 + sum(int((ep["verified"][:12] == 0).sum()) for ep in synthetic_episodes(3))
    assert rejected.sum() == 2000 and np.isclose(data.weight[rejected].sum(), total)
    assert (data.weight[~rejected] == 1).all() and (~rejected).sum() == sum(int(ep["verified"][:12].sum())
                                                                           for ep in synthetic_episodes(3))


def test_same_seed_same_weights():
    episodes = synthetic_episodes(6)
    a, _ = train_mechanism(episodes, TrainConfig(epochs=2, encoder=TINY, seed=3))
    b, _ = train_mechanism(episodes, TrainConfig(epochs=2, encoder=TINY, seed=3))
    for (name, x), (_, y) in zip(a.state_dict().items(), b.state_dict().items()):
        assert torch.equal(x, y), name


@pytest.fixture()
def com_fragment(tmp_path):
    """A copy of the Center-of-Mass fragment (and the basis it extends) to write beside."""
    shutil.copy(os.path.join(ROOT, "domains", "basis.pddl"), tmp_path / "basis.pddl")
    (tmp_path / "mechanisms").mkdir()
    path = tmp_path / "mechanisms" / "com.pddl"
    with open(os.path.join(ROOT, "domains", "mechanisms", "com.pddl"), encoding="utf-8") as handle:
        text = handle.read()  # as extracted: without the committed checkpoint's :sampler line
    path.write_text(text.replace('\n    :sampler "com.samplers.safetensors"', ""))
    return str(path)


def as_numpy(model) -> NumpyClassifiers:
    return NumpyClassifiers(list(model.specs.values()), model.encoder,
                            {k: v.numpy() for k, v in model.state_dict().items()})


def test_numpy_forward_pass_scores_as_torch_does():
    """Planning ranks with forward.py (no torch import); it must be the network training fitted."""
    from pdsketch_mech.samplers.learned.model import Batch, MechanismClassifiers
    torch.manual_seed(0)
    specs = [ParamSpec("?c", "contact", (("?g", "grasp"), ("?t", "push")), 3, axes=True, scaled=True),
             ParamSpec("?g", "grasp", (), 2, scaled=True),
             ParamSpec("?k", "contact", (), 2),   # a checkpoint from before directions were turned
             ParamSpec("?p", "placement", (("?g", "grasp"),), 2, outputs=1)]
    model = MechanismClassifiers(specs, TINY)
    with torch.no_grad():  # non-trivial statistics and priors, so that every term is exercised
        for name, tensor in model.state_dict().items():
            if name.endswith((".mean", ".std", "prior_shift")):
                tensor.copy_(torch.rand_like(tensor) + 0.5)
    numpy_model = as_numpy(model)
    rng = np.random.default_rng(0)
    clouds = rng.normal(size=(3, 64, 3)).astype(np.float32)
    clouds /= np.linalg.norm(clouds, axis=-1).max()
    for spec in specs:
        classifier, mirror = model.classifier(spec.variable), numpy_model.classifier(spec.variable)
        with torch.no_grad():
            expected_shapes = classifier.shape_vectors(torch.from_numpy(clouds)).numpy()
        shapes = np.stack([mirror.shape_vector(c) for c in clouds])
        np.testing.assert_allclose(shapes, expected_shapes, rtol=1e-4, atol=1e-4)
        rows, m = 5, spec.objects
        value = rng.normal(size=(rows, len(VALUE_LAYOUT[spec.kind])))
        parents = [rng.normal(size=len(VALUE_LAYOUT[k])) for _, k in spec.parents]
        present = np.array([1.0, 0.0][:len(parents)])
        parents = [p * flag for p, flag in zip(parents, present)]
        sizes, poses = rng.uniform(0.02, 0.2, size=(m, 3)), rng.normal(size=(m, 7))
        poses[:, 3:] /= np.linalg.norm(poses[:, 3:], axis=1, keepdims=True)
        f32 = lambda a: torch.tensor(np.asarray(a), dtype=torch.float32)  # noqa: E731
        batch = Batch(f32(value), [f32(p).expand(rows, -1) for p in parents], f32(present).expand(rows, -1),
                      f32(clouds), torch.arange(m).expand(rows, -1), f32(sizes).expand(rows, -1, -1),
                      f32(poses).expand(rows, -1, -1))
        with torch.no_grad():
            expected = classifier.log_score(batch).numpy()
        got = mirror.log_score(value, parents, present, sizes, poses, shapes[:m])
        np.testing.assert_allclose(got, expected, rtol=1e-4, atol=1e-4)
        assert np.ptp(got) > 1e-3  # the rows differ: the value reaches the score


def test_a_contacts_directions_are_seen_in_each_objects_frame():
    """With `axes`, a contact's normal and push direction are turned into every context
    object's frame (where a push goes relative to the tunnel); specs without it (older
    checkpoints) keep the old features and load as they were."""
    from pdsketch_mech.samplers.learned.model import Batch, ParamClassifier
    from pdsketch_mech.samplers.learned.specs import object_features
    turned, old = ParamSpec("?c", "contact", (), 1, axes=True), ParamSpec.from_json(
        {"variable": "?c", "kind": "contact", "parents": [], "objects": 1, "outputs": 2})
    assert not old.axes and object_features(turned) == object_features(old) + 6
    assert ParamSpec.from_json(turned.to_json()) == turned
    value = torch.zeros(1, 16)
    value[0, 13:16] = torch.tensor([1.0, 0.0, 0.0])                       # pushing along world x
    quarter = torch.tensor([0.0, 0.0, 0.5 ** 0.5, 0.5 ** 0.5])   # an object turned 90 deg about z
    poses = torch.cat([torch.zeros(3), quarter]).view(1, 1, 7)
    batch = Batch(value, [], torch.zeros(1, 0), torch.zeros(1, 8, 3), torch.zeros(1, 1, dtype=torch.long),
                  torch.ones(1, 1, 3), poses)
    features = ParamClassifier(turned, TINY).object_inputs(batch)[0, 0]
    assert torch.allclose(features[-3:], torch.tensor([0.0, -1.0, 0.0]), atol=1e-6)   # along the object's -y


def test_a_placement_is_also_seen_in_each_objects_half_extents():
    """With `scaled`, a placement's position is given in each context object's frame divided
    by its half-extents: the same spot on a plate resized 1.2x gives the same feature (a novel
    variant is often a resized seen one), and older specs load without it."""
    from pdsketch_mech.samplers.learned.model import Batch, ParamClassifier
    from pdsketch_mech.samplers.learned.specs import object_features
    scaled, old = ParamSpec("?p", "placement", (), 1, scaled=True), ParamSpec.from_json(
        {"variable": "?p", "kind": "placement", "parents": [], "objects": 1, "outputs": 2})
    assert not old.scaled and object_features(scaled) == object_features(old) + 3
    assert ParamSpec.from_json(scaled.to_json()) == scaled
    quarter = torch.tensor([0.0, 0.0, 0.5 ** 0.5, 0.5 ** 0.5])   # the plate turned 90 deg about z
    poses = torch.cat([torch.tensor([0.5, 0.0, 0.0]), quarter]).view(1, 1, 7)

    def features(half_extents, value_xyz):
        value = torch.zeros(1, 7)
        value[0, :3], value[0, 6] = torch.tensor(value_xyz), 1.0
        batch = Batch(value, [], torch.zeros(1, 0), torch.zeros(1, 8, 3), torch.zeros(1, 1, dtype=torch.long),
                      torch.tensor(half_extents).view(1, 1, 3), poses)
        return ParamClassifier(scaled, TINY).object_inputs(batch)[0, 0, -3:]

    small = features([0.10, 0.10, 0.01], [0.5, 0.08, 0.02])     # 8 cm along the plate's x
    large = features([0.12, 0.12, 0.01], [0.5, 0.096, 0.02])    # the same spot on a 1.2x plate
    assert torch.allclose(small, torch.tensor([0.8, 0.0, 2.0]), atol=1e-5)
    assert torch.allclose(small, large, atol=1e-5)


def test_checkpoint_round_trip_and_refusal(com_fragment, tmp_path):
    mechanism = load_domain([com_fragment]).domain.mechanisms[0]
    episodes = synthetic_episodes(4)
    model, _ = train_mechanism(episodes, TrainConfig(epochs=1, encoder=TINY))
    weights = str(tmp_path / "mechanisms" / "com.samplers.safetensors")
    save(weights, model, mechanism, {"seed": 0})
    with open(weights, "rb") as handle:
        assert not handle.read(64).startswith(b"\x80")  # not a pickle
    loaded, meta = load(weights, mechanism, com_fragment)
    assert meta["mechanism"] == "com" and meta["encoder"]["out"] == TINY.out
    for (name, x), (_, y) in zip(model.state_dict().items(), loaded.state_dict().items()):
        assert torch.equal(x, y), name
    changed = replace(mechanism, actions=mechanism.actions[:1])
    with pytest.raises(CheckpointError, match=r"com\.samplers\.safetensors was trained for another definition .*/com\.pddl;"):
        load(weights, changed, com_fragment)
    assert load(weights, replace(mechanism, sampler="elsewhere.safetensors"), com_fragment)  # :sampler is not hashed
    assert set(load_numpy(weights, mechanism, com_fragment)[0].by_variable) == set(model.by_variable)


def test_a_checkpoint_missing_a_tensor_is_refused_when_loaded(com_fragment, tmp_path):
    from safetensors.numpy import load_file, save_file
    mechanism = load_domain([com_fragment]).domain.mechanisms[0]
    model, _ = train_mechanism(synthetic_episodes(4), TrainConfig(epochs=1, encoder=TINY))
    weights = str(tmp_path / "com.samplers.safetensors")
    save(weights, model, mechanism, {"seed": 0})
    tensors = load_file(weights)
    del tensors[next(k for k in tensors if k.endswith("head.2.bias"))]
    save_file(tensors, weights)
    for loader in (load, load_numpy):
        with pytest.raises(CheckpointError, match=r"com\.samplers\.safetensors: cannot load the checkpoint"):
            loader(weights, mechanism, com_fragment)


def test_walk_ranks_and_explores_but_keeps_every_proposal():
    scores = np.array([0.1, 0.9, 0.5, 0.7])
    assert [i for i, _ in walk(scores, np.random.default_rng(0), lambda: 0.0)] == [1, 3, 2, 0]
    for seed in range(5):
        picks = list(walk(scores, np.random.default_rng(seed), lambda: 0.5))
        assert sorted(i for i, _ in picks) == [0, 1, 2, 3]
    assert all(explored for _, explored in list(walk(scores, np.random.default_rng(0), lambda: 1.0))[:-1])


def test_walk_tops_up_a_batch_whose_best_left_is_hopeless():
    """After the batch's best, the rest lie more than GAP below it: the walk takes the fresh
    proposals the caller appends first, and walks on through the old ones when no more come."""
    fresh = [np.array([-1.0, -4.0 * GAP])]
    calls = []

    def top_up():
        calls.append(1)
        return fresh.pop() if fresh else np.zeros(0)

    scores = np.array([0.0, -2.0 * GAP, -3.0 * GAP])
    picks = [i for i, _ in walk(scores, np.random.default_rng(0), lambda: 0.0, top_up)]
    assert picks == [0, 3, 1, 2, 4]           # the fresh -1 before the old -2 GAP; nothing dropped
    assert len(calls) == TOP_UPS              # a walk stops asking once its top-ups are spent
    close = np.array([0.0, -0.5 * GAP])
    assert [i for i, _ in walk(close, np.random.default_rng(0), lambda: 0.0, top_up)] == [0, 1]
    assert len(calls) == TOP_UPS              # the rest was not hopeless: no top-up asked
    fresh[:] = [np.array([-1.0]), np.array([-1.0])]
    once = SamplerBudget(learned_top_ups=1)
    assert [i for i, _ in walk(scores, np.random.default_rng(0), lambda: 0.0, top_up, once)] == [0, 3, 1, 2]
    assert len(calls) == TOP_UPS + 1          # the budget given is the one spent


def test_trust_keeps_the_learned_order_unless_random_picks_do_better():
    trust = Trust(EXPLORE)
    assert trust.explore_chance() == EXPLORE                 # no evidence: the floor
    for _ in range(4):
        trust.record(explored=False, ok=True)
        trust.record(explored=True, ok=False)
    assert trust.explore_chance() == EXPLORE                 # learned picks do better: unchanged
    even = Trust(EXPLORE)
    for ok in (True, True, False):
        even.record(explored=False, ok=ok)
        even.record(explored=True, ok=ok)
    assert even.explore_chance() == EXPLORE                  # as good as random (a grasp that works either way)
    doubt = Trust(EXPLORE)
    for _ in range(3):
        doubt.record(explored=False, ok=False)
    assert 0.4 < doubt.explore_chance() < 0.9                # learned picks keep failing: explore more
    for _ in range(3):
        doubt.record(explored=True, ok=True)
    assert doubt.explore_chance() > 0.95                     # and random ones work: the generic order


class ByValue:
    """A stand-in scorer: higher numbers first."""

    score_seconds: list = []

    def score(self, world, request, variable, proposals):
        return np.array(proposals, dtype=float)

    def extrapolates(self, world, request, variable, budget=None):
        return None   # no fixed object out of place


def best_first(scores, rng, explore, top_up=None, budget=None):
    """A walk that never explores nor tops up: the batch strictly best first."""
    return ((int(i), False) for i in np.argsort(-scores, kind="stable"))


def test_ranked_sampler_verifies_best_first_and_drops_nothing(monkeypatch):
    monkeypatch.setattr("pdsketch_mech.samplers.learned.ranked.walk", best_first)
    no_refills = SamplerBudget(learned_refills=0)   # Numbers proposes the same each call
    request = SampleRequest("s", (), (), StepContext("grasp", ()))
    proposals = RankedSampler(Numbers(10), ByValue(), "?t", pool=0, budget=no_refills)   # a push: rank proposals
    assert list(proposals.draw(None, request, np.random.default_rng(0), budget=10)) == [8, 6, 4, 2, 0]
    assert proposals.examined == 10
    pooled = RankedSampler(Numbers(10), ByValue(), "?g", pool=3, budget=no_refills)  # a grasp: rank values
    assert list(pooled.draw(None, request, np.random.default_rng(0), budget=10)) == [4, 2, 0, 8, 6]
    assert pooled.examined == 10


class TwoPerCall(Numbers):
    """A stand-in proposer that finds two proposals per call (a contact proposer's few usable
    points), new ones each call, and none after `calls` calls."""

    def __init__(self, calls):
        super().__init__(0)
        self.calls, self.made = calls, 0

    def propose(self, world, request, rng, budget):
        self.made += 1
        start = 2 * (self.made - 1)
        return iter(range(start, start + 2) if self.made <= self.calls else ())


def test_a_batch_calls_a_proposer_that_ran_dry_again(monkeypatch):
    """A proposer that finds two proposals per call is called again until the batch is full,
    so that the classifier has a batch to choose from; a call that finds none ends it. The
    visit verifies no more than the first call found."""
    monkeypatch.setattr("pdsketch_mech.samplers.learned.ranked.walk", best_first)
    BATCH, REFILLS = BUDGET.learned_batch, BUDGET.learned_refills
    request = SampleRequest("s", (), (), StepContext("grasp", ()))
    proposer = TwoPerCall(calls=100)
    ranked = RankedSampler(proposer, ByValue(), "?c", pool=0)
    first = next(ranked.draw(None, request, np.random.default_rng(0), budget=60))
    assert proposer.made == BATCH // 2 <= 1 + REFILLS
    assert first == BATCH - 2                 # the best even number of the full batch 0..15
    dry = TwoPerCall(calls=3)
    capped = RankedSampler(dry, ByValue(), "?c", pool=0)
    values = list(capped.draw(None, request, np.random.default_rng(0), budget=60))
    assert dry.made == 4                      # the fourth call found none: no more calls
    assert values == [4] and capped.examined == 2   # 5 and 4, the best two of 0..5: a visit verifies
                                                    # as many as the first call found, as generic would


class Peaked(AllVerify):
    """A stand-in proposer whose every call proposes one value a classifier believes in
    (100 - the call's number) among fifteen it does not (-100 and below)."""

    def __init__(self):
        super().__init__(0)
        self.made = 0

    def propose(self, world, request, rng, budget):
        self.made += 1
        k = self.made - 1
        return iter([100 - k] + [-100 - 16 * k - j for j in range(15)])


def test_a_ranked_sampler_tops_up_a_batch_rather_than_verify_its_hopeless_rest():
    """Once the batch's best is taken, the next verified is the best of a fresh batch, not
    the old batch's hopeless second; after TOP_UPS fresh batches the old rest comes in order.
    A visit that will verify no more draws no fresh batch (proposing moves the rng)."""
    never_explore = SamplerBudget(learned_explore=0.0)
    assert 200 > GAP
    request = SampleRequest("s", (), (), StepContext("place", ()))
    proposer = Peaked()
    ranked = RankedSampler(proposer, ByValue(), "?p", pool=0, budget=never_explore)
    values = list(itertools.islice(ranked.draw(None, request, np.random.default_rng(0), budget=16), TOP_UPS + 2))
    assert values == [100.0 - k for k in range(TOP_UPS + 1)] + [-100.0]
    assert proposer.made == TOP_UPS + 1
    one = Peaked()
    once = RankedSampler(one, ByValue(), "?p", pool=0, budget=never_explore)
    assert list(once.draw(None, request, np.random.default_rng(0), budget=1)) == [100.0]
    assert one.made == 1


def test_a_ranked_sampler_that_keeps_failing_falls_back_to_the_generic_order():
    """The classifier ranks the high numbers first, but only values below 4 simulate well
    (a shape it never saw): the plan's outcomes move the walk to random picks, per grounding."""
    from pdsketch_mech.planner.bindings import StepSampler
    request = SampleRequest("s", (), (), StepContext("place", (), "m", ("tool", "box")))
    ranked = RankedSampler(AllVerify(16), ByValue(), "?p", pool=0)
    steps = StepSampler({}, {}, None)
    steps._ranked[("s", "m", "?p")] = ranked      # as sampler_for() registers it
    rng = np.random.default_rng(0)
    firsts = []
    for _ in range(12):                           # twelve visits of the step, 3 values each
        values = list(itertools.islice(ranked.draw(None, request, rng, budget=16), 3))
        firsts.append(values[0])
        for value in values:
            steps.note_outcome({"#p": value}, value < 4)
    trust = ranked.trust[("tool", "box")]
    assert trust.learned_failed >= 3 and trust.explore_chance() > 0.9, trust
    assert firsts[0] == 15.0 and np.mean(firsts[-4:]) < 12   # the best-ranked first, random picks later
    assert steps.trust()["m ?p"]["explore"] > 0.9
    other = SampleRequest("s", (), (), StepContext("place", (), "m", ("stick", "box")))
    assert ranked.trust_for(other).explore_chance() == EXPLORE   # another grounding starts afresh
    ranked.outcome(15.0, False)                   # a value this sampler never yielded: ignored
    assert ranked.trust[("tool", "box")].learned_failed == trust.learned_failed


class _Spread:
    """A classifier whose training had every object at x = y = 0.5, give or take 2 cm."""

    def position_statistics(self, slot):
        return np.array([0.5, 0.5]), np.array([0.02, 0.02])


class _Where:
    """A world of objects at given positions; the slope is fixed, the others movable."""

    def __init__(self, **at):
        self.at = at
        self.bodies = {name: type("Body", (), {"fixed": name == "slope"})() for name in at}

    def pose(self, name):
        return (self.at[name] + (0.1,), (0.0, 0.0, 0.0, 1.0))


def test_a_classifier_is_not_asked_where_its_objects_never_were(monkeypatch):
    """A fixed object farther from its training positions than EXTRAPOLATION_Z standard
    deviations (a slope moved across the table in a composition) sends the step to the
    generic sampler, unranked and counted; within them, or a movable object as far (a box
    out of reach elsewhere), the classifier ranks."""
    from pdsketch_mech.planner.bindings import StepSampler
    from pdsketch_mech.samplers.learned.ranked import LearnedMechanism
    EXTRAPOLATION_Z = BUDGET.learned_extrapolation_z
    monkeypatch.setattr("pdsketch_mech.samplers.learned.ranked.walk", best_first)
    learned = LearnedMechanism.__new__(LearnedMechanism)
    learned.model = type("Model", (), {"classifier": lambda self, variable: _Spread()})()
    learned.context, learned._context = 0, {}
    learned.score = ByValue().score
    request = SampleRequest("s", (), (), StepContext("place", (), "m", ("stick", "slope")))
    near = 0.5 + 0.02 * (EXTRAPOLATION_Z - 1)
    far = 0.5 + 0.02 * (EXTRAPOLATION_Z + 1)
    assert not learned.extrapolates(_Where(stick=(0.5, 0.5), slope=(near, 0.5)), request, "?p")
    assert learned.extrapolates(_Where(stick=(0.5, 0.5), slope=(0.5, far)), request, "?p") == "slope"
    assert learned.extrapolates(_Where(stick=(far, far), slope=(0.5, 0.5)), request, "?p") is None
    stricter = SamplerBudget(learned_extrapolation_z=EXTRAPOLATION_Z - 2)   # the budget given decides
    assert learned.extrapolates(_Where(stick=(0.5, 0.5), slope=(near, 0.5)), request, "?p", stricter) == "slope"
    ranked = RankedSampler(AllVerify(8), learned, "?p", pool=0)
    steps = StepSampler({}, {}, None)
    steps._ranked[("s", "m", "?p")] = ranked
    rng = np.random.default_rng(0)
    assert list(ranked.draw(_Where(stick=(0.5, 0.5), slope=(near, 0.5)), request, rng, budget=3))[0] == 7.0
    moved = _Where(stick=(0.5, 0.5), slope=(0.5, far))
    assert list(ranked.draw(moved, request, rng, budget=3)) == [0.0, 1.0, 2.0]   # the generic order
    assert ranked.extrapolated == {(("stick", "slope"), "slope"): 1}
    assert steps.trust()["m ?p"]["extrapolated"] == 1
    warning, = steps.extrapolation_warnings()   # the plan command prints it
    assert warning.startswith("mechanism 'm': its learned samplers were not used on 1 visit of its steps, "
                              "because slope stood far")


def test_classifiers_of_proposals_rank_proposals_and_those_of_values_a_pool():
    from pdsketch_mech.samplers.learned.model import MechanismClassifiers
    from pdsketch_mech.samplers.learned.ranked import LearnedMechanism
    POOL = BUDGET.learned_pool
    specs = [ParamSpec("?g", "grasp", (), 2), ParamSpec("?p", "placement", (), 2, outputs=1),
             ParamSpec("?t", "push", (), 2, outputs=1)]
    learned = LearnedMechanism(as_numpy(MechanismClassifiers(specs, TINY)), {})
    assert RankedSampler(Numbers(4), learned, "?g").pool == 0      # schema /2: raw proposals, best first
    assert RankedSampler(Numbers(4), learned, "?p").pool == POOL   # schema /1: a pool of verified values
    assert RankedSampler(Numbers(4), learned, "?p", budget=SamplerBudget(learned_pool=3)).pool == 3
    assert RankedSampler(Numbers(4), learned, "?t").pool == 0      # a push's distance either way


def test_the_mechanism_steps_know_their_variables():
    from pdsketch_mech.lang.loader import load_problem
    from pdsketch_mech.planner.bilevel import prepare_task
    from pdsketch_mech.planner.skeleton import skeleton_steps
    dom = load_domain([os.path.join(ROOT, "domains", "mechanisms", "hook-use.pddl")])
    _, problem = load_problem(os.path.join(ROOT, "problems", "hook-use.pddl"), [dom])
    task, _ = prepare_task(dom, problem, use_mechanisms=True)
    macro = next(i for i, op in enumerate(task.operators) if op.name == "hook-use" and op.args[:2] == ("hook", "box"))
    steps = skeleton_steps(task, [macro])
    roles = {var: ph for ph, var in steps[0].roles}
    assert {"?g1", "?c", "?p", "?g2"} <= set(roles)
    assert roles["?g1"] in steps[0].args and roles["?c"] in steps[1].args and roles["?g2"] in steps[3].args


@pytest.mark.slow
def test_learn_train_then_plan_with_the_checkpoint(com_fragment, tmp_path, capsys):
    data = str(tmp_path / "data")
    assert learn.main(["train", "com", "--episodes", "4", "--epochs", "2", "--out", data, "--unvalidated",
                       "--fragment", com_fragment, "--task", "com", "--compare", "1"]) == 0
    folder = os.path.dirname(com_fragment)
    for suffix in (".samplers.safetensors", ".samplers.json", ".samplers.md", ".samplers.png", ".samplers-fig8.png"):
        assert os.path.isfile(os.path.join(folder, "com" + suffix)), suffix
    with open(os.path.join(folder, "com.samplers.md"), encoding="utf-8") as handle:
        assert "| all | macro+sampler | 1/1 |" in handle.read()  # --compare: the test instance, planned both ways
    with open(com_fragment, encoding="utf-8") as handle:
        assert ':sampler "com.samplers.safetensors"' in handle.read()
    capsys.readouterr()
    assert learn.main(["train", "com", "--episodes", "4", "--epochs", "2", "--out", data, "--unvalidated",
                       "--fragment", com_fragment, "--task", "com"]) == 2  # not replaced without --force
    assert "exists: --force replaces it" in capsys.readouterr().err
    # Training reads episodes 0 and 1 of the 4 on disk, and the recorded command asks for 2.
    assert learn.main(["train", "com", "--episodes", "2", "--epochs", "2", "--out", data, "--unvalidated",
                       "--fragment", com_fragment, "--task", "com", "--force"]) == 0
    import json
    with open(os.path.join(folder, "com.samplers.json"), encoding="utf-8") as handle:
        meta = json.load(handle)
    assert meta["episodes"] == 2 and "--episodes 2 " in meta["command"] + " "
    # Re-run as recorded, the command reads this fragment and data, not the repository's.
    assert f" --fragment {com_fragment} --task com --out {data}" in meta["command"]
    problem = str(tmp_path / "p.pddl")
    from pdsketch_mech.envs.generate import sample
    from pdsketch_mech.envs.tasks import TASKS
    with open(problem, "w", encoding="utf-8") as handle:
        handle.write(sample(TASKS["com"], "dev", 5).problem_text())
    capsys.readouterr()
    result = str(tmp_path / "plan.json")
    assert plan.main([com_fragment, problem, "--timeout", "120", "--json", result]) == 0
    with open(result, encoding="utf-8") as handle:
        stats = json.load(handle)["stats"]
    assert stats["learned_samplers"] == ["com"] and stats["proposals"]["learned"].get("grasp", 0) > 0
    assert plan.main([com_fragment, problem, "--timeout", "120", "--json", result, "--no-learned-samplers"]) == 0
    with open(result, encoding="utf-8") as handle:
        stats = json.load(handle)["stats"]
    assert stats["learned_samplers"] == "off" and not stats["proposals"]["learned"]


def test_bench_samplers_table_compares_medians_overall_and_where_both_solved():
    from pdsketch_mech.bench.samplers import SamplerTrial, table
    trials = [SamplerTrial("a", False, "macro", "solved", 10, {"grasp": 10}, {"grasp": 6}),
              SamplerTrial("a", False, "macro+sampler", "solved", 5, {"grasp": 4}, {"grasp": 2}),
              SamplerTrial("b", True, "macro", "unsolved", 120, {"grasp": 50}, {"grasp": 30}),
              SamplerTrial("b", True, "macro+sampler", "solved", 9, {"grasp": 5}, {"grasp": 3}),
              SamplerTrial("b", True, "macro", "solved", 20, {"grasp": 50}, {"grasp": 30}, seed=1000),   # another run of b
              SamplerTrial("b", True, "macro+sampler", "unsolved", 120, {"grasp": 50}, {"grasp": 30}, seed=1000)]
    _, rows, lines = table(trials)
    assert ["all", "macro", "2/3", "15.0", "50.0", "30.0", "grasp 50.0/30.0"] in rows
    assert ["held-out categories", "macro+sampler", "1/2", "9.0", "27.5", "16.5", "grasp 27.5/16.5"] in rows
    assert ["solved by both", "macro", "1/1", "10.0", "10.0", "6.0", "grasp 10.0/6.0"] in rows  # runs, not instances
    assert lines[0].startswith("all instances, learned against generic samplers (medians): 10.00x fewer values "
                               "simulated (3 against 30)")
    assert lines[1].startswith("instances solved by both, learned against generic samplers (medians): 3.00x fewer "
                               "values simulated (2 against 6)")


def test_bench_samplers_says_as_many_or_more_when_learned_samplers_do_not_save():
    from pdsketch_mech.bench.samplers import _fewer
    assert (_fewer(4, 4), _fewer(12, 4), _fewer(4, 5)) == ("as many", "3.00x fewer", "1.25x more")


def test_bench_samplers_says_how_few_values_a_plan_through_the_mechanism_can_take():
    """Center-of-Mass's two steps have four continuous parameters: where the generic samplers
    take 4 values, the table says no sampler can take fewer, rather than leave 1.0x unexplained."""
    from pdsketch_mech.bench.samplers import SamplerTrial, fewest_values, table
    assert (fewest_values("domains/mechanisms/com.pddl", "com"), fewest_values("domains/mechanisms/lever.pddl", "lever"),
            fewest_values("domains/mechanisms/poking.pddl", "poking")) == (4, 6, 8)
    trials = [SamplerTrial("a", False, "macro", "solved", 1, {"grasp": 12}, {"grasp": 2, "placement": 2}),
              SamplerTrial("a", False, "macro+sampler", "solved", 1, {"grasp": 4}, {"grasp": 2, "placement": 2})]
    assert ("the fewest values a plan through the mechanism's steps simulates: 4 (one per continuous parameter), "
            "1.00x fewer than the generic median (4)") in table(trials, 4)[2][1]
    assert not any(line.startswith("the fewest") for line in table(trials)[2])


def test_bench_samplers_plans_each_instance_with_its_own_seed(monkeypatch):
    """Both methods of instance k get planner seed S + k, as in `bench mechanisms` (with one
    seed for every instance the generic sampler drew the same first values on each), and
    run j of it S + k + 1000 j."""
    from pdsketch_mech.bench import samplers
    from pdsketch_mech.bench.trials import Trial
    jobs = []

    def run_job(job, folder):
        jobs.append(job)
        return Trial(job.task, job.method, job.index, job.instance, job.seed, "solved", 1.0)
    monkeypatch.setattr(samplers, "run_job", run_job)
    trials = samplers.run_samplers("com", "domains/mechanisms/com.pddl", 3, "dev", 5, 10.0, progress=False, runs=2)
    assert sorted((job.index, job.method, job.seed) for job in jobs) == sorted(
        (k, method, 5 + k + 1000 * j) for k in range(3) for j in range(2) for method in samplers.METHODS)
    assert len({job.instance for job in jobs}) == 6          # each run keeps its own files
    assert {t.instance for t in trials} == {"com-dev-5", "com-dev-6", "com-dev-7"}
    assert len({t.run for t in trials}) == 6


def test_a_push_is_ranked_by_its_distance():
    from pdsketch_mech.learning.sampler_data import row_kind, row_value
    from pdsketch_mech.samplers.learned.encoding import encode_proposal
    value = np.full((2, 16), np.nan)
    value[0, :15] = np.r_[np.zeros(14), 0.12]   # a push trajectory, 12 cm
    value[1, :14] = 0.0                          # a grasp motion (no push distance)
    ep = {"kind": np.array(["trajectory", "trajectory"]), "value": value}
    assert row_kind(ep, 0) == "push" and row_kind(ep, 1) == "trajectory"
    assert row_value(ep, 0, "push").tolist() == [0.12]
    assert encode_proposal(None, 0.2).tolist() == [0.2]


def test_the_comparison_goes_into_the_learning_report_once(tmp_path):
    from pdsketch_mech.bench.samplers import REPORT_HEADING, SamplerTrial, add_to_report
    report = tmp_path / "hook-use.samplers.md"
    report.write_text("# Learned samplers of mechanism `hook-use`\n\n| parameter | AUC |\n|---|---|\n")
    trials = [SamplerTrial("a", False, "macro", "solved", 10, {"grasp": 10, "contact": 40}, {"grasp": 6, "contact": 9}),
              SamplerTrial("a", False, "macro+sampler", "solved", 5, {"grasp": 4, "contact": 12}, {"grasp": 2, "contact": 1})]
    png = add_to_report(trials, str(report), "hook-use", "python -m pdsketch_mech.bench samplers hook-use --report",
                        "abc1234")
    assert png == str(tmp_path / "hook-use.samplers-fig8.png") and os.path.getsize(png) > 0
    text = report.read_text()
    assert "Made by `python -m pdsketch_mech.bench samplers hook-use --report` at commit abc1234:" in text
    assert text.startswith("# Learned samplers of mechanism `hook-use`") and "| parameter | AUC |" in text
    assert "| all | macro+sampler | 1/1 | 5.0 | 16.0 | 3.0 |" in text and "hook-use.samplers-fig8.png" in text
    trials[1] = replace(trials[1], status="unsolved", reason="timed out")
    add_to_report(trials, str(report), "hook-use", "again")
    text = report.read_text()
    assert text.count(REPORT_HEADING) == 1 and "| all | macro+sampler | 0/1 |" in text and "| parameter | AUC |" in text


def test_bench_samplers_report_needs_a_learned_sampler(tmp_path, capsys):
    from pdsketch_mech.bench.__main__ import main
    fragment = tmp_path / "edge.pddl"
    text = open(os.path.join("domains", "mechanisms", "edge.pddl"), encoding="utf-8").read()
    fragment.write_text(text.replace('\n    :sampler "edge.samplers.safetensors"', "")
                        .replace('"../basis.pddl"', '"' + os.path.abspath("domains/basis.pddl") + '"'))
    assert main(["samplers", "edge", "--fragment", str(fragment), "--task", "edge", "--report"]) == 2
    assert "names no learned sampler for edge" in capsys.readouterr().err


def test_bench_samplers_report_names_the_seed_load_and_commit_it_was_measured_at(tmp_path, monkeypatch):
    from pdsketch_mech.bench import samplers
    from pdsketch_mech.bench.__main__ import main
    text = open(os.path.join("domains", "mechanisms", "com.pddl"), encoding="utf-8").read()
    fragment = tmp_path / "com.pddl"
    fragment.write_text(text.replace('"../basis.pddl"', '"' + os.path.abspath("domains/basis.pddl") + '"'))
    for suffix in (".safetensors", ".json"):
        shutil.copy(os.path.join("domains", "mechanisms", "com.samplers" + suffix), tmp_path)
    (tmp_path / "com.samplers.md").write_text("# Learned samplers of mechanism `com`\n")
    trials = [samplers.SamplerTrial("a", False, method, "solved", 1.0, {"grasp": 2}, {"grasp": 1})
              for method in ("macro", "macro+sampler")]
    monkeypatch.setattr(samplers, "run_samplers", lambda *args, **kwargs: trials)
    monkeypatch.setattr("pdsketch_mech.bench.trials.checkout_commit", lambda: "abc1234")
    assert main(["samplers", "com", "--fragment", str(fragment), "--seed", "5", "--workers", "2", "--report"]) == 0
    assert ("Made by `python -m pdsketch_mech.bench samplers com --instances 10 --runs 1 --timeout 120 --seed 5 "
            "--workers 2 --report` at commit abc1234:") in (tmp_path / "com.samplers.md").read_text()


def test_the_used_logit_learns_only_from_successful_episodes():
    from pdsketch_mech.learning.sampler_training import TwoHeadLoss
    episodes = synthetic_episodes(4)
    episodes[0]["episode_success"], episodes[0]["label"] = np.array([False]), np.zeros_like(episodes[0]["label"])
    data = param_data(episodes, parent_specs(episodes)["?g"])
    loss = TwoHeadLoss(data, np.arange(len(data)))
    failed = data.episode == 0
    # a failed episode's values say which contexts fail, not which value to try first
    assert not loss.scored[torch.from_numpy(failed)].any()
    assert loss.scored[torch.from_numpy(~failed & (data.verified > 0.5))].all()


def test_planning_with_learned_samplers_does_not_import_torch():
    """torch costs seconds to import: planning scores with the numpy forward pass."""
    import subprocess
    import sys
    code = ("import sys, glob\n"
            "from pdsketch_mech.lang.loader import load_domain\n"
            "from pdsketch_mech.api.planner import learned_samplers\n"
            "loaded = load_domain(['domains/basis.pddl', *sorted(glob.glob('domains/mechanisms/*.pddl'))])\n"
            "learned = learned_samplers(loaded, use_learned=True, use_mechanisms=True)\n"
            "assert len(learned) == sum(m.sampler is not None for m in loaded.domain.mechanisms) >= 6, sorted(learned)\n"
            "print('torch' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_scoring_time_leaves_out_embedding_a_new_shape(monkeypatch, tmp_path):
    """`score_ms` times a batch (encoding proposals, the forward pass); embedding a shape the
    plan scores for the first time is timed apart (`shape_ms`), once per shape."""
    monkeypatch.setenv("PDSKETCH_CACHE", str(tmp_path))   # no embedding kept from before
    import time
    from pdsketch_mech.envs.generate import sample
    from pdsketch_mech.envs.tasks import TASKS
    from pdsketch_mech.lang.parser import parse_text
    from pdsketch_mech.planner.execute import settle_start
    from pdsketch_mech.samplers.grasp import propose_grasps
    from pdsketch_mech.samplers.learned.forward import NumpyClassifier
    from pdsketch_mech.samplers.learned.ranked import load_learned
    from pdsketch_mech.world.build import build_world
    loaded = load_domain([os.path.join(ROOT, "domains", "mechanisms", "com.pddl")])
    mechanism = next(m for m in loaded.domain.mechanisms if m.name == "com")
    learned = load_learned([mechanism])["com"]
    embed = NumpyClassifier.shape_vector
    monkeypatch.setattr(NumpyClassifier, "shape_vector", lambda self, cloud: time.sleep(0.2) or embed(self, cloud))
    problem = parse_text(sample(TASKS["com"], "dev", 1).problem_text(), file="<com>")
    with build_world(problem, visual=False) as world:
        settle_start(world)
        request = SampleRequest("s", (), (), StepContext("grasp", (), "com", ("flat", "table", "pedestal")))
        grasps = list(itertools.islice(propose_grasps(world, "flat", np.random.default_rng(0), 200), 8))
        assert grasps
        for _ in range(2):
            learned.score(world, request, "?g", grasps)
    assert len(learned.shape_seconds) == len(learned.objects(world, request))   # once per shape
    assert all(t >= 0.2 for t in learned.shape_seconds)
    assert len(learned.score_seconds) == 2 and max(learned.score_seconds) < 0.2


def test_the_learning_report_flags_an_auc_measured_on_few_rows():
    from pdsketch_mech.learning.sampler_report import FEW_ROWS, report_markdown
    from pdsketch_mech.learning.sampler_training import ParamReport
    reports = [ParamReport("?g", "grasp", 100, 10, validation_rows=4, validation_positives=1, auc=1.0),
               ParamReport("?p", "placement", 900, 90, validation_rows=FEW_ROWS, validation_positives=9, auc=0.8)]
    text = report_markdown("com", reports, {"totals": {}}, {"task": "com", "seconds_training": 1.0,
                                                            "seconds_selfplay": 1.0, "command": "c"}, "x.png")
    assert "| 1.000 (only 4 rows) |" in text and "| 0.800 |" in text


def test_learn_train_refuses_classifiers_it_could_not_validate(com_fragment, tmp_path, monkeypatch, capsys):
    """Self-play with one success in 30 leaves the held-out episodes one class: the classifiers
    cannot be validated, so no checkpoint is written and the fragment keeps its text."""
    from pdsketch_mech.commands import learn_train
    from pdsketch_mech.learning.sampler_training import ParamReport
    from pdsketch_mech.lang.parser import parse_file

    mechanism = parse_file(com_fragment).mechanisms[0]
    before = open(com_fragment, encoding="utf-8").read()
    monkeypatch.setattr(learn_train, "read_episodes", lambda data, count=None: [object()] * 30)
    monkeypatch.setattr(learn_train, "parent_specs", lambda episodes: {"?g": ()})
    monkeypatch.setattr(learn_train, "train_mechanism", lambda episodes, config, progress: (
        object(), [ParamReport("?g", "grasp", rows=40, positives=1)]))   # auc None: one class held out
    checkpoint = str(tmp_path / "com.samplers.safetensors")
    with pytest.raises(learn_train.Unvalidated) as refused:
        learn_train.train_and_save("com", mechanism, com_fragment, str(tmp_path), checkpoint,
                                   learn_train.default_config(1, 0), {}, {"command": "x"}, quiet=True)
    assert refused.value.variables == ["?g"] and refused.value.episodes == 30
    assert not os.path.exists(checkpoint) and open(com_fragment, encoding="utf-8").read() == before
    assert not refused.value.all_used   # one success in 30: the advice is to play more


def test_learn_train_says_when_every_held_out_proposal_was_used(com_fragment, tmp_path, monkeypatch):
    """A trick whose first values always succeed leaves nothing rejected to learn from: the
    refusal says so, rather than asking for more episodes."""
    from pdsketch_mech.commands import learn_train
    from pdsketch_mech.learning.sampler_training import ParamReport
    from pdsketch_mech.lang.parser import parse_file

    mechanism = parse_file(com_fragment).mechanisms[0]
    monkeypatch.setattr(learn_train, "read_episodes", lambda data, count=None: [object()] * 30)
    monkeypatch.setattr(learn_train, "parent_specs", lambda episodes: {"?g": ()})
    monkeypatch.setattr(learn_train, "train_mechanism", lambda episodes, config, progress: (
        object(), [ParamReport("?g", "grasp", rows=30, positives=30, validation_rows=6, validation_positives=6)]))
    with pytest.raises(learn_train.Unvalidated) as refused:
        learn_train.train_and_save("com", mechanism, com_fragment, str(tmp_path), str(tmp_path / "c.safetensors"),
                                   learn_train.default_config(1, 0), {}, {"command": "x"}, quiet=True)
    assert refused.value.all_used
