"""Classifiers f(value | context) in [0, 1], one per continuous parameter of a mechanism.

A parameter's context is what its sampler is told: the mechanism's objects (their shapes,
sizes and current poses) and the values its parent parameters took. Each part has its own
encoder -- PointNet++ for shapes (pointnet.py), MLPs for poses, contacts and values -- and
the embeddings are concatenated in the mechanism's order (objects, parents, the value)
before the head. The head has one hidden layer rather than the paper's single linear layer:
whether a grasp is good depends on the value *and* the context together (which end of which
tool), and a linear layer over separately encoded parts cannot express that.

Positions of the value (a contact's point, a placement's position) are also given in each
object's frame, so that "behind the target" means the same wherever the target stands.

A classifier trained on proposals (ParamSpec.outputs 2) has two logits: whether the proposal
verifies (IK, collisions, motion) and whether its value, once verified, ends up in a
successful plan. Trained with class-balanced weights, each logit is off by the log of its
weight; `prior_shift` holds those logs, so `log_score` is the calibrated
log P(verifies) + log P(used | verified), the log-probability that a raw proposal is the one
a plan uses. Checkpoints of values only (outputs 1) have the second logit alone.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence

import torch
from torch import nn

from .pointnet import PointNetEncoder
from .specs import (HIDDEN, MIN_HALF_EXTENT, SHAPE_PROJECTION, EncoderConfig, ParamSpec, framed_columns,
                    object_features, scaled_columns, width)


@dataclass
class Batch:
    """Inputs for B rows (all float32 tensors unless said)."""

    value: torch.Tensor                  # (B, width(kind))
    parents: List[torch.Tensor]          # per parent: (B, width(parent kind)); zeros when absent
    present: torch.Tensor                # (B, P): 1 where the parent was drawn
    clouds: torch.Tensor                 # (U, N, 3): the distinct shapes
    cloud_index: torch.Tensor            # (B, M) long: each object's row in `clouds`
    sizes: torch.Tensor                  # (B, M, 3)
    poses: torch.Tensor                  # (B, M, 7)
    extra: Dict[str, torch.Tensor] = field(default_factory=dict)

    def rows(self, index: torch.Tensor) -> "Batch":
        return Batch(self.value[index], [p[index] for p in self.parents], self.present[index], self.clouds,
                     self.cloud_index[index], self.sizes[index], self.poses[index])


def quat_rotate_inverse(q: torch.Tensor, v: torch.Tensor) -> torch.Tensor:
    """Rotate vectors v (..., 3) by the inverse of unit quaternions q (..., 4) (x, y, z, w)."""
    u, w = -q[..., :3], q[..., 3:]
    t = 2.0 * torch.cross(u, v, dim=-1)
    return v + w * t + torch.cross(u, t, dim=-1)


class Standardise(nn.Module):
    """x -> (x - mean) / std with statistics fixed from the training data (saved with the weights)."""

    def __init__(self, size: int):
        super().__init__()
        self.register_buffer("mean", torch.zeros(size))
        self.register_buffer("std", torch.ones(size))

    def fit(self, x: torch.Tensor) -> None:
        flat = x.reshape(-1, x.shape[-1])
        self.mean.copy_(flat.mean(0))
        self.std.copy_(flat.std(0).clamp_min(1e-3) if len(flat) > 1 else torch.ones_like(self.std))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return (x - self.mean) / self.std


def mlp(inputs: int, hidden: int = HIDDEN) -> nn.Sequential:
    return nn.Sequential(nn.Linear(inputs, hidden), nn.ReLU(), nn.Linear(hidden, hidden), nn.ReLU())


class ParamClassifier(nn.Module):
    """Logits for (value, context) rows of one parameter: column 0, the value ends up in a
    successful plan (given it verifies); column 1 (outputs 2), the proposal verifies."""

    def __init__(self, spec: ParamSpec, encoder: EncoderConfig):
        super().__init__()
        self.spec = spec
        self.shape = PointNetEncoder(encoder)
        self.shape_projection = nn.Linear(encoder.out, SHAPE_PROJECTION)
        object_inputs = object_features(spec)
        self.object_norm = nn.ModuleList(Standardise(object_inputs) for _ in range(spec.objects))
        self.objects = nn.ModuleList(mlp(SHAPE_PROJECTION + object_inputs) for _ in range(spec.objects))
        self.parent_norm = nn.ModuleList(Standardise(width(k)) for _, k in spec.parents)
        self.parents = nn.ModuleList(mlp(width(k) + 1) for _, k in spec.parents)
        self.value_norm = Standardise(width(spec.kind))
        self.value = mlp(width(spec.kind))
        parts = spec.objects + len(spec.parents) + 1
        self.head = nn.Sequential(nn.Linear(parts * HIDDEN, 2 * HIDDEN), nn.ReLU(),
                                  nn.Linear(2 * HIDDEN, spec.outputs))
        if spec.outputs > 1:
            self.register_buffer("prior_shift", torch.zeros(spec.outputs))

    def object_inputs(self, batch: Batch) -> torch.Tensor:
        """(B, M, `object_features`): each object's pose and size, the value's positions (and,
        with `axes`, directions) in that object's frame, and (with `scaled`) its positions in
        that object's half-extents."""
        poses = batch.poses
        parts = [poses, batch.sizes]
        framed = {}
        for start, stop, is_point in framed_columns(self.spec):
            columns = batch.value[:, start:stop].unsqueeze(1).expand(-1, poses.shape[1], -1)
            framed[start, stop] = quat_rotate_inverse(poses[..., 3:], columns - poses[..., :3] if is_point else columns)
            parts.append(framed[start, stop])
        for start, stop, is_framed in scaled_columns(self.spec):
            columns = framed[start, stop] if is_framed else batch.value[:, None, start:stop]
            parts.append(columns / batch.sizes.clamp_min(MIN_HALF_EXTENT))
        return torch.cat(parts, dim=-1)

    def fit_statistics(self, batch: Batch) -> None:
        """Fix the input standardisation from the training rows."""
        inputs = self.object_inputs(batch)
        for m, norm in enumerate(self.object_norm):
            norm.fit(inputs[:, m])
        for p, norm in enumerate(self.parent_norm):
            rows = batch.present[:, p] > 0
            if rows.any():
                norm.fit(batch.parents[p][rows])
        self.value_norm.fit(batch.value)

    def shape_vectors(self, clouds: torch.Tensor) -> torch.Tensor:
        """(U, S) embeddings of distinct clouds (fixed once trained: planning caches them)."""
        return self.shape_projection(self.shape(clouds))

    def log_score(self, batch: Batch, shapes: Optional[torch.Tensor] = None) -> torch.Tensor:
        """(B,) what ranking sorts by: the calibrated log-probability that a proposal verifies
        and is used (outputs 2), or the used-logit of a value (outputs 1)."""
        logits = self(batch, shapes)
        if self.spec.outputs == 1:
            return logits[:, 0]
        return torch.nn.functional.logsigmoid(logits - self.prior_shift).sum(-1)

    def forward(self, batch: Batch, shapes: Optional[torch.Tensor] = None) -> torch.Tensor:
        """Logits (B, outputs); `shapes`: precomputed `shape_vectors(batch.clouds)`."""
        shapes = (self.shape_vectors(batch.clouds) if shapes is None else shapes)[batch.cloud_index]  # (B, M, S)
        inputs = self.object_inputs(batch)
        parts = [net(torch.cat([shapes[:, m], norm(inputs[:, m])], dim=-1))
                 for m, (net, norm) in enumerate(zip(self.objects, self.object_norm))]
        for p, (net, norm) in enumerate(zip(self.parents, self.parent_norm)):
            present = batch.present[:, p:p + 1]
            parts.append(net(torch.cat([norm(batch.parents[p]) * present, present], dim=-1)))
        parts.append(self.value(self.value_norm(batch.value)))
        return self.head(torch.cat(parts, dim=-1))


class MechanismClassifiers(nn.Module):
    """The classifiers of one mechanism, by variable."""

    def __init__(self, specs: Sequence[ParamSpec], encoder: EncoderConfig):
        super().__init__()
        self.specs = {s.variable: s for s in specs}
        self.encoder = encoder
        # ModuleDict keys cannot hold "?": "?g1" is stored as "g1"
        self.by_variable = nn.ModuleDict({s.variable.lstrip("?"): ParamClassifier(s, encoder) for s in specs})

    def classifier(self, variable: str) -> ParamClassifier:
        return self.by_variable[variable.lstrip("?")]

    def __contains__(self, variable: object) -> bool:
        return isinstance(variable, str) and variable.lstrip("?") in self.by_variable
