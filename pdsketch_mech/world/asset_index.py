"""Find generated assets by name: `"<category>/<variant>"`, or `"<category>"` for variant 0.

Reads `assets/manifest.json` (written by `python -m pdsketch_mech.assets`) only, so loading a
scene needs neither trimesh nor the generator.
"""
from __future__ import annotations

import json
import os
from functools import lru_cache
from typing import Any, Dict, List, Optional, Tuple

from ..util.data import data_path

ASSETS_DIR = data_path("assets")
MANIFEST = "manifest.json"


def assets_root() -> str:
    """Where scenes' assets are looked up: `$PDSKETCH_ASSETS`, else the shipped `assets/` (util/data.py)."""
    return os.environ.get("PDSKETCH_ASSETS") or ASSETS_DIR


@lru_cache(maxsize=8)
def _load(path: str, mtime: float) -> Dict[str, Any]:
    # Keyed on the modification time, so a regenerated manifest is re-read.
    with open(path, encoding="utf-8") as f:
        return json.load(f)


def load_manifest(root: Optional[str] = None) -> Dict[str, Any]:
    """The manifest of the assets folder `root` (default: the repository's `assets/`)."""
    root = root or assets_root()
    path = os.path.join(root, MANIFEST)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"no {MANIFEST} in {root}; "
                                "generate the assets with `python -m pdsketch_mech.assets`")
    return _load(path, os.path.getmtime(path))


def parse_asset_name(name: str) -> Tuple[str, int]:
    """Split `"category/variant"` (variant defaults to 0)."""
    category, _, variant = name.strip().partition("/")
    if not variant:
        return category, 0
    if not variant.isdigit():
        raise ValueError(f"bad asset name {name!r}: expected '<category>' or '<category>/<variant number>'")
    return category, int(variant)


def asset_info(name: str, root: Optional[str] = None) -> Dict[str, Any]:
    """The manifest entry of an asset (path, mass, friction, parts, extents, aabb, ...),
    plus `category`, `variant` and `fixed`."""
    manifest = load_manifest(root)
    categories = manifest["categories"]
    category, variant = parse_asset_name(name)
    if category not in categories:
        raise ValueError(f"unknown asset {name!r}: known categories are {', '.join(sorted(categories))}")
    variants = categories[category]["variants"]
    if variant >= len(variants):
        raise ValueError(f"unknown asset {name!r}: category {category!r} has variants "
                         f"0..{len(variants) - 1}")
    return dict(variants[variant], category=category, variant=variant, fixed=categories[category]["fixed"])


@lru_cache(maxsize=256)
def collision_vertices(name: str, root: Optional[str] = None) -> Tuple[Tuple[float, float, float], ...]:
    """Every vertex of an asset's convex collision parts (`collision_<i>.obj` beside its
    model), in its link frame, unscaled: where it touches what it rests on, at any tilt."""
    info = asset_info(name, root)
    folder = os.path.dirname(os.path.join(os.path.abspath(root or assets_root()), info["path"]))
    vertices: List[Tuple[float, float, float]] = []
    for i in range(int(info.get("parts", 1))):
        with open(os.path.join(folder, f"collision_{i}.obj"), encoding="utf-8") as f:
            vertices += [tuple(float(v) for v in line.split()[1:4]) for line in f if line.startswith("v ")]
    return tuple(vertices)


def asset_names(root: Optional[str] = None) -> List[str]:
    """Every asset of the manifest, as `category/variant`."""
    categories = load_manifest(root)["categories"]
    return [f"{c}/{i}" for c, entry in categories.items() for i in range(len(entry["variants"]))]


def resolve_asset(name: str, root: Optional[str] = None) -> str:
    """The absolute path of the asset's `model.urdf`; ValueError for an unknown name."""
    base = os.path.abspath(root or assets_root())
    path = os.path.join(base, asset_info(name, root)["path"])
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{path} is listed in the manifest but missing; "
                                "regenerate with `python -m pdsketch_mech.assets`")
    return path
