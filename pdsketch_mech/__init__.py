"""pdsketch_mech: task-and-motion planning with mechanisms (see README.md and docs/).

Importing the package changes nothing in the importing process. Only a command's process
(`python -m pdsketch_mech.NAME`) gets the Ctrl-C handling and the quiet PyBullet import
hook of `util/`; they are installed here because this is the first code such a process runs.
"""
import _signal
import os as _os


def _interrupted(signum, frame) -> None:   # until early.install decides (util/early.py says why)
    _os.write(2, b"interrupted\n")
    _os._exit(130)


try:
    _previous_sigint = _signal.signal(_signal.SIGINT, _interrupted)
except ValueError:   # imported outside the main thread: signals cannot be set there
    _previous_sigint = None
from .util import early as _early  # noqa: E402

_early.install(_previous_sigint)  # a command: Ctrl-C while the modules below import exits 130; else as before
if _early.is_command():  # `python -m pdsketch_mech.X`: Ctrl-C ends it at any moment (exit 130)
    from .util import process as _process
    from .util.quiet_pybullet import install as _install_quiet_pybullet

    _process.install_interrupt_handler()
    _process.limit_blas_threads()
    _install_quiet_pybullet()  # PyBullet, when a module needs it, loads without its banner
