"""pdsketch_mech: task-and-motion planning with mechanisms (see README.md)."""
from .quiet_pybullet import install as _install_quiet_pybullet

_install_quiet_pybullet()  # PyBullet, when a module needs it, loads without its banner
