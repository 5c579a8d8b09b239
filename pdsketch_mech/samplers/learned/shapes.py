"""Point clouds of object shapes, the input of the shape encoder.

A cloud is drawn once per asset (URDF) from its solid with trimesh, seeded by the file's
name, centred on its bounding box and scaled into the unit sphere (the encoder sees form, not
size); the size is given separately (`size_features`): the scaled half-extents.
"""
from __future__ import annotations

import os
import zlib
from functools import lru_cache
from typing import Tuple

import numpy as np

from ..geometry import sample_surface, solid_mesh

CLOUD_POINTS = 256


@lru_cache(maxsize=128)
def unit_cloud(urdf: str, points: int = CLOUD_POINTS) -> np.ndarray:
    """(points, 3) float32 surface points of the asset, centred and inside the unit sphere."""
    mesh = solid_mesh(urdf, 1.0)
    seed = zlib.crc32(os.path.relpath(urdf, os.path.dirname(os.path.dirname(os.path.dirname(urdf)))).encode())
    cloud, _ = sample_surface(mesh, points, np.random.default_rng(seed))
    lo, hi = mesh.bounds
    cloud = cloud - (lo + hi) / 2.0
    radius = float(np.linalg.norm(cloud, axis=1).max()) or 1.0
    return (cloud / radius).astype(np.float32)


@lru_cache(maxsize=512)
def size_features(urdf: str, scale: float) -> Tuple[float, float, float]:
    """The asset's half-extents at `scale` (metres)."""
    lo, hi = solid_mesh(urdf, 1.0).bounds
    return tuple(float(v) for v in (hi - lo) / 2.0 * scale)
