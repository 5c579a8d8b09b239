"""Where mechanisms live and how commands name them (light: the command line imports it first)."""
from __future__ import annotations

import os
import re
from typing import List, Sequence, Union

from ..lang.errors import PddlError, did_you_mean
from ..util.data import data_path, data_root

BASIS = data_path("domains", "basis.pddl")
MECHANISMS_DIR = data_path("domains", "mechanisms")
NAME = re.compile(r"^[a-z][a-z0-9_-]*$")   # a mechanism's name, as commands accept it


def repo_path(path: str) -> str:
    """A path as a command to re-run names it: relative to the repository when inside it."""
    full = os.path.abspath(path)
    root = data_root()
    inside = os.path.commonpath([full, root]) == root
    return os.path.relpath(full, root) if inside else full


def shipped_mechanisms() -> List[str]:
    """The mechanism fragments that come with the package, by name."""
    return sorted(os.path.splitext(name)[0] for name in os.listdir(MECHANISMS_DIR) if name.endswith(".pddl"))


def _resolve(name: str, folder: str, shipped: Sequence[str], what: str) -> str:
    """`name` itself when it is an existing file; else the shipped file of that name."""
    if os.path.exists(name) or os.sep in name or "." in name:
        return name   # a path: the loader says what is wrong with it
    if name in shipped:
        return os.path.join(folder, name + ".pddl")
    raise PddlError(f"{name}: no such file, nor a shipped {what}{did_you_mean(name, shipped)}; "
                    f"shipped: {', '.join(shipped)}")


def resolve_domain(name: str) -> str:
    """A domain file, `basis` for the shipped basis domain, or a shipped mechanism's name
    (its fragment :extends the basis domain)."""
    if name == "basis":
        return _resolve(name, os.path.dirname(BASIS), ["basis"], "domain")
    return _resolve(name, MECHANISMS_DIR, ["basis", *shipped_mechanisms()], "domain")


def resolve_mechanisms(names: Union[str, Sequence[str]]) -> List[str]:
    """Fragment files: paths, shipped mechanisms' names, or `all` for every shipped one
    (beside a user's own: `all my-trick.pddl`), each once."""
    names = [names] if isinstance(names, str) else list(names)
    shipped = shipped_mechanisms()
    out: List[str] = []
    for name in names:
        for path in (shipped if name == "all" else [name]):
            resolved = _resolve(path, MECHANISMS_DIR, shipped, "mechanism")
            out += [] if resolved in out else [resolved]
    return out


def shipped_problems() -> List[str]:
    """The example problems that come with the package, by name."""
    return sorted(os.path.splitext(name)[0] for name in os.listdir(data_path("problems")) if name.endswith(".pddl"))


def resolve_problem(name: str) -> str:
    """A problem file, or the name of a shipped example problem (`hook-use`)."""
    return _resolve(name, data_path("problems"), shipped_problems(), "problem")


def resolve_shipped(name: str) -> str:
    """A file as `check` takes it: a path, else a shipped domain or mechanism (`basis`,
    `edge`), else a shipped example problem."""
    try:
        return resolve_domain(name)
    except PddlError:
        return resolve_problem(name)
