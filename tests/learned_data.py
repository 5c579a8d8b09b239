"""Self-play-shaped data for the learned-sampler tests: small, fast, with a rule to learn."""
from __future__ import annotations

import numpy as np

from pdsketch_mech.samplers.interface import Sampler
from pdsketch_mech.samplers.learned.specs import EncoderConfig

TINY = EncoderConfig(centres=(16, 4), radii=(0.4, 0.8), neighbours=8, widths1=(8, 16), widths2=(16, 16), out=16)


def synthetic_episodes(count: int, seed: int = 0):
    """Episodes shaped like self-play's: a block's grasp proposals (object frame), which fail
    verification when the gripper is on the block's -y side (y < -0.01) and are labelled 1
    when it is on the +x half otherwise, then a placement whose parent is the grasp."""
    rng = np.random.default_rng(seed)
    episodes = []
    for e in range(count):
        n = 12
        value = np.full((n + 1, 16), np.nan)
        value[:n, :8] = np.c_[rng.uniform(-0.03, 0.03, (n, 3)), np.tile([0, 0, 0, 1.0], (n, 1)), np.full(n, 0.05)]
        value[n, :7] = [0.5, 0.0, 0.1, 0, 0, 0, 1]
        verified = np.r_[(value[:n, 1] >= -0.01).astype(np.int8), 1]
        label = np.r_[((value[:n, 0] > 0) & (verified[:n] > 0)).astype(np.int8), 1]
        parents = np.full((n + 1, 12), -1)
        parents[n, 0] = int(np.flatnonzero(label[:n])[0]) if label[:n].any() else 0
        episodes.append({
            "episode_id": np.array([e]), "episode_objects": np.array([["block", "table"]]),
            "episode_assets": np.array([["block/0", "table"]]), "episode_scales": np.array([[1.0, 1.0]]),
            "kind": np.array(["grasp"] * n + ["placement"]), "param": np.array(["?g"] * n + ["?p"]),
            "param_index": np.array([3] * n + [4]), "value": value, "parents": parents, "label": label,
            "proposal": value, "verified": verified, "episode_success": np.array([bool(label[:n].any())]),
            "poses": np.tile(np.array([[0.5, 0.0, 0.03, 0, 0, 0, 1], [0.6, 0, 0, 0, 0, 0, 1]]), (n + 1, 1, 1)),
        })
    return episodes


class Numbers(Sampler):
    """A stand-in generic sampler: proposes 0..n-1; verifies the even ones."""

    def __init__(self, n):
        self.n = n

    def propose(self, world, request, rng, budget):
        return iter(range(self.n))

    def verify(self, world, request, candidate, rng):
        return candidate if candidate % 2 == 0 else None


class AllVerify(Numbers):
    """... that verifies them all."""

    def verify(self, world, request, candidate, rng):
        return float(candidate)   # a new object per proposal, as real values are
