"""`python -m pdsketch_mech.envs`: the entry point of `commands/envs.py`."""
from ..commands.common import run_and_exit
from ..commands.envs import main

run_and_exit(main)
