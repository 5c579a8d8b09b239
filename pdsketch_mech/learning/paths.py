"""Where mechanisms live and how commands name them (light: the command line imports it first)."""
from __future__ import annotations

import os
import re

from ..world.asset_index import REPO_ROOT
BASIS = os.path.join(REPO_ROOT, "domains", "basis.pddl")
MECHANISMS_DIR = os.path.join(REPO_ROOT, "domains", "mechanisms")
NAME = re.compile(r"^[a-z][a-z0-9_-]*$")   # a mechanism's name, as commands accept it


def repo_path(path: str) -> str:
    """A path as a command to re-run names it: relative to the repository when inside it."""
    full = os.path.abspath(path)
    inside = os.path.commonpath([full, REPO_ROOT]) == REPO_ROOT
    return os.path.relpath(full, REPO_ROOT) if inside else full
