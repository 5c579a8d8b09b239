"""pdsketch_mech: task-and-motion planning with mechanisms (see README.md)."""
from . import early as _early

_early.install()  # first: Ctrl-C while the modules below import exits 130 too
from . import process as _process  # noqa: E402
from .quiet_pybullet import install as _install_quiet_pybullet  # noqa: E402

if _process.is_command():  # `python -m pdsketch_mech.X`: Ctrl-C ends it at any moment (exit 130)
    _process.install_interrupt_handler()
    _process.limit_blas_threads()
_install_quiet_pybullet()  # PyBullet, when a module needs it, loads without its banner
