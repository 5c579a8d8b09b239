"""The simulated world: PyBullet bodies, the Panda, collisions, motion, contacts, rendering.

Modules here `import pybullet as p` directly: the package's import hook
(`pdsketch_mech/util/quiet_pybullet.py`, installed by the commands) keeps PyBullet's load-time banner off the output.
"""
