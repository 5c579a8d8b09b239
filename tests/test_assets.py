"""The procedural assets: manifest, PyBullet loading, concave compounds, determinism, names."""
from __future__ import annotations

import math
import os
import re
import shutil

import numpy as np
import pybullet as p
import pytest
from scipy.spatial import Delaunay

from pdsketch_mech.commands import assets
from pdsketch_mech.world.asset_index import ASSETS_DIR, load_manifest, resolve_asset

CATEGORIES = ["block", "brick", "box", "small-block", "bowl", "plate", "document", "calculator", "caliper",
              "spoon", "fork", "soup-ladle", "dipper", "spatula", "hairbrush", "hammer", "wooden-stick",
              "l-stick", "walnut", "banana", "apple", "ball", "table", "slope", "tunnel", "ledge"]
FIXED = {"table", "slope", "tunnel", "ledge"}


@pytest.fixture(scope="module")
def generated(tmp_path_factory) -> str:
    out = str(tmp_path_factory.mktemp("assets_a"))
    assets.generate(out)
    return out


@pytest.fixture(scope="module")
def manifest() -> dict:
    return load_manifest(ASSETS_DIR)


@pytest.fixture
def client():
    cid = p.connect(p.DIRECT)
    yield cid
    p.disconnect(cid)


def _variants(manifest):
    for name, cat in manifest["categories"].items():
        for i, entry in enumerate(cat["variants"]):
            yield f"{name}/{i}", cat["fixed"], entry


def test_generator_is_deterministic(generated, tmp_path):
    assets.generate(str(tmp_path))
    assert assets.compare(generated, str(tmp_path)) == []


def test_committed_assets_are_current(generated):
    # Fails when shapes.py/urdf.py changed without `python -m pdsketch_mech.assets` being rerun.
    assert assets.compare(generated, ASSETS_DIR) == []


def test_check_cli_lists_differing_files(generated, tmp_path, capsys):
    stale = tmp_path / "assets"
    shutil.copytree(generated, stale)
    (stale / "block" / "0" / "model.urdf").write_text("<robot/>\n")
    (stale / "ball" / "1" / "stray.txt").write_text("x\n")
    assert assets.main(["--check", "--out", str(stale)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert "differs: block/0/model.urdf" in out and "extra: ball/1/stray.txt" in out


def test_manifest_lists_every_category(manifest):
    assert sorted(manifest["categories"]) == sorted(CATEGORIES)
    for name in CATEGORIES:
        cat = manifest["categories"][name]
        assert cat["fixed"] == (name in FIXED)
        assert len(cat["variants"]) >= 3, name
    for name, _, entry in _variants(manifest):
        urdf = os.path.join(ASSETS_DIR, entry["path"])
        assert os.path.isfile(urdf), name
        text = open(urdf).read()
        meshes = re.findall(r'filename="([^"]+)"', text)
        assert meshes.count("visual.obj") == 1 and len(meshes) == entry["parts"] + 1, name
        assert all(os.path.isfile(os.path.join(os.path.dirname(urdf), m)) for m in meshes), name
        lo, hi = np.array(entry["aabb"]["min"]), np.array(entry["aabb"]["max"])
        assert np.allclose(hi - lo, entry["extents"], atol=2e-6), name


def test_slope_angles(manifest):
    # rise = length sin(angle) + board thickness: ~10, 20 and 30 degrees on 30 cm boards,
    # and the test split's 25 degrees on a 28 cm one.
    heights = [v["extents"][2] for v in manifest["categories"]["slope"]["variants"]]
    angles = [math.degrees(math.asin((h - 0.01) / length)) for h, length in zip(heights, (0.3, 0.3, 0.3, 0.28))]
    assert np.allclose(angles, [10, 20, 30, 25], atol=1.0), angles


def test_sizes_are_realistic(manifest):
    def extents(name, i=0):
        return manifest["categories"][name]["variants"][i]["extents"]
    assert np.allclose(extents("block"), [0.05] * 3)
    assert np.allclose(extents("table")[:2], [1.0, 1.2])
    assert manifest["categories"]["table"]["variants"][0]["aabb"]["max"][2] == 0.0  # top at z = 0
    for name in ["block", "small-block", "box", "apple", "ball", "walnut"]:
        for i in range(3):
            assert min(extents(name, i)[:2]) < 0.075, name  # fits the 8 cm gripper some way
    for name in ["wooden-stick", "l-stick"]:
        assert extents(name)[2] <= 0.025 and 0.3 <= extents(name)[0] <= 0.45, name
    for name in ["spoon", "fork", "soup-ladle", "dipper", "spatula", "hairbrush", "hammer"]:
        assert 0.16 <= extents(name)[0] <= 0.37, name
    plate = extents("plate")
    assert 0.2 <= plate[0] <= 0.24 and plate[2] <= 0.016


def test_urdfs_load_in_pybullet(manifest, client):
    for k, (name, fixed, entry) in enumerate(_variants(manifest)):
        pos = (3.0 * (k % 9), 3.0 * (k // 9), 1.0)
        body = p.loadURDF(os.path.join(ASSETS_DIR, entry["path"]), pos, useFixedBase=fixed,
                          flags=p.URDF_USE_INERTIA_FROM_FILE, physicsClientId=client)
        shapes = p.getCollisionShapeData(body, -1, physicsClientId=client)
        assert len(shapes) == entry["parts"], name
        info = p.getDynamicsInfo(body, -1, physicsClientId=client)
        assert info[0] == pytest.approx(entry["mass"], abs=1e-6), name
        assert info[0] > 0 or fixed, name
        # The link frame is the inertial frame: no position or orientation offset.
        assert np.allclose(info[3], 0, atol=1e-9) and np.allclose(info[4], (0, 0, 0, 1), atol=1e-9), name
        base = p.getBasePositionAndOrientation(body, physicsClientId=client)
        assert np.allclose(base[0], pos, atol=1e-9) and np.allclose(base[1], (0, 0, 0, 1), atol=1e-9), name
        lo, hi = p.getAABB(body, -1, physicsClientId=client)
        # PyBullet pads AABBs by the collision margin and contact threshold (a few mm).
        assert np.allclose(np.subtract(lo, pos), entry["aabb"]["min"], atol=0.006), name
        assert np.allclose(np.subtract(hi, pos), entry["aabb"]["max"], atol=0.006), name


def _read_obj_vertices(path: str) -> np.ndarray:
    with open(path) as f:
        return np.array([[float(v) for v in line.split()[1:4]] for line in f if line.startswith("v ")])


def _box_distance(point: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    return float(np.linalg.norm(np.maximum(0.0, np.maximum(lo - point, point - hi))))


@pytest.mark.parametrize("variant", [0, 1, 2])
def test_l_stick_crook_is_open(manifest, client, variant):
    entry = manifest["categories"]["l-stick"]["variants"][variant]
    folder = os.path.dirname(os.path.join(ASSETS_DIR, entry["path"]))
    parts = [_read_obj_vertices(os.path.join(folder, f"collision_{i}.obj")) for i in range(entry["parts"])]
    assert len(parts) == 2
    radius = 0.008
    lo, hi = np.array(entry["aabb"]["min"]), np.array(entry["aabb"]["max"])
    # A point inside the overall AABB, clear of both (box-shaped) parts by radius + 5 mm.
    grid = [np.array([x, y, (lo[2] + hi[2]) / 2]) for x in np.linspace(lo[0], hi[0], 81)
            for y in np.linspace(lo[1], hi[1], 41)]
    clear = [q for q in grid if all(_box_distance(q, v.min(0), v.max(0)) > radius + 0.005 for v in parts)]
    assert clear, "no free space inside the l-stick's bounding box"
    point = min(clear, key=lambda q: max(_box_distance(q, v.min(0), v.max(0)) for v in parts))
    # The point is inside the convex hull, so a single hull collider would fill the crook.
    assert Delaunay(np.vstack(parts)).find_simplex(point) >= 0
    pos = np.array([0.5, -0.3, 0.2])
    stick = p.loadURDF(os.path.join(ASSETS_DIR, entry["path"]), pos, flags=p.URDF_USE_INERTIA_FROM_FILE,
                       physicsClientId=client)
    sphere = p.createCollisionShape(p.GEOM_SPHERE, radius=radius, physicsClientId=client)
    probe = p.createMultiBody(0, sphere, basePosition=pos + point, physicsClientId=client)
    assert p.getClosestPoints(stick, probe, 0.0, physicsClientId=client) == ()
    # Control: the same probe on the handle does collide.
    p.resetBasePositionAndOrientation(probe, pos + parts[0].mean(0), (0, 0, 0, 1), physicsClientId=client)
    assert len(p.getClosestPoints(stick, probe, 0.0, physicsClientId=client)) > 0


def test_resolve_asset_names():
    default = resolve_asset("block")
    assert default.endswith(os.path.join("block", "0", "model.urdf")) and os.path.isfile(default)
    assert resolve_asset("block/1").endswith(os.path.join("block", "1", "model.urdf"))
    assert resolve_asset(" soup-ladle/2 ", ASSETS_DIR).endswith(os.path.join("soup-ladle", "2", "model.urdf"))
    with pytest.raises(ValueError, match=r"unknown asset 'teapot'.*known categories.*block"):
        resolve_asset("teapot")
    with pytest.raises(ValueError, match="variants 0..4"):
        resolve_asset("block/7")
    with pytest.raises(ValueError, match="bad asset name"):
        resolve_asset("block/x")
