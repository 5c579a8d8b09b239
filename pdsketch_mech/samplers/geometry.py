"""Shapes of the world's bodies for samplers (surfaces, normals, rays), and pose arithmetic.

A body's mesh is the union of its URDF collision parts (each convex) as one solid, in the
link frame, derived with trimesh once per URDF and scale and then read from the disk cache
as a `mesh.Mesh` (a plan on cached assets imports no trimesh); `world_mesh` places it at
the body's current pose.
"""
from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ElementTree
from functools import lru_cache
from typing import TYPE_CHECKING, Optional, Tuple

import numpy as np
import pybullet as p

if TYPE_CHECKING:
    import trimesh

    from ..world.world import World

from ..world.values import Pose
from .mesh import Mesh, cached_solid


def pose_matrix(pose: Pose) -> np.ndarray:
    """4x4 homogeneous transform of a pose."""
    matrix = np.eye(4)
    matrix[:3, :3] = np.array(p.getMatrixFromQuaternion(pose[1])).reshape(3, 3)
    matrix[:3, 3] = pose[0]
    return matrix


def matrix_pose(matrix: np.ndarray) -> Pose:
    """The pose of a 4x4 homogeneous transform (its rotation part orthonormal)."""
    return tuple(float(v) for v in matrix[:3, 3]), matrix_quaternion(matrix[:3, :3])


def matrix_quaternion(r: np.ndarray) -> Tuple[float, float, float, float]:
    """The unit quaternion (x, y, z, w), w >= 0, of a rotation matrix, by the largest of its
    four candidate components (numerically safe at every angle). Plain floats: a sampler
    turns tens of thousands of matrices into poses, and scipy's Rotation is slow per call."""
    (m00, m01, m02), (m10, m11, m12), (m20, m21, m22) = (tuple(map(float, row)) for row in r)
    trace = m00 + m11 + m22
    if trace > 0:
        s = 2.0 * (trace + 1.0) ** 0.5
        q = ((m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s)
    elif m00 > m11 and m00 > m22:
        s = 2.0 * (1.0 + m00 - m11 - m22) ** 0.5
        q = (0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s)
    elif m11 > m22:
        s = 2.0 * (1.0 + m11 - m00 - m22) ** 0.5
        q = ((m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s)
    else:
        s = 2.0 * (1.0 + m22 - m00 - m11) ** 0.5
        q = ((m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s)
    norm = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) ** 0.5 * (1.0 if q[3] >= 0 else -1.0)
    return q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm


def rotvec_matrices(rotvecs: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of rotation vectors (..., 3): axis times angle
    (Rodrigues' formula)."""
    rotvecs = np.asarray(rotvecs, dtype=float)
    if rotvecs.shape == (3,):  # one: plain floats, a third of the time of the batched arithmetic
        return _rotvec_matrix(*map(float, rotvecs))
    angle = np.linalg.norm(rotvecs, axis=-1)
    axis = rotvecs / np.where(angle > 1e-12, angle, 1.0)[..., None]   # ~0 for no turn: then R = I
    x, y, z = axis[..., 0], axis[..., 1], axis[..., 2]
    zero = np.zeros_like(x)
    cross = np.stack([np.stack([zero, -z, y], -1), np.stack([z, zero, -x], -1), np.stack([-y, x, zero], -1)], -2)
    sin, cos = np.sin(angle)[..., None, None], np.cos(angle)[..., None, None]
    return np.eye(3) + sin * cross + (1.0 - cos) * (cross @ cross)


def _rotvec_matrix(x: float, y: float, z: float) -> np.ndarray:
    angle = (x * x + y * y + z * z) ** 0.5
    if angle < 1e-12:
        return np.eye(3)
    x, y, z = x / angle, y / angle, z / angle
    sin, cos = math.sin(angle), math.cos(angle)
    c = 1.0 - cos
    return np.array([[cos + c * x * x, c * x * y - sin * z, c * x * z + sin * y],
                     [c * x * y + sin * z, cos + c * y * y, c * y * z - sin * x],
                     [c * x * z - sin * y, c * y * z + sin * x, cos + c * z * z]])


def rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation (3x3 matrix) taking unit vector `a` onto unit vector `b`;
    for opposite vectors, half a turn about an axis perpendicular to `a`."""
    axis = np.cross(a, b)
    sin, cos = np.linalg.norm(axis), float(np.dot(a, b))
    if sin < 1e-9:
        if cos > 0:
            return np.eye(3)
        axis = np.cross(a, np.eye(3)[int(np.argmin(np.abs(a)))])  # the axis least parallel to a
        return rotvec_matrices(np.pi * axis / np.linalg.norm(axis))
    return rotvec_matrices(axis / sin * np.arctan2(sin, cos))


@lru_cache(maxsize=256)
def urdf_mesh(urdf: str, scale: float = 1.0) -> "trimesh.Trimesh":
    """The collision parts of a single-link URDF, concatenated, in the link frame (trimesh)."""
    import trimesh
    root = ElementTree.parse(urdf).getroot()
    parts = []
    for collision in root.iter("collision"):
        mesh_el = collision.find("geometry/mesh")
        if mesh_el is None:
            continue
        mesh = trimesh.load(os.path.join(os.path.dirname(urdf), mesh_el.get("filename")), force="mesh")
        origin = collision.find("origin")
        if origin is not None:
            xyz = [float(v) for v in origin.get("xyz", "0 0 0").split()]
            rpy = [float(v) for v in origin.get("rpy", "0 0 0").split()]
            transform = np.eye(4)
            transform[:3, :3] = np.array(p.getMatrixFromQuaternion(p.getQuaternionFromEuler(rpy))).reshape(3, 3)
            transform[:3, 3] = xyz
            mesh.apply_transform(transform)
        parts.append(mesh)
    if not parts:
        raise ValueError(f"{urdf}: no mesh collision elements")
    mesh = trimesh.util.concatenate(parts)
    mesh.apply_scale(scale)
    return mesh


@lru_cache(maxsize=256)
def solid_mesh(urdf: str, scale: float = 1.0) -> Mesh:
    """The union of a URDF's convex collision parts as one watertight solid, with its convex
    hull (shared; never modified). The concatenated parts of `urdf_mesh` keep the faces where
    parts overlap or touch (a table's leg tops under its top), which would stop rays, offer
    hidden upward faces, and yield points inside the object."""
    return cached_solid(urdf, scale, _trimesh_solid)


def _trimesh_solid(urdf: str, scale: float) -> "trimesh.Trimesh":
    import trimesh
    mesh = urdf_mesh(urdf, scale)
    parts = [part.convex_hull for part in mesh.split(only_watertight=False)]  # parts are convex
    if len(parts) == 1:
        return parts[0]
    try:
        solid = trimesh.boolean.union(parts, engine="manifold")
        if solid.is_watertight and len(solid.faces):
            return solid
    except Exception:  # noqa: BLE001 - no boolean engine: fall back to the raw parts
        pass
    return mesh


def body_parts(world: "World", name: str) -> "trimesh.Trimesh":
    """The body's convex collision parts, concatenated, in its link frame (shared)."""
    body = world.bodies[name]
    return urdf_mesh(body.urdf, body.scale)


def body_mesh(world: "World", name: str) -> Mesh:
    """The body's solid (parts unioned) in its link frame (shared; never modified)."""
    body = world.bodies[name]
    return solid_mesh(body.urdf, body.scale)


def world_mesh(world: "World", name: str) -> Mesh:
    """The body's solid, and its hull, at the body's current pose."""
    return body_mesh(world, name).transformed(pose_matrix(world.pose(name)))


def sample_surface(mesh: Mesh, count: int, rng: np.random.Generator,
                   weights: Optional[np.ndarray] = None) -> Tuple[np.ndarray, np.ndarray]:
    """`count` points on the surface with their outward face normals; faces are drawn with
    probabilities `weights` (default: proportional to area)."""
    if weights is None:
        weights = mesh.area_faces / mesh.area_faces.sum()
    faces = rng.choice(len(mesh.faces), size=count, p=weights)
    u, v = rng.random(count), rng.random(count)
    flip = u + v > 1
    u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
    triangles = mesh.triangles[faces]
    points = triangles[:, 0] + u[:, None] * (triangles[:, 1] - triangles[:, 0]) + v[:, None] * (triangles[:, 2] - triangles[:, 0])
    return points, mesh.face_normals[faces]
