"""The Python API: load a domain with its mechanisms once, then plan, replay and check many
problems in one process (docs/api.md).

    from pdsketch_mech.api import Planner
    planner = Planner("basis", mechanisms="all")
    document = planner.plan("hook-use", timeout=60, seed=0)   # what `plan --json` writes
"""
from ..lang.errors import PddlError, PddlWarning
from .planner import PlanDocument, Planner

__all__ = ["Planner", "PlanDocument", "PddlError", "PddlWarning"]
