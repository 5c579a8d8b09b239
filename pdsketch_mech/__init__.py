"""pdsketch_mech: task-and-motion planning with mechanisms (see README.md)."""
import _signal
import os as _os


def _interrupted(signum, frame) -> None:   # until early.install decides (early.py says why)
    _os.write(2, b"interrupted\n")
    _os._exit(130)


try:
    _previous_sigint = _signal.signal(_signal.SIGINT, _interrupted)
except ValueError:   # imported outside the main thread: signals cannot be set there
    _previous_sigint = None
from . import early as _early  # noqa: E402

_early.install(_previous_sigint)  # Ctrl-C while the modules below import exits 130 too
from . import process as _process  # noqa: E402
from .quiet_pybullet import install as _install_quiet_pybullet  # noqa: E402

if _process.is_command():  # `python -m pdsketch_mech.X`: Ctrl-C ends it at any moment (exit 130)
    _process.install_interrupt_handler()
    _process.limit_blas_threads()
_install_quiet_pybullet()  # PyBullet, when a module needs it, loads without its banner
