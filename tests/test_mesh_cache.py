"""A body's solid is derived with trimesh once and then read from the disk cache as arrays
(samplers/mesh.py): the arrays give what trimesh gave (normals, areas, facets, the hull, ray
hits), a damaged entry is derived again, and a plan on cached assets imports no trimesh."""
import os
import subprocess
import sys

import numpy as np
import pytest
import trimesh

from pdsketch_mech.samplers import geometry
from pdsketch_mech.samplers.mesh import Mesh, cached_solid
from pdsketch_mech.world.asset_index import resolve_asset

from conftest import ROOT


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PDSKETCH_CACHE", str(tmp_path))
    geometry.solid_mesh.cache_clear()
    yield tmp_path
    geometry.solid_mesh.cache_clear()


@pytest.mark.parametrize("asset", ["l-stick/0", "soup-ladle/3", "plate/4", "block/0"])
def test_the_cached_solid_is_trimeshs_solid_with_its_facets_and_hull(fresh_cache, asset):
    urdf = resolve_asset(asset)
    reference = geometry._trimesh_solid(urdf, 1.1)
    solid = geometry.solid_mesh(urdf, 1.1)
    assert isinstance(solid, Mesh) and os.listdir(fresh_cache / "solids")
    assert np.allclose(solid.vertices, reference.vertices) and np.array_equal(solid.faces, reference.faces)
    assert np.allclose(solid.face_normals, reference.face_normals, atol=1e-9)
    assert np.allclose(solid.area_faces, reference.area_faces) and np.allclose(solid.bounds, reference.bounds)
    assert [list(f) for f in solid.facets] == [list(f) for f in reference.facets]
    assert np.allclose(solid.facets_area, reference.facets_area)
    hull = solid.convex_hull
    assert np.allclose(hull.vertices, reference.convex_hull.vertices)
    assert [list(f) for f in hull.facets] == [list(f) for f in reference.convex_hull.facets]
    geometry.solid_mesh.cache_clear()
    again = geometry.solid_mesh(urdf, 1.1)          # from the disk this time
    assert again is not solid and np.array_equal(again.faces, solid.faces)


def test_rays_hit_where_trimeshs_rays_hit(fresh_cache):
    reference = geometry._trimesh_solid(resolve_asset("soup-ladle/0"), 1.0)
    solid = geometry.solid_mesh(resolve_asset("soup-ladle/0"), 1.0)
    rng = np.random.default_rng(3)
    origins = rng.uniform(-0.3, 0.3, (300, 3))
    aims = reference.vertices[rng.integers(len(reference.vertices), size=300)] + rng.normal(0, 0.005, (300, 3))
    directions = (aims - origins) / np.linalg.norm(aims - origins, axis=1, keepdims=True)
    tri, ray, where = reference.ray.intersects_id(origins, directions, multiple_hits=False, return_locations=True)
    rays, faces, hits = solid.first_hits(origins, directions)
    assert len(rays) > 20 and sorted(rays) == sorted(ray)
    order = np.argsort(ray)
    assert np.allclose(hits, where[order], atol=1e-9)
    points, faces = solid.all_hits(origins[rays[0]], directions[rays[0]])
    expected, _, _ = reference.ray.intersects_location([origins[rays[0]]], [directions[rays[0]]])
    assert len(points) == len(expected) and np.allclose(points[0], hits[0])
    assert np.all(np.diff(np.linalg.norm(points - origins[rays[0]], axis=1)) >= 0)   # nearest first


def test_a_damaged_cache_entry_is_derived_again(fresh_cache):
    urdf = resolve_asset("box/0")
    first = geometry.solid_mesh(urdf, 1.0)
    (entry,) = (fresh_cache / "solids").iterdir()
    entry.write_bytes(b"not an npz")
    geometry.solid_mesh.cache_clear()
    again = geometry.solid_mesh(urdf, 1.0)
    assert np.array_equal(again.faces, first.faces) and np.allclose(again.vertices, first.vertices)


def test_a_solid_without_trimesh_in_its_derivation_is_refused_a_hull_it_does_not_have():
    with pytest.raises(ValueError, match="without its convex hull"):
        Mesh(np.eye(3), np.array([[0, 1, 2]])).convex_hull


def test_a_plan_on_cached_assets_imports_neither_trimesh_nor_scipy(tmp_path):
    code = ("import sys\n"
            "from pdsketch_mech.commands.plan import main\n"
            "try:\n    main(['domains/mechanisms/com.pddl', 'problems/com.pddl', '--timeout', '60'])\n"
            "except SystemExit:\n    pass\n"
            "print('LOADED', 'trimesh' in sys.modules, 'scipy' in sys.modules)\n")
    env = {**os.environ, "PDSKETCH_CACHE": str(tmp_path)}
    runs = [subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True,
                           timeout=120) for _ in range(2)]
    assert all("solved" in run.stderr for run in runs), runs[0].stderr
    assert runs[0].stdout.split()[-3:] == ["LOADED", "True", "True"]      # derived: trimesh did it
    assert runs[1].stdout.split()[-3:] == ["LOADED", "False", "False"]    # cached: nothing imported


def test_cached_solid_keeps_what_derive_gave_when_the_cache_cannot_be_written(monkeypatch, tmp_path):
    blocked = tmp_path / "file"
    blocked.write_text("")
    monkeypatch.setenv("PDSKETCH_CACHE", str(blocked))    # a file where the folder should be
    box = trimesh.creation.box((0.1, 0.2, 0.3))
    solid = cached_solid(resolve_asset("box/0"), 1.0, lambda urdf, scale: box)
    assert np.allclose(solid.bounds, box.bounds) and len(solid.convex_hull.faces) == len(box.convex_hull.faces)
