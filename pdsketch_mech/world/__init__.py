"""The simulated world: PyBullet bodies, the Panda, collisions, motion, contacts, rendering."""
import os
import sys


def _import_pybullet_quietly() -> None:
    """PyBullet's C extension prints a "build time" banner when first imported; it would
    break the one-line error contract of the command-line tools. Silence both stdout and
    stderr at the file-descriptor level for that one import (later imports are cached)."""
    if "pybullet" in sys.modules:
        return
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        import pybullet  # noqa: F401
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in saved + [devnull]:
            os.close(fd)


_import_pybullet_quietly()
