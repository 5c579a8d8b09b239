"""Work kept on disk between processes (disk_cache.py): shapes' point clouds and the parser's
tables are read back exactly as drawn, a damaged or stale entry is drawn again, and a cache
that cannot be written costs only the work."""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT
from pdsketch_mech.util import disk_cache
from pdsketch_mech.samplers import geometry
from pdsketch_mech.samplers.learned import shapes
from pdsketch_mech.samplers.learned.forward import groupings
from pdsketch_mech.samplers.learned.specs import EncoderConfig
from pdsketch_mech.world.asset_index import resolve_asset


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """An empty cache folder of the test's own, and no cloud remembered in this process."""
    monkeypatch.setenv("PDSKETCH_CACHE", str(tmp_path / "cache"))
    shapes._shape.cache_clear()
    yield tmp_path / "cache"
    shapes._shape.cache_clear()


def entries(folder):
    return sorted(p for p in (folder / "clouds").iterdir()) if (folder / "clouds").is_dir() else []


def stretched(obj_line):
    """An OBJ line with its vertex (if it is one) twice as far along x."""
    if not obj_line.startswith("v "):
        return obj_line
    _, x, *rest = obj_line.split()
    return " ".join(["v", str(2 * float(x))] + rest)


def never_draw(*args, **kwargs):
    raise AssertionError("the cloud was drawn again instead of read from the cache")


def test_a_cloud_is_read_back_exactly_without_building_the_solid(cache, monkeypatch):
    urdf = resolve_asset("plate/2")
    cloud, size = shapes.unit_cloud(urdf), shapes.size_features(urdf, 1.083)
    assert len(entries(cache)) == 1
    shapes._shape.cache_clear()                       # as a new process would start
    monkeypatch.setattr(shapes, "solid_mesh", never_draw)
    np.testing.assert_array_equal(shapes.unit_cloud(urdf), cloud)
    assert shapes.size_features(urdf, 1.083) == size
    assert cloud.shape == (shapes.CLOUD_POINTS, 3) and cloud.dtype == np.float32
    assert np.linalg.norm(cloud, axis=1).max() == pytest.approx(1.0, abs=1e-6)


def test_a_damaged_entry_is_drawn_again_and_replaced(cache):
    urdf = resolve_asset("block/1")
    cloud = shapes.unit_cloud(urdf)
    (entry,) = entries(cache)
    entry.write_bytes(b"not an npz")
    shapes._shape.cache_clear()
    np.testing.assert_array_equal(shapes.unit_cloud(urdf), cloud)
    shapes._shape.cache_clear()
    with np.load(entry) as stored:                     # rewritten whole
        np.testing.assert_array_equal(stored["cloud"], cloud)


def test_an_asset_whose_mesh_changed_gets_a_new_cloud(cache, tmp_path):
    source = os.path.dirname(resolve_asset("block/1"))
    copy = tmp_path / "assets" / "block" / "1"
    shutil.copytree(source, copy)
    urdf = str(copy / os.path.basename(resolve_asset("block/1")))
    before = shapes.size_features(urdf, 1.0)
    for mesh in copy.glob("*.obj"):                   # the same block, twice as long in x
        mesh.write_text("".join(stretched(line) + "\n" for line in mesh.read_text().splitlines()))
    for remembered in (shapes._shape, shapes.cloud_key, geometry.solid_mesh, geometry.urdf_mesh):   # as a new process
        remembered.cache_clear()
    assert shapes.size_features(urdf, 1.0)[0] == pytest.approx(2 * before[0])
    assert len(entries(cache)) == 2


def test_a_cache_that_cannot_be_written_only_costs_the_work(tmp_path, monkeypatch):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    monkeypatch.setenv("PDSKETCH_CACHE", str(blocker / "cache"))   # a folder under a file
    shapes._shape.cache_clear()
    try:
        cloud = shapes.unit_cloud(resolve_asset("block/1"))
    finally:
        shapes._shape.cache_clear()
    assert cloud.shape == (shapes.CLOUD_POINTS, 3)
    assert disk_cache.store("x/y", lambda handle: handle.write(b"1")) is None


def test_entry_names_tell_part_lists_apart():
    assert disk_cache.content_key(["ab", "c"]) != disk_cache.content_key(["a", "bc"])
    assert disk_cache.content_key(["ab", b"c"]) == disk_cache.content_key([b"ab", "c"])


def test_a_shape_read_by_several_classifiers_is_grouped_once(monkeypatch):
    from pdsketch_mech.samplers.learned import forward
    encoder = EncoderConfig(centres=(16, 4), radii=(0.3, 0.6), neighbours=8, widths1=(8,), widths2=(8,), out=8)
    cloud = np.random.default_rng(0).normal(size=(64, 3)).astype(np.float32)
    first = groupings(cloud, encoder)
    monkeypatch.setattr(forward, "farthest_points", never_draw)
    assert groupings(cloud.copy(), encoder) is first
    with pytest.raises(AssertionError):
        groupings(cloud + 1.0, encoder)              # another shape is grouped anew


def test_a_classifiers_embedding_of_a_shape_is_read_back_under_its_weights_name(cache, monkeypatch):
    from pdsketch_mech.lang.loader import load_domain
    from pdsketch_mech.samplers.learned import forward
    from pdsketch_mech.samplers.learned.ranked import load_learned
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    loaded = load_domain([os.path.join(root, "domains", "basis.pddl"), os.path.join(root, "domains", "mechanisms", "com.pddl")])
    learned = load_learned(loaded.domain.mechanisms)["com"]
    urdf = resolve_asset("plate/2")
    embedding = learned._embedding("?p", urdf)
    np.testing.assert_array_equal(embedding, learned.model.classifier("?p").shape_vector(shapes.unit_cloud(urdf)))
    monkeypatch.setattr(forward.NumpyClassifier, "shape_vector", never_draw)
    np.testing.assert_array_equal(learned._embedding("?p", urdf), embedding)
    learned.digest = "other weights"                 # another checkpoint embeds the shape anew
    with pytest.raises(AssertionError):
        learned._embedding("?p", urdf)


def test_the_parser_reads_its_cached_tables_without_importing_numpy():
    import subprocess
    import sys
    code = "import sys, pdsketch_mech.lang.parser as p; p._lark(); print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"


class _Planted:
    """A pickle that creates a file when unpickled."""

    def __init__(self, marker):
        self.marker = marker

    def __reduce__(self):
        return (open, (self.marker, "w"))


def test_the_parsers_cached_tables_are_data_a_planted_pickle_runs_nothing(tmp_path):
    import pickle

    env = {**os.environ, "PDSKETCH_CACHE": str(tmp_path / "cache")}
    code = ("from pdsketch_mech.lang.parser import parse_text\n"
            "print(parse_text('(define (domain d) (:predicates (p)))').name)")
    first = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=env, check=True)
    [entry] = list((tmp_path / "cache").iterdir())
    assert json.loads(entry.read_text())["memo"]   # the tables, as JSON
    marker = tmp_path / "ran"
    entry.write_bytes(pickle.dumps(_Planted(str(marker))))
    second = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=env, check=True)
    assert first.stdout == second.stdout == "d\n" and not marker.exists()
