"""`python -m pdsketch_mech.plan`: the entry point of `commands/plan.py`."""
if __name__ == "__main__":
    from .commands.common import run_and_exit
    from .commands.plan import main
    run_and_exit(main)
