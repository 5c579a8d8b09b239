"""pdsketch_mech: task-and-motion planning with mechanisms (see README.md)."""
from . import process as _process
from .quiet_pybullet import install as _install_quiet_pybullet

if _process.is_command():  # `python -m pdsketch_mech.X`: Ctrl-C ends it at any moment (exit 130)
    _process.install_interrupt_handler()
    _process.limit_blas_threads()
_install_quiet_pybullet()  # PyBullet, when a module needs it, loads without its banner
