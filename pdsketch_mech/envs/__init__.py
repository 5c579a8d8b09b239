"""Task distributions (one per mechanism of the paper) that write ordinary problem files, and
the scripted demonstrations (`envs/demos/`). See `spec.py` for the declarations, `generate.py`
for the generator and `tasks.py` for the six tasks."""
from .generate import Instance, Placed, sample
from .spec import Align, Assets, Distractors, ObjectSpec, TaskSpec
from .tasks import TASKS, get_task

__all__ = ["Align", "Assets", "Distractors", "Instance", "ObjectSpec", "Placed", "TASKS", "TaskSpec", "get_task",
           "sample"]
