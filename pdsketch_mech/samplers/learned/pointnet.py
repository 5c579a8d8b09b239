"""A PointNet++-style shape encoder (Qi et al. 2017) in plain torch.

Set abstraction: farthest-point sampling picks centres, a ball query groups up to k
neighbours within a radius of each (padded with the nearest one when fewer fall inside),
a shared MLP embeds each neighbour's offset from its centre (and its features), and a max
over the group pools them. Two set abstractions and a global one map a cloud to a vector.
The compiled torch_cluster / pytorch3d kernels are not installable here; for clouds of a few
hundred points these loops cost milliseconds.
"""
from __future__ import annotations

from typing import Sequence, Tuple

import torch
from torch import nn

from .specs import EncoderConfig


def farthest_points(xyz: torch.Tensor, count: int) -> torch.Tensor:
    """Indices (B, count) of farthest-point samples of clouds (B, N, 3), starting at point 0
    (deterministic: the same cloud gives the same centres)."""
    b, n, _ = xyz.shape
    chosen = torch.zeros(b, count, dtype=torch.long, device=xyz.device)
    distance = torch.full((b, n), float("inf"), device=xyz.device)
    farthest = torch.zeros(b, dtype=torch.long, device=xyz.device)
    rows = torch.arange(b, device=xyz.device)
    for i in range(count):
        chosen[:, i] = farthest
        centre = xyz[rows, farthest].unsqueeze(1)
        distance = torch.minimum(distance, ((xyz - centre) ** 2).sum(-1))
        farthest = distance.argmax(-1)
    return chosen


def ball_query(xyz: torch.Tensor, centres: torch.Tensor, radius: float, k: int) -> torch.Tensor:
    """Indices (B, M, k) of up to k points within `radius` of each centre, nearest first;
    when fewer fall inside, the nearest one fills the rest."""
    d2 = torch.cdist(centres, xyz) ** 2                       # (B, M, N)
    k = min(k, xyz.shape[1])
    near_d, near_i = d2.topk(k, dim=-1, largest=False)        # nearest first
    outside = near_d > radius * radius
    return torch.where(outside, near_i[..., :1].expand_as(near_i), near_i)


def gather(points: torch.Tensor, index: torch.Tensor) -> torch.Tensor:
    """points (B, N, C) at index (B, ...) -> (B, ..., C)."""
    b = points.shape[0]
    flat = index.reshape(b, -1)
    out = torch.gather(points, 1, flat.unsqueeze(-1).expand(-1, -1, points.shape[-1]))
    return out.reshape(*index.shape, points.shape[-1])


def shared_mlp(widths: Sequence[int]) -> nn.Sequential:
    layers = []
    for a, b in zip(widths[:-1], widths[1:]):
        # LayerNorm, not BatchNorm: a batch holds a few shapes, and a plan scores one at a time
        layers += [nn.Linear(a, b), nn.LayerNorm(b), nn.ReLU()]
    return nn.Sequential(*layers)


class SetAbstraction(nn.Module):
    def __init__(self, centres: int, radius: float, k: int, in_features: int, widths: Sequence[int]):
        super().__init__()
        self.centres, self.radius, self.k = centres, radius, k
        self.mlp = shared_mlp([in_features + 3, *widths])

    def forward(self, xyz: torch.Tensor, features: torch.Tensor = None) -> Tuple[torch.Tensor, torch.Tensor]:
        index = farthest_points(xyz, min(self.centres, xyz.shape[1]))
        centres = gather(xyz, index)                              # (B, M, 3)
        group = ball_query(xyz, centres, self.radius, self.k)     # (B, M, k)
        local = gather(xyz, group) - centres.unsqueeze(2)         # offsets (B, M, k, 3)
        if features is not None:
            local = torch.cat([local, gather(features, group)], dim=-1)
        return centres, self.mlp(local).max(dim=2).values         # (B, M, C)


class PointNetEncoder(nn.Module):
    """Clouds (B, N, 3) in the unit sphere -> shape vectors (B, config.out)."""

    def __init__(self, config: EncoderConfig = EncoderConfig()):
        super().__init__()
        self.config = config
        c = config
        self.sa1 = SetAbstraction(c.centres[0], c.radii[0], c.neighbours, 0, c.widths1)
        self.sa2 = SetAbstraction(c.centres[1], c.radii[1], c.neighbours, c.widths1[-1], c.widths2)
        self.glob = shared_mlp([c.widths2[-1] + 3, c.out])

    def forward(self, xyz: torch.Tensor) -> torch.Tensor:
        xyz1, f1 = self.sa1(xyz)
        xyz2, f2 = self.sa2(xyz1, f1)
        return self.glob(torch.cat([xyz2, f2], dim=-1)).max(dim=1).values
