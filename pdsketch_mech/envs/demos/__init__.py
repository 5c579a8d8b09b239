"""Scripted demonstrations, one per task (the paper: "created by executing a manually written
script in one specific initial configuration").

A script reads the object poses from the world it is given (so perturbed instances work
too) and moves the robot with `motion.Driver` — planned free motions, straight moves,
pushes, the fingers — all simulated step by step. Scripts call neither the planner nor the
basis operators. `run.record_demo` runs one under a recorder and checks the goal from the
contact graph at the end.
"""
from .motion import DemoError, Driver
from .run import DEMOS, DemoResult, goal_holds, record_demo, run_demo

__all__ = ["DEMOS", "DemoError", "DemoResult", "Driver", "goal_holds", "record_demo", "run_demo"]
