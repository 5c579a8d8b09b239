"""Self-play data -> one training set per mechanism parameter (the classifiers' inputs).

A row is one proposal a generic sampler verified for a parameter in an episode -- a value
(`verified` 1) or a proposal that failed verification (0) -- with its context: the
mechanism's objects (asset cloud, size at the episode's scale, pose when drawn) and the
values the parameter's parents took (the rankable parameters drawn before it in the
mechanism's order; a parent not drawn is zeros with its presence flag 0). The numbers are
the proposal's (what a learned sampler scores before verifying); the label is 1 if the
episode's successful plan used its value. Rejected proposals can outnumber values a
hundredfold (placements on a crowded table): beyond REJECTED_CAP per value a seeded subset
is kept, each kept row weighted by how many it stands for.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..samplers.learned.encoding import RANKABLE, VALUE_LAYOUT
from ..samplers.learned.specs import ParamSpec, width
from ..samplers.learned.shapes import size_features, unit_cloud
from ..world.asset_index import resolve_asset
from .selfplay_store import StoreError, done_episodes, read_episode

REJECTED_CAP = 4        # rejected proposals kept per verified value (at least REJECTED_MIN in all)
REJECTED_MIN = 2000

# Columns holding a quaternion (x, y, z, w), per kind: stored with either sign in older data.
QUATERNIONS = {"grasp": (3, 7), "contact": (3, 7), "placement": (3, 7), "trajectory": (10, 14)}


@dataclass
class ParamData:
    """One parameter's rows as numpy arrays (Batch fields, see samplers/learned/model.py)."""

    spec: ParamSpec
    value: np.ndarray            # (n, width)
    parents: List[np.ndarray]    # per parent (n, width of its kind)
    present: np.ndarray          # (n, P)
    urdfs: List[str]             # distinct object shapes
    cloud_index: np.ndarray      # (n, M) into urdfs
    sizes: np.ndarray            # (n, M, 3)
    poses: np.ndarray            # (n, M, 7)
    label: np.ndarray            # (n,)
    episode: np.ndarray          # (n,): which episode (validation splits by episode)
    verified: np.ndarray         # (n,): 1 a value, 0 a proposal that failed verification
    success: np.ndarray          # (n,): 1 if the row's episode succeeded
    weight: np.ndarray           # (n,): how many rows each stands for (rejected ones subsampled)
    first_step: np.ndarray       # (n,): 1 if drawn for the mechanism's first step

    def __len__(self) -> int:
        return len(self.label)

    def clouds(self) -> np.ndarray:
        return np.stack([unit_cloud(u) for u in self.urdfs])


def row_kind(ep: Dict[str, np.ndarray], row: int) -> str:
    """The kind a classifier sees: a trajectory with a push distance is a "push"."""
    kind = str(ep["kind"][row])
    if kind == "trajectory" and not np.isnan(ep["value"][row, len(VALUE_LAYOUT["trajectory"]) - 1]):
        return "push"
    return kind


def row_value(ep: Dict[str, np.ndarray], row: int, kind: str, column: str = "value") -> np.ndarray:
    """A row's numbers in `kind`'s layout, from its value or (column "proposal") its proposal."""
    numbers = ep[column if column in ep else "value"][row]
    if kind == "push":
        return numbers[len(VALUE_LAYOUT["trajectory"]) - 1:len(VALUE_LAYOUT["trajectory"])]
    return numbers[:width(kind)]


def canonical(numbers: np.ndarray, kind: str) -> np.ndarray:
    """NaN -> 0 and quaternions with w >= 0 (q and -q are one rotation)."""
    out = np.nan_to_num(np.asarray(numbers, dtype=np.float64))
    if kind not in QUATERNIONS:
        return out
    start, stop = QUATERNIONS[kind]
    flip = out[..., stop - 1] < 0
    out[flip, start:stop] *= -1
    return out


def read_episodes(folder: str, count: Optional[int] = None) -> List[Dict[str, np.ndarray]]:
    """Every episode with a grounding and samples, in episode order (only those of
    0..count-1 if `count` is given)."""
    episodes = [read_episode(folder, e) for e in done_episodes(folder) if count is None or e < count]
    if not episodes:
        raise StoreError(f"{folder}: no self-play episodes")
    return [e for e in episodes if e["episode_objects"].shape[1] and len(e["label"])]


def parent_specs(episodes: Sequence[Dict[str, np.ndarray]]) -> Dict[str, ParamSpec]:
    """The rankable parameters and, for each, its rankable parents in the mechanism's order."""
    kinds: Dict[str, str] = {}
    order: Dict[str, int] = {}
    parents: Dict[str, set] = {}
    objects = 0
    for ep in episodes:
        objects = ep["episode_objects"].shape[1]
        for row in range(len(ep["label"])):
            kind, var = row_kind(ep, row), str(ep["param"][row])
            if kind not in RANKABLE or not var.startswith("?"):
                continue
            kinds[var], order[var] = kind, int(ep["param_index"][row])
            for p in ep["parents"][row]:
                if p >= 0 and row_kind(ep, p) in RANKABLE and str(ep["param"][p]).startswith("?"):
                    parents.setdefault(var, set()).add(str(ep["param"][p]))
                    kinds[str(ep["param"][p])] = row_kind(ep, p)
                    order[str(ep["param"][p])] = int(ep["param_index"][p])
    return {var: ParamSpec(var, kind, tuple((p, kinds[p]) for p in sorted(parents.get(var, ()), key=order.get)),
                           objects, axes=True, scaled=True)
            for var, kind in sorted(kinds.items(), key=lambda kv: order[kv[0]])}


def param_data(episodes: Sequence[Dict[str, np.ndarray]], spec: ParamSpec, seed: int = 0,
               subsample: bool = True) -> ParamData:
    """The rows of `spec`'s parameter across the episodes, in the order they were drawn
    (rejected proposals subsampled beyond REJECTED_CAP per value, by `seed`, unless not
    `subsample`: evaluation scores every proposal)."""
    urdf_ids: Dict[str, int] = {}
    cols: Dict[str, list] = {k: [] for k in ("value", "present", "cloud", "sizes", "poses", "label", "episode",
                                             "verified", "success", "first_step")}
    parent_rows: List[list] = [[] for _ in spec.parents]
    for ep in episodes:
        assets = [str(a) for a in ep["episode_assets"][0]]
        scales = [float(s) for s in ep["episode_scales"][0]]
        urdfs = [resolve_asset(a) for a in assets]
        ids = [urdf_ids.setdefault(u, len(urdf_ids)) for u in urdfs]
        sizes = [size_features(u, s) for u, s in zip(urdfs, scales)]
        first_step = ep["step"] == 0 if "step" in ep else np.zeros(len(ep["param"]), dtype=bool)
        for row in np.flatnonzero(ep["param"] == spec.variable):
            if row_kind(ep, row) != spec.kind:
                continue
            by_var = {str(ep["param"][p]): p for p in ep["parents"][row] if p >= 0}  # later ones win
            for k, (var, kind) in enumerate(spec.parents):
                p = by_var.get(var)
                parent_rows[k].append(canonical(row_value(ep, p, kind), kind) if p is not None
                                      else np.zeros(width(kind)))
            cols["present"].append([float(var in by_var) for var, _ in spec.parents])
            cols["value"].append(canonical(row_value(ep, row, spec.kind, "proposal"), spec.kind))
            cols["cloud"].append(ids)
            cols["sizes"].append(sizes)
            cols["poses"].append(canonical(ep["poses"][row], "placement"))  # poses in a placement's layout
            cols["label"].append(int(ep["label"][row]))
            cols["episode"].append(int(ep["episode_id"][0]))
            cols["verified"].append(int(ep["verified"][row]) if "verified" in ep else 1)
            cols["success"].append(float(ep["episode_success"][0]))
            cols["first_step"].append(float(first_step[row]))
    verified = np.asarray(cols["verified"], dtype=np.float32)
    keep, weight = _subsample_rejected(verified, seed) if subsample else (np.arange(len(verified)),
                                                                          np.ones(len(verified), np.float32))
    cols = {k: [v[i] for i in keep] for k, v in cols.items()}
    parent_rows = [[r[i] for i in keep] for r in parent_rows]
    n = len(cols["label"])
    f32 = lambda rows, shape: np.asarray(rows, dtype=np.float32).reshape(shape)  # noqa: E731
    m = spec.objects
    return ParamData(spec, f32(cols["value"], (n, width(spec.kind))),
                     [f32(r, (n, width(k))) for r, (_, k) in zip(parent_rows, spec.parents)],
                     f32(cols["present"], (n, len(spec.parents))), list(urdf_ids),
                     np.asarray(cols["cloud"], dtype=np.int64).reshape(n, m), f32(cols["sizes"], (n, m, 3)),
                     f32(cols["poses"], (n, m, 7)), np.asarray(cols["label"], dtype=np.float32),
                     np.asarray(cols["episode"], dtype=np.int64), verified[keep],
                     np.asarray(cols["success"], dtype=np.float32), weight[keep],
                     np.asarray(cols["first_step"], dtype=np.float32))


def context_groups(data: ParamData) -> np.ndarray:
    """(n,) a group id per row: rows drawn in one context (the objects' poses and the parents'
    values alike) share one. Whether a value is "used" means something only against the
    other values of its context: across contexts a classifier learns to tell a context that
    led to success (the box already pulled close) from one that did not, which no sampler is
    ever asked to do."""
    parts = [data.poses.reshape(len(data), -1)] + [p * data.present[:, k:k + 1] for k, p in enumerate(data.parents)]
    if not len(data):
        return np.zeros(0, dtype=np.int64)
    keys = np.round(np.concatenate(parts, axis=1), 5)
    return np.unique(keys, axis=0, return_inverse=True)[1].reshape(-1)


def _subsample_rejected(verified: np.ndarray, seed: int) -> Tuple[np.ndarray, np.ndarray]:
    """(rows kept, each row's weight): every value, and at most max(REJECTED_CAP per value,
    REJECTED_MIN) rejected proposals, each weighted by how many it stands for."""
    rejected = np.flatnonzero(verified < 0.5)
    cap = max(REJECTED_CAP * int((verified > 0.5).sum()), REJECTED_MIN)
    weight = np.ones(len(verified), dtype=np.float32)
    if len(rejected) <= cap:
        return np.arange(len(verified)), weight
    kept = np.sort(np.random.default_rng(seed).choice(rejected, size=cap, replace=False))
    weight[kept] = len(rejected) / cap
    return np.sort(np.concatenate([np.flatnonzero(verified > 0.5), kept])), weight


def split_episodes(episodes: Sequence[int], fraction: float, seed: int) -> Tuple[set, set]:
    """(train, validation) episode ids: `fraction` of them held out, chosen by `seed`."""
    ids = sorted(set(int(e) for e in episodes))
    rng = np.random.default_rng(seed)
    held = set(rng.choice(ids, size=int(round(fraction * len(ids))), replace=False).tolist()) if len(ids) > 1 else set()
    return set(ids) - held, held
