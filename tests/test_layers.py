"""The package's layers (docs/layout.md): a module imports only its own folder and the
folders below it, so each folder can be read, tested and replaced knowing only what is under it."""
import ast
import os

import pytest

from conftest import ROOT

PACKAGE = os.path.join(ROOT, "pdsketch_mech")
# Lowest first; folders on one line are side by side and do not import each other.
LAYERS = [
    {"util"},
    {"lang"},
    {"world", "symbolic"},
    {"samplers", "operators"},
    {"envs", "planner"},
    {"learning"},
    {"api"},
    {"commands"},
    {"bench"},
]
RANK = {folder: rank for rank, folders in enumerate(LAYERS) for folder in folders}


def folder_of(module: str) -> str:
    """`pdsketch_mech.world.robot` -> `world`; a module at the package's top -> its own name."""
    return module.split(".")[1] if "." in module else ""


def module_name(path: str) -> str:
    relative = os.path.relpath(path, ROOT)[:-len(".py")].replace(os.sep, ".")
    return relative[:-len(".__init__")] if relative.endswith(".__init__") else relative


def imported_modules(path: str):
    """Every pdsketch_mech module `path` imports, anywhere in it (lazy and typing-only imports too)."""
    module = module_name(path)
    package = module if path.endswith("__init__.py") else module.rsplit(".", 1)[0]
    with open(path, encoding="utf-8") as handle:
        tree = ast.parse(handle.read())
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            yield target
            yield from (f"{target}.{alias.name}" for alias in node.names)  # `from . import world`


def is_entry_point(path: str) -> bool:
    """`python -m pdsketch_mech.NAME` and `python -m pdsketch_mech.FOLDER` only hand over to commands/."""
    return os.path.basename(path) == "__main__.py" or os.path.dirname(path) == PACKAGE


def sources():
    for folder, _, files in os.walk(PACKAGE):
        for name in files:
            if name.endswith(".py"):
                yield os.path.join(folder, name)


def upward_imports(path: str):
    here = folder_of(module_name(path))
    for target in imported_modules(path):
        there = folder_of(target) if target.startswith("pdsketch_mech.") else None
        if there is None or there == here or there not in RANK:
            continue
        if RANK[there] >= RANK[here]:
            yield there


def test_every_folder_of_the_package_has_a_layer():
    folders = {name for name in os.listdir(PACKAGE)
               if os.path.isfile(os.path.join(PACKAGE, name, "__init__.py"))}
    assert folders == set(RANK)


@pytest.mark.parametrize("path", sorted(p for p in sources() if not is_entry_point(p)),
                         ids=lambda p: os.path.relpath(p, PACKAGE))
def test_a_module_imports_only_its_own_folder_and_the_layers_below(path):
    assert sorted(set(upward_imports(path))) == []


def test_entry_points_are_thin_and_import_only_commands_or_util():
    for path in sources():
        if not is_entry_point(path) or os.path.basename(path) == "__main__.py" and "bench" in path:
            continue
        with open(path, encoding="utf-8") as handle:
            assert len(handle.read().splitlines()) <= 30, path
        assert {folder_of(m) for m in imported_modules(path) if m.startswith("pdsketch_mech.")} <= {"commands", "util"}


def test_the_check_finds_an_upward_import(tmp_path, monkeypatch):
    """A world module importing the planner is caught (the test above cannot pass vacuously)."""
    world = tmp_path / "pdsketch_mech" / "world"
    world.mkdir(parents=True)
    bad = world / "bad.py"
    bad.write_text("from ..planner.bilevel import bilevel_plan\nfrom ..lang import nodes\n")
    monkeypatch.setattr(__import__(__name__), "ROOT", str(tmp_path))
    assert set(upward_imports(str(bad))) == {"planner"}
