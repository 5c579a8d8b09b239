"""Point clouds of object shapes, the input of the shape encoder.

A cloud is drawn once per asset (URDF) from its solid with trimesh, seeded by the file's
name, centred on its bounding box and scaled into the unit sphere (the encoder sees form, not
size); the size is given separately (`size_features`): the scaled half-extents.

Both are kept on disk (disk_cache.py) under a hash of the asset's files and the libraries
that draw them. Drawing needs the union of the asset's convex parts at scale 1, ~30-60 ms
for a plate or a table, and each plan is a new process: on Center-of-Mass, whose plans take
a second, it was most of what the learned samplers added to a plan's time.
"""
from __future__ import annotations

import os
import zlib
from functools import lru_cache
from typing import List, Tuple, Union
from xml.etree import ElementTree

import numpy as np

from ...util.disk_cache import content_key, load_arrays, store_arrays
from ..geometry import sample_surface, solid_mesh
from ..mesh import mesh_libraries, read_bytes

CLOUD_POINTS = 256
FORMAT = "unit-cloud/1"   # change when the drawing below changes: older entries are then not read


def unit_cloud(urdf: str, points: int = CLOUD_POINTS) -> np.ndarray:
    """(points, 3) float32 surface points of the asset, centred and inside the unit sphere."""
    return _shape(urdf, points)[0]


def size_features(urdf: str, scale: float) -> Tuple[float, float, float]:
    """The asset's half-extents at `scale` (metres)."""
    return tuple(float(v) * scale for v in _shape(urdf, CLOUD_POINTS)[1])


@lru_cache(maxsize=128)
def _shape(urdf: str, points: int) -> Tuple[np.ndarray, np.ndarray]:
    """(the unit cloud, the half-extents at scale 1), from the disk cache when there."""
    name = os.path.join("clouds", cloud_key(urdf, points) + ".npz")
    entry = load_arrays(name)
    if entry is not None and set(entry) == {"cloud", "half_extents"}:
        cloud, half = entry["cloud"], entry["half_extents"]
        if cloud.shape == (points, 3) and cloud.dtype == np.float32 and half.shape == (3,):
            return cloud, half
    cloud, half = _draw(urdf, points)
    store_arrays(name, cloud=cloud, half_extents=half)
    return cloud, half


@lru_cache(maxsize=128)
def cloud_key(urdf: str, points: int = CLOUD_POINTS) -> str:
    """A name for the asset's cloud that changes whenever the cloud would (what is derived
    from the cloud, e.g. a classifier's embedding of it, is cached under it too)."""
    return content_key(_derived_from(urdf, points))


def _draw(urdf: str, points: int) -> Tuple[np.ndarray, np.ndarray]:
    mesh = solid_mesh(urdf, 1.0)
    cloud, _ = sample_surface(mesh, points, np.random.default_rng(_seed(urdf)))
    lo, hi = mesh.bounds
    cloud = cloud - (lo + hi) / 2.0
    radius = float(np.linalg.norm(cloud, axis=1).max()) or 1.0
    return (cloud / radius).astype(np.float32), np.asarray((hi - lo) / 2.0, dtype=np.float64)


def _seed(urdf: str) -> int:
    """The asset's name as the file's last two folders and its name give it (`block/2/...`):
    the same cloud wherever the assets folder lies."""
    return zlib.crc32(os.path.relpath(urdf, os.path.dirname(os.path.dirname(os.path.dirname(urdf)))).encode())


def _derived_from(urdf: str, points: int) -> List[Union[str, bytes]]:
    """Everything a cloud depends on: the drawing, its seed, the URDF and its mesh files, and
    the libraries that read and unite the meshes."""
    parts: List[Union[str, bytes]] = [FORMAT, str(points), str(_seed(urdf)), read_bytes(urdf)]
    for mesh in ElementTree.parse(urdf).getroot().iter("mesh"):
        parts.append(read_bytes(os.path.join(os.path.dirname(urdf), mesh.get("filename", ""))))
    return parts + list(mesh_libraries())
