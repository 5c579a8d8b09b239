"""`python -m pdsketch_mech.learn`: the entry point of `commands/learn.py`."""
if __name__ == "__main__":
    from .commands.common import run_and_exit
    from .commands.learn import main
    run_and_exit(main)
