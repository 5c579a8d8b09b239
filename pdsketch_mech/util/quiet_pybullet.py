"""Import PyBullet without its banner, wherever it is first imported from.

PyBullet's C extension prints a "pybullet build time: ..." line when first loaded; it would
break the one-line contract of the command-line tools. `install()` (run by the package's
`__init__`) adds an import hook that silences stdout and stderr at the file-descriptor
level while that one module loads, so every module can simply `import pybullet as p` —
and a process that never needs the simulator never loads it.
"""
from __future__ import annotations

import contextlib
import importlib.machinery
import os
import sys
from typing import Iterator

from . import process


@contextlib.contextmanager
def silenced() -> Iterator[None]:
    """Send whatever C code writes to fds 1 and 2 to /dev/null for the duration."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        # A Ctrl-C in here ends the process at once (process.py); its line must not go to /dev/null.
        with process.reporting_to(saved[1]):
            os.dup2(devnull, 1)
            os.dup2(devnull, 2)
            yield
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in saved + [devnull]:
            os.close(fd)


class _QuietLoader:
    """Wraps the extension's loader; its module init runs with output silenced."""

    def __init__(self, loader) -> None:
        self.loader = loader

    def create_module(self, spec):
        with silenced():
            return self.loader.create_module(spec)

    def exec_module(self, module) -> None:
        with silenced():
            self.loader.exec_module(module)


class _QuietFinder:
    """A meta-path finder for `pybullet` only; finds it as usual, then wraps its loader."""

    def find_spec(self, name: str, path=None, target=None):
        if name != "pybullet":
            return None
        spec = importlib.machinery.PathFinder.find_spec(name, path)
        if spec is not None and spec.loader is not None:
            spec.loader = _QuietLoader(spec.loader)
        return spec


def install() -> None:
    """Put the hook first on `sys.meta_path` (once)."""
    if not any(isinstance(finder, _QuietFinder) for finder in sys.meta_path):
        sys.meta_path.insert(0, _QuietFinder())
