"""Where the shipped data lives: the assets, the basis domain, the mechanisms (fragments,
checkpoints, demonstrations) and the example problems.

In a checkout (or an editable install) they are the repository's top-level folders
`assets/`, `domains/` and `problems/`; in an installed wheel the same folders are package
data under `pdsketch_mech/data/` (setup.py maps them there at build time). Either way
`data_path("domains", "basis.pddl")` names the file. Users' own files are always given by path.
"""
from __future__ import annotations

import os
from functools import lru_cache
from typing import Optional

SHIPPED = ("assets", "domains", "problems")
_PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def checkout_root() -> Optional[str]:
    """The repository the package is imported from, or None for an installed wheel."""
    root = os.path.dirname(_PACKAGE_DIR)
    markers = (os.path.join(root, "domains", "basis.pddl"), os.path.join(root, "setup.cfg"))
    return root if all(os.path.isfile(m) for m in markers) else None


REPO_ROOT = checkout_root() or ""   # benchmarks and tests that read the checkout's own folders


@lru_cache(maxsize=1)
def data_root() -> str:
    """The folder holding `assets/`, `domains/` and `problems/`."""
    root = checkout_root()
    if root is not None:
        return root
    from importlib import resources   # here: a checkout's commands start without it

    # A wheel is installed as plain files, which PyBullet and trimesh need: no zip imports.
    return str(resources.files("pdsketch_mech") / "data")


def data_path(*parts: str) -> str:
    """A shipped file or folder, e.g. `data_path("domains", "mechanisms")`."""
    return os.path.join(data_root(), *parts)
