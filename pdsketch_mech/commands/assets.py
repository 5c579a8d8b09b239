"""`python -m pdsketch_mech.assets [--out assets] [--check]`: the procedural asset generator.

Writes `<out>/<category>/<variant>/{model.urdf, visual.obj, collision_<i>.obj}` for every
category of `world/shapes.py` and `<out>/manifest.json`. The output is deterministic, so the
generated folder is committed and `--check` tells whether it is current: it regenerates into
a temporary folder, compares bytes, and exits 1 listing the differing files (0 if identical).
Scenes name assets `"<category>/<variant>"` (`"<category>"` is variant 0); see
`world/asset_index.py`.
"""
from __future__ import annotations

import json
import os
import shutil
import sys
import tempfile
from typing import Any, Dict, List, Optional, Sequence

from ..world.asset_index import ASSETS_DIR, MANIFEST
from ..world.shapes import CATEGORIES, all_models
from ..world.urdf import write_model
from .common import ArgumentParser

CONVENTIONS = {
    "units": "metres, kilograms",
    "names": "'<category>/<variant>'; a bare '<category>' means variant 0",
    "movable_frame": "link frame at the centre of mass (identity inertial origin); x the long axis, "
                     "z up in the natural resting pose; rest on a support at z = top - aabb.min[2]",
    "fixed_frame": "mass 0 (static); table: top surface centre at the origin, top surface z = 0, "
                   "floor at z = -0.75; slope and tunnel: footprint centred at the origin, bottom z = 0, "
                   "the slope rises towards +x, the tunnel runs along x",
    "collision": "one <collision> element per convex part (collision_<i>.obj)",
}


def generate(out: str) -> Dict[str, Any]:
    """Write every category/variant and the manifest into `out`; returns the manifest."""
    os.makedirs(out, exist_ok=True)
    for name in CATEGORIES:  # remove stale files of a previous generation (only our folders)
        shutil.rmtree(os.path.join(out, name), ignore_errors=True)
    categories: Dict[str, Any] = {
        name: {"fixed": cat.fixed, "density": cat.density, "rgba": list(cat.rgba), "variants": []}
        for name, cat in CATEGORIES.items()}
    for model in all_models():
        categories[model.category.name]["variants"].append(write_model(model, out))
    manifest = {"generator": "python -m pdsketch_mech.assets", "conventions": CONVENTIONS,
                "categories": categories}
    with open(os.path.join(out, MANIFEST), "w", encoding="utf-8", newline="\n") as f:
        json.dump(manifest, f, indent=1, sort_keys=False)
        f.write("\n")
    return manifest


def _files(root: str) -> List[str]:
    """Relative paths of the generator's files under `root` (manifest + category folders)."""
    found = [MANIFEST] if os.path.isfile(os.path.join(root, MANIFEST)) else []
    for name in CATEGORIES:
        for folder, _, files in os.walk(os.path.join(root, name)):
            found += [os.path.relpath(os.path.join(folder, f), root).replace(os.sep, "/") for f in files]
    return sorted(found)


def compare(generated: str, committed: str) -> List[str]:
    """Lines `differs|missing|extra: <path>` where `committed` is not `generated`."""
    new, old = set(_files(generated)), set(_files(committed))
    problems = [f"missing: {f}" for f in sorted(new - old)] + [f"extra: {f}" for f in sorted(old - new)]
    for rel in sorted(new & old):
        with open(os.path.join(generated, rel), "rb") as a, open(os.path.join(committed, rel), "rb") as b:
            if a.read() != b.read():
                problems.append(f"differs: {rel}")
    return problems


def check(committed: str) -> List[str]:
    """Regenerate into a temporary folder and compare with `committed`."""
    with tempfile.TemporaryDirectory(prefix="pdsketch_assets_") as tmp:
        generate(tmp)
        return compare(tmp, committed)


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = ArgumentParser(prog="python -m pdsketch_mech.assets", description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=None,
                        help="assets folder (default: assets/ of the repository root, whatever the working directory)")
    parser.add_argument("--check", action="store_true",
                        help="compare a fresh generation with the folder; exit 1 if they differ")
    args = parser.parse_args(argv)
    out = ASSETS_DIR if args.out is None else os.path.abspath(args.out)
    if os.path.exists(out) and not os.path.isdir(out):
        parser.error(f"--out {args.out}: is a file, not a folder")
    if args.check:
        problems = check(out)
        for line in problems:
            print(line)
        status = "out of date" if problems else "up to date"
        print(f"assets in {out}: {status} ({len(problems)} differing files)", file=sys.stderr)
        return 1 if problems else 0
    manifest = generate(out)
    n = sum(len(c["variants"]) for c in manifest["categories"].values())
    print(f"wrote {len(manifest['categories'])} categories, {n} variants to {out}", file=sys.stderr)
    return 0
