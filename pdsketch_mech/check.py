"""`python -m pdsketch_mech.check`: the entry point of `commands/check.py`."""
if __name__ == "__main__":
    from .commands.check import main
    from .commands.common import run_and_exit
    run_and_exit(main)
