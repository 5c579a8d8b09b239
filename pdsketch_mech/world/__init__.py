"""The simulated world: PyBullet bodies, the Panda, collisions, motion, contacts, rendering.

Modules here `import pybullet as p` directly: the package's import hook
(`pdsketch_mech/quiet_pybullet.py`) keeps PyBullet's load-time banner off the output.
"""
