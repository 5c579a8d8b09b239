"""`python -m pdsketch_mech.envs`: the entry point of `commands/envs.py`."""
import sys

from ..commands.common import run
from ..commands.envs import main

sys.exit(run(main))
