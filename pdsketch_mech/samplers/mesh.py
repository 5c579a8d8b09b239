"""A body's solid as plain arrays: the few mesh operations the samplers use, without trimesh.

Every plan is a new process, and importing trimesh (with scipy and networkx) was most of a
plan's start-up. The solid (geometry.py: the union of a URDF's convex parts) and its convex
hull are derived with trimesh once per asset and scale, then kept in the disk cache
(util/disk_cache.py) as arrays: vertices, faces and facets (groups of adjacent coplanar
faces). A `Mesh` gives what samplers read of them (normals, areas, triangles, bounds) and
casts rays itself (`first_hits`, `all_hits`), so a plan on cached assets imports neither.
"""
from __future__ import annotations

import os
import xml.etree.ElementTree as ElementTree
from functools import cached_property, lru_cache
from importlib import metadata
from typing import Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from ..util.disk_cache import content_key, load_arrays, store_arrays

FORMAT = "solid/1"     # change when what is stored changes: older entries are then not read
RAY_EPSILON = 1e-9     # a hit this close to a triangle's edge (barycentric) still counts
RAY_BLOCK = 200_000    # ray-triangle pairs tested at once (memory: ~10 arrays of this many)


class Mesh:
    """A triangle mesh: `vertices` (n, 3), `faces` (m, 3) indices, `facets` (groups of
    adjacent coplanar faces, as trimesh finds them; faces in no group are their own). Shared
    between callers: never modified (`transformed` and `submesh` make new ones)."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, facets: Sequence[np.ndarray] = (),
                 hull: Optional["Mesh"] = None):
        self.vertices = np.asarray(vertices, dtype=np.float64)
        self.faces = np.asarray(faces, dtype=np.int64)
        self.facets = tuple(np.asarray(f, dtype=np.int64) for f in facets)
        self._hull = hull

    @property
    def convex_hull(self) -> "Mesh":
        if self._hull is None:
            raise ValueError("this mesh was built without its convex hull")
        return self._hull

    @cached_property
    def triangles(self) -> np.ndarray:
        return self.vertices[self.faces]

    @cached_property
    def _cross(self) -> np.ndarray:
        t = self.triangles
        return np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])

    @cached_property
    def face_normals(self) -> np.ndarray:
        return self._cross / np.maximum(np.linalg.norm(self._cross, axis=1), 1e-300)[:, None]

    @cached_property
    def area_faces(self) -> np.ndarray:
        return 0.5 * np.linalg.norm(self._cross, axis=1)

    @cached_property
    def facets_area(self) -> np.ndarray:
        return np.array([self.area_faces[f].sum() for f in self.facets])

    @cached_property
    def triangles_center(self) -> np.ndarray:
        return self.triangles.mean(axis=1)

    @cached_property
    def bounds(self) -> np.ndarray:
        return np.array([self.vertices.min(axis=0), self.vertices.max(axis=0)])

    def transformed(self, matrix: np.ndarray) -> "Mesh":
        """This mesh (and its hull) moved by a 4x4 rigid transform."""
        hull = self._hull.transformed(matrix) if self._hull is not None else None
        return Mesh(self.vertices @ matrix[:3, :3].T + matrix[:3, 3], self.faces, self.facets, hull)

    def submesh(self, faces: np.ndarray) -> "Mesh":
        """The faces `faces` (indices) alone, with only the vertices they use."""
        kept = self.faces[np.asarray(faces, dtype=np.int64)]
        used, inverse = np.unique(kept, return_inverse=True)
        return Mesh(self.vertices[used], inverse.reshape(-1, 3))

    def _distances(self, origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
        """Distance along each ray (in units of its direction) to each triangle, inf where
        it misses: (rays, faces). Moller-Trumbore, a block of rays at a time."""
        t = self.triangles
        e1, e2 = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]                       # (m, 3)
        out = np.empty((len(origins), len(t)))
        block = max(1, RAY_BLOCK // max(len(t), 1))
        for start in range(0, len(origins), block):
            o, d = origins[start:start + block], directions[start:start + block]
            p = np.cross(d[:, None, :], e2[None])                           # (r, m, 3)
            det = np.einsum("rmk,mk->rm", p, e1)
            parallel = np.abs(det) < 1e-15
            inv = 1.0 / np.where(parallel, 1.0, det)
            s = o[:, None, :] - t[None, :, 0]
            u = np.einsum("rmk,rmk->rm", s, p) * inv
            q = np.cross(s, e1[None])
            v = np.einsum("rk,rmk->rm", d, q) * inv
            distance = np.einsum("mk,rmk->rm", e2, q) * inv
            hit = (~parallel & (u >= -RAY_EPSILON) & (v >= -RAY_EPSILON) & (u + v <= 1.0 + RAY_EPSILON)
                   & (distance > 0.0))
            out[start:start + block] = np.where(hit, distance, np.inf)
        return out

    def first_hits(self, origins: np.ndarray, directions: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """For the rays that hit the mesh: (their indices, the faces they first hit, where)."""
        origins, directions = np.atleast_2d(origins).astype(float), np.atleast_2d(directions).astype(float)
        distance = self._distances(origins, directions)
        rays = np.nonzero(np.isfinite(distance).any(axis=1))[0]
        faces = np.argmin(distance[rays], axis=1)
        return rays, faces, origins[rays] + directions[rays] * distance[rays, faces][:, None]

    def all_hits(self, origin: np.ndarray, direction: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """Every point where one ray crosses the mesh, nearest first, and the faces there."""
        origin, direction = np.asarray(origin, dtype=float), np.asarray(direction, dtype=float)
        distance = self._distances(origin[None], direction[None])[0]
        faces = np.nonzero(np.isfinite(distance))[0]
        faces = faces[np.argsort(distance[faces], kind="stable")]
        return origin + direction * distance[faces][:, None], faces


def cached_solid(urdf: str, scale: float, derive) -> Mesh:
    """The solid of `urdf` at `scale` from the disk cache, else `derive(urdf, scale)` (a
    trimesh solid, with `.facets` and `.convex_hull`) turned into arrays and kept there."""
    name = os.path.join("solids", content_key(_derived_from(urdf, scale)) + ".npz")
    entry = load_arrays(name)
    if entry is not None:
        try:
            return _from_arrays(entry)
        except (KeyError, ValueError, IndexError):
            pass   # a damaged or foreign entry: derive it again
    solid = derive(urdf, scale)
    hull = solid.convex_hull
    arrays = {**_to_arrays("", solid), **_to_arrays("hull_", hull)}
    store_arrays(name, **arrays)
    return _from_arrays(arrays)


def _to_arrays(prefix: str, mesh) -> Dict[str, np.ndarray]:
    facets = [np.asarray(f, dtype=np.int64) for f in mesh.facets]
    return {f"{prefix}vertices": np.asarray(mesh.vertices, dtype=np.float64),
            f"{prefix}faces": np.asarray(mesh.faces, dtype=np.int64),
            f"{prefix}facet_faces": np.concatenate(facets) if facets else np.zeros(0, dtype=np.int64),
            f"{prefix}facet_sizes": np.array([len(f) for f in facets], dtype=np.int64)}


def _from_arrays(arrays: Dict[str, np.ndarray]) -> Mesh:
    def mesh(prefix: str, hull: Optional[Mesh] = None) -> Mesh:
        vertices, faces = arrays[f"{prefix}vertices"], arrays[f"{prefix}faces"]
        if vertices.ndim != 2 or vertices.shape[1] != 3 or faces.ndim != 2 or faces.shape[1] != 3:
            raise ValueError("not a mesh")
        if len(faces) and (faces.min() < 0 or faces.max() >= len(vertices)):
            raise ValueError("faces outside the vertices")
        sizes = arrays[f"{prefix}facet_sizes"]
        facets = np.split(arrays[f"{prefix}facet_faces"], np.cumsum(sizes)[:-1]) if len(sizes) else []
        return Mesh(vertices, faces, facets, hull)
    return mesh("", mesh("hull_"))


def _derived_from(urdf: str, scale: float) -> List[Union[str, bytes]]:
    """Everything a solid depends on: the URDF and its mesh files, the scale, and the
    libraries that read and unite the meshes."""
    parts: List[Union[str, bytes]] = [FORMAT, repr(float(scale)), read_bytes(urdf)]
    for mesh in ElementTree.parse(urdf).getroot().iter("mesh"):
        parts.append(read_bytes(os.path.join(os.path.dirname(urdf), mesh.get("filename", ""))))
    return parts + list(mesh_libraries())


@lru_cache(maxsize=1)
def mesh_libraries() -> Tuple[str, ...]:
    """The versions of the libraries that read, unite and sample meshes."""
    out = []
    for library in ("trimesh", "manifold3d", "numpy"):
        try:
            out.append(f"{library} {metadata.version(library)}")
        except metadata.PackageNotFoundError:
            out.append(f"{library} -")
    return tuple(out)


def read_bytes(path: str) -> bytes:
    with open(path, "rb") as handle:
        return handle.read()
